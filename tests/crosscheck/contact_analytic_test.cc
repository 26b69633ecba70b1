// Contact against answers known in closed form (../docs/environment.md lists
// them), each through the whole step: the scene, the environment model, the
// contact layer, the linearly-implicit step.
//   resting box: the normal forces carry m g, nothing moves;
//   box on a 20 deg slope, mu = 1 (inside the cone): it sticks, creep < 1 um/s over 10 s;
//   box on a 20 deg slope, mu = 0.2 (outside): it slides at g (sin - mu cos);
//   box launched at 1 m/s, mu = 0.5: decelerates at mu g and stops where the time-stepping's own
//     discrete solution says (and within h v0 / 2 of v0^2 / (2 mu g)); a diagonal launch alike, straight;
//   box spinning flat, sent off sliding and spinning, and pushed off-centre: turns as uniform pressure
//     under its face says (RK4 on 1,024 Coulomb points given the same push);
//   sphere and cylinder rolling down 15 deg: (5/7) g sin and (2/3) g sin, to 5.5e-4 at 1 ms;
//   ball dropped with restitution 0, 0.5, 1: rebound height ratio e^2 within 1 %;
//   ten stacked boxes, a staggered pyramid of ten boxes and 216 spheres in columns: still for 10 s; a
//     pile of three logs, whose contacts lean 30 degrees: it falls apart at mu = 0 and 0.2 and stands
//     still at 0.3 and 0.6 (statics: mu >= 2 - sqrt 3);
//   Go1 standing: the feet carry m g to 1e-6, no drift, no sinking; Talos standing on its soles;
//   the Panda's hand against a non-convex mesh channel: overlap within 1 mm;
//   a workcell (the PUMA's line past a table with boxes and a ball, a Go1 standing behind it):
//     the arm knocks the boxes over and the ball off the table, the ball rolls on along the floor
//     without slipping, the boxes rest on the table, the Go1 keeps standing, no overlap over 0.1 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

constexpr double g = 9.81;

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }

Scene shipped(const char* name) { return loadScene(test::sourceDir() + "/scenes/" + name); }

// A free body's world position and velocity (its frame origin) and angular velocity.
FreeBodyState body(const Simulation& sim, const std::string& name) {
  for (const ModelPart& part : sim.model().parts)
    if (part.name == name) return freeBodyState(part, sim.q(), sim.v());
  ADD_FAILURE() << "no body " << name;
  return {};
}

void run(Simulation& sim, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / sim.scene().dt));
  for (int k = 0; k < steps; ++k) ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
}

// The total contact force on the world (the ground and fixed obstacles), N.
Vector3 forceOnWorld(const Simulation& sim) {
  Vector3 f = Vector3::Zero();
  for (int k = 0; k < sim.contacts().n; ++k) {
    const Contact& c = sim.contacts()[k];
    if (c.body_b < 0) f += c.impulse;
    if (c.body_a < 0) f -= c.impulse;
  }
  return f / sim.scene().dt;
}

// The total contact force on a free body, N.
Vector3 contactForceOn(const Simulation& sim, const std::string& name) {
  int index = -1;
  for (const ModelPart& part : sim.model().parts)
    if (part.name == name) index = part.body_begin;
  Vector3 f = Vector3::Zero();
  for (int k = 0; k < sim.contacts().n; ++k) {
    const Contact& c = sim.contacts()[k];
    if (c.body_b == index) f += c.impulse;
    if (c.body_a == index) f -= c.impulse;
  }
  return f / sim.scene().dt;
}

TEST(ContactAnalytic, ARestingBoxIsCarriedAndStill) {
  Simulation sim(sceneText("ground: true\nbodies: [{name: box, shape: box, size: [0.3, 0.2, 0.1], mass: 2.5, xyz: [0.1, 0.2, 0.05]}]\n"));
  run(sim, 2.0);
  const FreeBodyState b = body(sim, "box");
  EXPECT_EQ(sim.contacts().n, 4) << "a flat contact: its four corners";
  // Still, the corners carry m g between them whatever they do (that follows from the next lines);
  // which share each carries does not: four corners are redundant, and the symmetric box's even split
  // is the answer that does not depend on the corners' order (measured 2e-6 from it).
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(std::abs(sim.contacts()[k].impulse.z()) / sim.scene().dt, 2.5 * g / 4.0, 1e-5 * 2.5 * g)
        << "corner " << k;
  EXPECT_LT(b.v.norm(), 1e-9);
  EXPECT_LT((b.p - Vector3(0.1, 0.2, 0.05)).norm(), 1e-9);
  EXPECT_LT(sim.contacts().maxPenetration(), 1e-6);
}

TEST(ContactAnalytic, ABoxInsideTheFrictionConeSticksOnASlope) {
  Simulation sim(shipped("box_slope.yaml"));
  run(sim, 0.5);
  const Vector3 start = body(sim, "box").p;
  run(sim, 10.0);
  const double creep = (body(sim, "box").p - start).norm() / 10.0;
  std::printf("box on 20 deg, mu 1: creep %.3e m/s over 10 s\n", creep);
  EXPECT_LT(creep, 1e-6) << "1 um/s";
  EXPECT_LT(sim.contacts().maxPenetration(), 1e-6);
}

TEST(ContactAnalytic, ABoxOutsideTheFrictionConeSlidesAtGSinMinusMuCos) {
  const double theta = 20.0 * M_PI / 180.0, mu = 0.2;
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml,
                "ground: {height: 0, rpy: [0, %.17g, 0], material: m}\nmaterials: {m: {friction: %g}}\n"
                "bodies: [{name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1, material: m, xyz: [%.17g, 0, %.17g], "
                "rpy: [0, %.17g, 0]}]\n",
                theta, mu, 0.1 * std::sin(theta), 0.1 * std::cos(theta), theta);
  Simulation sim(sceneText(yaml));
  run(sim, 0.1);
  const double v1 = body(sim, "box").v.norm();
  run(sim, 0.5);
  const double a = (body(sim, "box").v.norm() - v1) / 0.5;
  const double expected = g * (std::sin(theta) - mu * std::cos(theta));
  std::printf("box on 20 deg, mu 0.2: %.6f m/s^2 (analytic %.6f)\n", a, expected);
  EXPECT_NEAR(a, expected, 1e-9 * expected);
}

TEST(ContactAnalytic, ASlidingBoxStopsWhereCoulombSays) {
  Simulation sim(shipped("box_slide.yaml"));
  run(sim, 0.4);
  const FreeBodyState b = body(sim, "box");
  const double h = sim.scene().dt, v0 = 1.0, a = 0.5 * g;
  // The step's own solution: v_k = v0 - k a h while positive, x = h sum v_k (velocity, then position).
  double x = 0.0;
  for (int k = 1; v0 - k * a * h > 0.0; ++k) x += h * (v0 - k * a * h);
  const double analytic = v0 * v0 / (2.0 * a);
  std::printf("sliding box: stops at %.6f mm (discrete %.6f, analytic %.6f: %+.3f %%)\n", 1e3 * b.p.x(), 1e3 * x,
              1e3 * analytic, 100.0 * (b.p.x() - analytic) / analytic);
  EXPECT_NEAR(b.p.x(), x, 1e-9) << "Coulomb's deceleration exactly, every step";
  // (The discrete stop is within h v0 / 2 of the analytic one by arithmetic alone: no assertion.)
  EXPECT_LT(std::abs(b.p.y()), 1e-9) << "straight";
  EXPECT_LT(b.v.norm(), 1e-9) << "stopped, and stuck";
}

TEST(ContactAnalytic, ADiagonalSlideIsIsotropic) {
  Scene s = shipped("box_slide.yaml");
  s.bodies[0].velocity = Vector3(std::sqrt(0.5), std::sqrt(0.5), 0.0);
  Simulation diagonal(s), straight(shipped("box_slide.yaml"));
  run(diagonal, 0.4);
  run(straight, 0.4);
  const Vector3 d = body(diagonal, "box").p, x = body(straight, "box").p;
  EXPECT_NEAR(std::hypot(d.x(), d.y()), x.x(), 1e-9) << "the same distance whatever the direction";
  EXPECT_NEAR(d.x(), d.y(), 1e-9) << "along the launch";
}

double rollingAcceleration(const char* shape, double theta, double* omega_error) {
  const double r = 0.05;
  char yaml[1024];
  const Vector3 n(std::sin(theta), 0.0, std::cos(theta));  // the slope plane turned about y by theta: its normal
  const Vector3 at = r * n;
  const bool cylinder = std::string(shape) == "cylinder";
  // A cylinder lies across the slope, its axis along y.
  std::snprintf(yaml, sizeof yaml,
                "ground: {height: 0, rpy: [0, %.17g, 0]}\nbodies: [{name: b, shape: %s, radius: %g%s, mass: 1, "
                "xyz: [%.17g, 0, %.17g], rpy: [%s, %.17g, 0]}]\n",
                theta, shape, r, cylinder ? ", length: 0.2" : "", at.x(), at.z(), cylinder ? "1.5707963267948966" : "0",
                theta);
  Simulation sim(sceneText(yaml));
  run(sim, 1.0);
  const FreeBodyState b = body(sim, "b");
  const double v = b.v.norm(), w = b.w.norm();
  *omega_error = std::abs(w * r - v) / v;
  return v / 1.0;  // from rest: a = v / t
}

TEST(ContactAnalytic, ASphereAndACylinderRollDownASlope) {
  const double theta = 15.0 * M_PI / 180.0;
  double w_err = 0.0;
  const double sphere = rollingAcceleration("sphere", theta, &w_err);
  const double expected_sphere = 5.0 / 7.0 * g * std::sin(theta);
  std::printf("sphere rolling down 15 deg: %.8f m/s^2 (analytic %.8f), |w r - v| / v = %.1e\n", sphere, expected_sphere,
              w_err);
  EXPECT_NEAR(sphere, expected_sphere, 5.5e-4 * expected_sphere);
  EXPECT_LT(w_err, 5.5e-4) << "rolling without slip";
  const double cylinder = rollingAcceleration("cylinder", theta, &w_err);
  const double expected_cylinder = 2.0 / 3.0 * g * std::sin(theta);
  std::printf("cylinder rolling down 15 deg: %.8f m/s^2 (analytic %.8f), |w r - v| / v = %.1e\n", cylinder,
              expected_cylinder, w_err);
  EXPECT_NEAR(cylinder, expected_cylinder, 5.5e-4 * expected_cylinder);
  EXPECT_LT(w_err, 5.5e-4);
}

// Rolling resistance (material `rolling`, m): a torque of at most rolling x N opposes the rolling.
// A solid ball rolling on a flat floor then decelerates at a = 5 rolling g / (7 r) (its friction
// keeping it rolling), so from v0 it stops after v0^2 / 2a.
TEST(ContactAnalytic, ABallWithRollingResistanceStopsWhereTheAnalyticAnswerSays) {
  const double r = 0.05, v0 = 1.0;
  for (const double rolling : {0.002, 0.0005}) {
    char yaml[512];
    std::snprintf(yaml, sizeof yaml,
                  "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5, rolling: %.17g}}\n"
                  "bodies: [{name: ball, shape: sphere, radius: %g, mass: 1, xyz: [0, 0, %g], v: [%g, 0, 0], "
                  "w: [0, %.17g, 0], material: m}]\n",
                  rolling, r, r, v0, v0 / r);
    Simulation sim(sceneText(yaml));
    const double a = 5.0 * rolling * g / (7.0 * r), stop = v0 * v0 / (2.0 * a), when = v0 / a;
    double stopped_at = -1.0, moment = 0.0;
    const int steps = static_cast<int>(1.5 * when / sim.scene().dt);
    for (int k = 1; k <= steps; ++k) {
      ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
      if (k == steps / 4 && sim.contacts().n == 1) moment = sim.contacts()[0].moment.norm() / sim.scene().dt;
      if (stopped_at < 0.0 && body(sim, "ball").v.x() < 1e-9) stopped_at = k * sim.scene().dt;
    }
    const FreeBodyState b = body(sim, "ball");
    std::printf("ball rolling at %g m/s, rolling resistance %g m: stops at x %.5f m after %.4f s (analytic %.5f m, "
                "%.4f s), resisting moment %.6f N m (rolling m g %.6f)\n",
                v0, rolling, b.p.x(), stopped_at, stop, when, moment, rolling * g);
    EXPECT_NEAR(b.p.x(), stop, 0.01 * stop) << "the goal: within 1 %";
    EXPECT_NEAR(stopped_at, when, 0.01 * when);
    EXPECT_LT(b.v.norm() + b.w.norm() * r, 1e-9) << "then it stays: no creep";
    EXPECT_NEAR(moment, rolling * g, 1e-9) << "the moment at its limit while it rolls";
  }
}

// Torsional resistance (material `torsion`, m): a ball spinning on the spot about the vertical
// stops after I w0 / (torsion m g), I = 2/5 m r^2.
TEST(ContactAnalytic, ASpinningBallWithTorsionalResistanceStopsWhenTheAnalyticAnswerSays) {
  const double r = 0.05, w0 = 10.0, torsion = 0.001;
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5, torsion: %.17g}}\n"
                "bodies: [{name: ball, shape: sphere, radius: %g, mass: 1, xyz: [0, 0, %g], w: [0, 0, %g], "
                "material: m}]\n",
                torsion, r, r, w0);
  Simulation sim(sceneText(yaml));
  const double when = 0.4 * r * r * w0 / (torsion * g);
  double stopped_at = -1.0;
  for (int k = 1; k <= static_cast<int>(1.5 * when / sim.scene().dt); ++k) {
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    if (stopped_at < 0.0 && body(sim, "ball").w.z() < 1e-9) stopped_at = k * sim.scene().dt;
  }
  const FreeBodyState b = body(sim, "ball");
  std::printf("ball spinning at %g rad/s, torsion %g m: stops at %.4f s (analytic %.4f s), drifted %.1e m\n", w0,
              torsion, stopped_at, when, b.p.head<2>().norm());
  EXPECT_NEAR(stopped_at, when, 0.01 * when);
  EXPECT_LT(b.w.norm(), 1e-9);
  EXPECT_LT(b.p.head<2>().norm(), 1e-9) << "spinning on the spot";
}

// A ball on a slope with rolling resistance holds while m g sin(theta) r <= rolling m g cos(theta),
// tan(theta) <= rolling / r (here 0.04: 2.29 deg), without creeping; past it, it rolls.
TEST(ContactAnalytic, ABallWithRollingResistanceHoldsOnAGentleSlopeOnly) {
  const double r = 0.05, rolling = 0.002;
  for (const double degrees : {2.0, 2.5}) {
    const double theta = degrees * M_PI / 180.0;
    const Vector3 at = r * Vector3(std::sin(theta), 0.0, std::cos(theta));
    char yaml[512];
    std::snprintf(yaml, sizeof yaml,
                  "ground: {height: 0, rpy: [0, %.17g, 0], material: m}\nmaterials: {m: {friction: 0.5, rolling: %g}}\n"
                  "bodies: [{name: ball, shape: sphere, radius: %g, mass: 1, xyz: [%.17g, 0, %.17g], material: m}]\n",
                  theta, rolling, r, at.x(), at.z());
    Simulation sim(sceneText(yaml));
    run(sim, 2.0);
    const FreeBodyState b = body(sim, "ball");
    std::printf("ball on %.1f deg with rolling resistance %g m (holds below %.2f deg): speed %.3e m/s after 2 s\n",
                degrees, rolling, std::atan(rolling / r) * 180.0 / M_PI, b.v.norm());
    if (std::tan(theta) < rolling / r) EXPECT_LT(b.v.norm(), 1e-12) << degrees << " deg: it holds, no creep";
    else EXPECT_GT(b.v.norm(), 0.05) << degrees << " deg: it rolls";
  }
}

TEST(ContactAnalytic, ADroppedBallReboundsToEToTheSquare) {
  for (const double e : {0.0, 0.5, 1.0}) {
    char yaml[512];
    std::snprintf(yaml, sizeof yaml,
                  "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5, restitution: %g}}\n"
                  "bodies: [{name: ball, shape: sphere, radius: 0.05, mass: 0.2, xyz: [0, 0, 1.05], material: m}]\n",
                  e);
    Simulation sim(sceneText(yaml));
    double lowest = 1e9, apex = 0.0;
    bool bounced = false;
    for (int k = 0; k < 2500; ++k) {
      ASSERT_TRUE(sim.step(nullptr));
      const FreeBodyState b = body(sim, "ball");
      const double height = b.p.z() - 0.05;
      if (!bounced && b.v.z() > 0.0) bounced = true;
      if (!bounced) lowest = std::min(lowest, height);
      if (bounced) apex = std::max(apex, height);
      if (bounced && b.v.z() < 0.0 && apex > 0.0) break;
    }
    std::printf("ball dropped from 1 m, e = %.1f: rebounds to %.5f m (e^2 = %.2f)\n", e, apex, e * e);
    if (e == 0.0) {
      EXPECT_LT(apex, 1e-6) << "no bounce";
    } else {
      EXPECT_NEAR(apex, e * e, 0.01 * e * e);
    }
    EXPECT_GT(lowest, -1e-4) << "the ball never sinks in";
  }
}

// The mean distance from the centre of an a x b rectangle over its area, by a fine midpoint rule.
double meanRadius(double a, double b) {
  const int n = 2000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) sum += std::hypot(a * ((i + 0.5) / n - 0.5), b * ((j + 0.5) / n - 0.5));
  return sum / (static_cast<double>(n) * n);
}

// How long the body takes to stop spinning about z (|w| below 1e-9), s.
double spinDown(Simulation& sim, const char* name) {
  for (int k = 1; k <= 20000; ++k) {
    EXPECT_TRUE(sim.step(nullptr));
    if (body(sim, name).w.norm() < 1e-9) return k * sim.scene().dt;
  }
  return INFINITY;
}

TEST(ContactAnalytic, ABoxSpinningFlatStopsWhenUniformPressureSays) {
  // Coulomb friction under uniform pressure over the face: a torque mu m g r, r the face's mean
  // distance from its centre, so w falls at mu m g r / I_z and stops at w0 I_z / (mu m g r).
  const double a = 0.3, b = 0.2, m = 2.0, mu = 0.5, w0 = 5.0;
  Simulation sim(sceneText(
      "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5}}\n"
      "bodies: [{name: box, shape: box, size: [0.3, 0.2, 0.1], mass: 2, xyz: [0, 0, 0.05], w: [0, 0, 5], material: m}]\n"));
  const double Iz = m * (a * a + b * b) / 12.0, r = meanRadius(a, b);
  const double expected = w0 * Iz / (mu * m * g * r);
  const double stop = spinDown(sim, "box");
  std::printf("box spinning flat: stops at %.4f s (uniform pressure: %.4f s, r = %.5f m; at the corners' %.5f m "
              "it would stop at %.4f s)\n",
              stop, expected, r, 0.5 * std::hypot(a, b), w0 * Iz / (mu * m * g * 0.5 * std::hypot(a, b)));
  EXPECT_NEAR(stop, expected, 0.02 * expected);
  EXPECT_LT(body(sim, "box").p.head<2>().norm(), 1e-9) << "a pure spin: its centre stays";
}

TEST(ContactAnalytic, ALogSpinningOnItsSideStopsWhenUniformLineLoadSays) {
  // A cylinder lying down touches along a line of its length L: uniform load along it gives a torque
  // mu m g L / 4 about the vertical.
  const double r = 0.05, L = 0.4, m = 1.0, mu = 0.5, w0 = 4.0;
  Simulation sim(sceneText(
      "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5}}\n"
      "bodies: [{name: log, shape: cylinder, radius: 0.05, length: 0.4, mass: 1, xyz: [0, 0, 0.05], "
      "rpy: [1.5707963267948966, 0, 0], w: [0, 0, 4], material: m}]\n"));
  const double I = m * (3 * r * r + L * L) / 12.0;  // about a diameter through its centre
  const double expected = w0 * I / (mu * m * g * L / 4.0);
  const double stop = spinDown(sim, "log");
  std::printf("log spinning on its side: stops at %.4f s (uniform line load: %.4f s)\n", stop, expected);
  EXPECT_NEAR(stop, expected, 0.02 * expected);
}

// A force applied to the plate: (fx, fy), world, N a kg, through each dt from t = 0, at the plate's
// point (rx, ry) (its own frame, at the floor).
struct PlateForce {
  std::vector<double> fx, fy;
  double rx = 0.0, ry = 0.0, dt = 1e-3;
};

// A square plate of side 2a on K x K equally loaded Coulomb points (its cells' centres), sent off at
// v0 along x spinning at w0 (and pushed, if push is given), integrated by RK4 (a 0.1 ms step) until it
// all but stops: its turn, rad, and the distance its centre went, m (and its turn when the push
// ended). K = 32 is uniform pressure to 0.03 % (the points' mean radius against the face's); K = 4,
// the grid of point contacts. Independent of the contact solve.
struct PlateRun {
  double turn = 0.0, travel = 0.0, turn_pushed = 0.0;
};
PlateRun gridSlide(int K, double a, double mu, double v0, double w0, const PlateForce* push = nullptr) {
  const int n = K * K;
  std::vector<double> px(static_cast<size_t>(n)), py(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    px[static_cast<size_t>(i)] = a * (2.0 * (i % K + 0.5) / K - 1.0);
    py[static_cast<size_t>(i)] = a * (2.0 * (i / K + 0.5) / K - 1.0);
  }
  const double Iz = (2 * a) * (2 * a) / 6.0;  // per unit mass
  // The state (x, y, vx, vy, theta, w); the points turned with theta.
  size_t interval = 0;  // the push's, for the RK4 step being taken (its stages stay inside it)
  auto rate = [&](const double* s, double* d) {
    double fx = 0.0, fy = 0.0, tz = 0.0;
    const double c = std::cos(s[4]), sn = std::sin(s[4]);
    if (push && interval < push->fx.size()) {
      const double pushx = push->fx[interval], pushy = push->fy[interval];
      const double rx = c * push->rx - sn * push->ry, ry = sn * push->rx + c * push->ry;
      fx += pushx, fy += pushy, tz += rx * pushy - ry * pushx;
    }
    for (int i = 0; i < n; ++i) {
      const double rx = c * px[static_cast<size_t>(i)] - sn * py[static_cast<size_t>(i)];
      const double ry = sn * px[static_cast<size_t>(i)] + c * py[static_cast<size_t>(i)];
      const double ux = s[2] - s[5] * ry, uy = s[3] + s[5] * rx, len = std::hypot(ux, uy);
      if (!(len > 1e-15)) continue;
      fx -= mu * g / n * ux / len;
      fy -= mu * g / n * uy / len;
      tz -= mu * g / n * (rx * uy - ry * ux) / len;
    }
    d[0] = s[2], d[1] = s[3], d[2] = fx, d[3] = fy, d[4] = s[5], d[5] = tz / Iz;
  };
  double s[6] = {0, 0, v0, 0, 0, w0};
  const double h = 1e-4;
  // Until it all but stops: Coulomb's jump makes the last millimetres per second chatter at the
  // step's mu g h, and what it turns from 1e-3 m/s on is below 1e-5 rad.
  const int pushed = push ? static_cast<int>(std::lround(push->fx.size() * push->dt / h)) : 0;
  PlateRun out;
  for (int k = 0; k < 100000 && (k < pushed || std::hypot(s[2], s[3]) + a * std::abs(s[5]) > 1e-3); ++k) {
    if (push) interval = static_cast<size_t>((k + 0.5) * h / push->dt);
    double k1[6], k2[6], k3[6], k4[6], t[6];
    rate(s, k1);
    for (int i = 0; i < 6; ++i) t[i] = s[i] + 0.5 * h * k1[i];
    rate(t, k2);
    for (int i = 0; i < 6; ++i) t[i] = s[i] + 0.5 * h * k2[i];
    rate(t, k3);
    for (int i = 0; i < 6; ++i) t[i] = s[i] + h * k3[i];
    rate(t, k4);
    for (int i = 0; i < 6; ++i) s[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    if (k + 1 == pushed) out.turn_pushed = s[4];
  }
  out.turn = s[4];
  out.travel = std::hypot(s[0], s[1]);
  return out;
}

TEST(ContactAnalytic, ABoxSentOffSlidingAndSpinningTurnsAsUniformPressureSays) {
  // Sliding and spinning at once, where Howe and Cutkosky's ellipsoid turned 18 % short: the patch's
  // sampled limit surface against uniform pressure over the face. The surface itself (16 samples,
  // smoothed, scaled to the face's mean radius) turns within 0.8 % of uniform pressure here (the same
  // integrator on it); a 4 x 4 grid of point contacts is 2.4-3.1 % from it (printed, not asserted).
  const double a = 0.1, mu = 0.5;
  for (const double w0 : {5.0, 20.0, -10.0}) {
    char yaml[512];
    std::snprintf(yaml, sizeof yaml,
                  "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5}}\n"
                  "bodies: [{name: box, shape: box, size: [0.2, 0.2, 0.1], mass: 1, xyz: [0, 0, 0.05], v: [1, 0, 0], "
                  "w: [0, 0, %g], material: m}]\n",
                  w0);
    Simulation sim(sceneText(yaml));
    double turn = 0.0;
    int k = 0;
    for (; k < 5000; ++k) {
      ASSERT_TRUE(sim.step(nullptr));
      const FreeBodyState b = body(sim, "box");
      turn += b.w.z() * sim.scene().dt;
      if (b.v.norm() + a * b.w.norm() < 1e-9) break;
    }
    const double travel = body(sim, "box").p.head<2>().norm();
    const PlateRun uniform = gridSlide(32, a, mu, 1.0, w0), grid = gridSlide(4, a, mu, 1.0, w0);
    const double uniform_turn = uniform.turn, uniform_travel = uniform.travel;
    const double grid_turn = grid.turn, grid_travel = grid.travel;
    std::printf("box sent off at 1 m/s spinning at %g rad/s: turns %.4f rad, goes %.4f m, stops at %.3f s; uniform "
                "pressure: %.4f rad (%+.2f %%), %.4f m (%+.2f %%); a 4 x 4 grid of points: %.4f rad (%+.2f %%), "
                "%.4f m (%+.2f %%)\n",
                w0, turn, travel, k * sim.scene().dt, uniform_turn, 100 * (turn / uniform_turn - 1), uniform_travel,
                100 * (travel / uniform_travel - 1), grid_turn, 100 * (turn / grid_turn - 1), grid_travel,
                100 * (travel / grid_travel - 1));
    EXPECT_NEAR(turn, uniform_turn, 0.01 * std::abs(uniform_turn)) << w0;
    EXPECT_NEAR(travel, uniform_travel, 0.01 * uniform_travel) << w0;
    EXPECT_LT(k, 5000) << "it stops";
  }
}

TEST(ContactAnalytic, ABoxPushedOffCentreYawsAsUniformPressureSays) {
  // The same box pushed along x for 0.3 s at a point of its back face's bottom edge, off its centre
  // line, by the pull's spring held ahead of the point (so the push is level, and the references can
  // be planar), then let go: it yaws while pushed and turns on as it slides to a stop. The references
  // take the force each step applied (reported exact: applied_force_test) at the same point of the
  // plate. Uniform pressure is asserted, and so is every K x K grid of point contacts from K = 8 on,
  // within 2 %. The 4 x 4 grid is printed, not asserted: it is itself 2.5, 2.8 and 6.3 % from
  // uniform pressure's turn here (its points' mean radius is 2.1 % short), and the grids converge
  // on uniform pressure as K grows (asserted: each finer grid nearer it).
  const double a = 0.1, mu = 0.5;
  struct Push {
    double stretch, offset;  // the spring's, m (800 N/m: 10, 6.4, 8 N against friction's 4.9), the point's, m
  };
  for (const Push c : {Push{0.0125, 0.05}, Push{0.008, 0.09}, Push{0.01, -0.02}}) {
    Simulation sim(sceneText(
        "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5}}\n"
        "bodies: [{name: box, shape: box, size: [0.2, 0.2, 0.1], mass: 1, xyz: [0, 0, 0.05], material: m}]\n"
        "interaction:\n  pull: {k: 800, b: 20, max_force: 100, max_stretch: 0.5}\n"));
    const double dt = sim.scene().dt;
    const Vector3 grabbed(-a, c.offset, -0.05);
    InteractionInput in;
    in.mode = InteractionMode::Pull;
    in.client = 1;
    in.attach_frame = static_cast<int>(sim.model().frames.size()) - 1;
    in.attach_point = grabbed;
    PlateForce push;
    push.rx = grabbed.x(), push.ry = grabbed.y(), push.dt = dt;
    const int pushed = static_cast<int>(std::lround(0.3 / dt));
    double turn = 0.0, turn_pushed = 0.0, largest = 0.0;
    int k = 0;
    for (; k < 5000; ++k) {
      const FreeBodyState b = body(sim, "box");
      if (k < pushed) {
        in.tip_position = b.p + b.R * grabbed + Vector3(c.stretch, 0.0, 0.0);
        in.tip_velocity = b.v + b.w.cross(b.R * grabbed);
        in.seq = k + 1;
        ASSERT_TRUE(sim.step(&in)) << sim.divergenceReport();
        const Vector3 f = sim.outcome().force_on_robot;
        push.fx.push_back(f.x()), push.fy.push_back(f.y());
        largest = std::max(largest, std::abs(f.z()));
      } else {
        ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
      }
      const FreeBodyState after = body(sim, "box");
      turn += after.w.z() * dt;
      if (k + 1 == pushed) turn_pushed = turn;
      if (k >= pushed && after.v.norm() + a * after.w.norm() < 1e-9) break;
    }
    const double travel = body(sim, "box").p.head<2>().norm();
    const PlateRun uniform = gridSlide(32, a, mu, 0.0, 0.0, &push), grid = gridSlide(4, a, mu, 0.0, 0.0, &push);
    std::printf("box pushed %.1f cm off-centre (vertical force at most %.2g N): turns %.4f rad while pushed and %.4f "
                "in all, goes %.4f m, stops at %.3f s; uniform pressure: %.4f (%+.2f %%) and %.4f rad (%+.2f %%), %.4f "
                "m (%+.2f %%); a 4 x 4 grid of points: %.4f (%+.2f %%) and %.4f rad (%+.2f %%), %.4f m (%+.2f %%)\n",
                100 * c.offset, largest, turn_pushed, turn, travel, (k + 1) * dt, uniform.turn_pushed,
                100 * (turn_pushed / uniform.turn_pushed - 1), uniform.turn, 100 * (turn / uniform.turn - 1),
                uniform.travel, 100 * (travel / uniform.travel - 1), grid.turn_pushed,
                100 * (turn_pushed / grid.turn_pushed - 1), grid.turn, 100 * (turn / grid.turn - 1), grid.travel,
                100 * (travel / grid.travel - 1));
    // The grid refined: what a 4 x 4 grid of point contacts predicts, with its discretisation's error
    // taken out step by step.
    double nearer = std::abs(grid.turn - uniform.turn);
    for (const int K : {8, 16}) {
      const PlateRun finer = gridSlide(K, a, mu, 0.0, 0.0, &push);
      std::printf("  a %d x %d grid: %.4f (%+.2f %%) and %.4f rad (%+.2f %%), %.4f m (%+.2f %%)\n", K, K,
                  finer.turn_pushed, 100 * (turn_pushed / finer.turn_pushed - 1), finer.turn,
                  100 * (turn / finer.turn - 1), finer.travel, 100 * (travel / finer.travel - 1));
      EXPECT_NEAR(turn_pushed, finer.turn_pushed, 0.02 * std::abs(finer.turn_pushed)) << c.offset << ", K " << K;
      EXPECT_NEAR(turn, finer.turn, 0.02 * std::abs(finer.turn)) << c.offset << ", K " << K;
      EXPECT_LT(std::abs(finer.turn - uniform.turn), nearer) << c.offset << ", K " << K << ": the grids converge";
      nearer = std::abs(finer.turn - uniform.turn);
    }
    EXPECT_LT(k, 5000) << c.offset << ": it stops";
    EXPECT_LT(largest, 1e-6) << c.offset << ": the push is level (the references are planar)";
    EXPECT_GT(std::abs(turn), 0.1) << c.offset << ": the push turns it";
    EXPECT_NEAR(turn_pushed, uniform.turn_pushed, 0.01 * std::abs(uniform.turn_pushed)) << c.offset;
    EXPECT_NEAR(turn, uniform.turn, 0.01 * std::abs(uniform.turn)) << c.offset;
    // Its path: 0.98 % long at 9 cm (0.88 % at a 0.5 ms step: the surface's own approximation, 16
    // smoothed samples, not the step's).
    EXPECT_NEAR(travel, uniform.travel, 0.015 * uniform.travel) << c.offset;
  }
}

// Still: every free body's speed below 1e-6 m/s, overlap within 0.1 mm, for 10 s.
// \return the exact (active-set) solve's rounds per step, over the 10 s.
double expectStill(const char* name) {
  Simulation sim(shipped(name));
  double speed = 0.0, overlap = 0.0;
  long rounds = 0;
  for (int k = 0; k < 10000; ++k) {
    EXPECT_TRUE(sim.step(nullptr));
    rounds += sim.contactStats().polish_rounds;
    for (const ModelPart& part : sim.model().parts)
      if (part.free_body) speed = std::max(speed, body(sim, part.name).v.norm());
    overlap = std::max(overlap, sim.contacts().maxPenetration());
  }
  std::printf("%s over 10 s: largest speed %.2e m/s, largest overlap %.2e m, %ld unconverged solves, "
              "%.3f exact-solve rounds a step, %ld islands by conjugate gradients (%ld iterations)\n",
              name, speed, overlap, static_cast<long>(sim.contactStats().unconverged), rounds / 1e4,
              static_cast<long>(sim.contactStats().large_solves), static_cast<long>(sim.contactStats().large_iterations));
  EXPECT_LT(speed, 1e-6) << name;
  EXPECT_LE(overlap, 1e-4) << name;
  EXPECT_EQ(sim.contactStats().unconverged, 0) << name;
  return rounds / 1e4;
}

TEST(ContactAnalytic, TenStackedBoxesStandStill) { expectStill("box_tower.yaml"); }

TEST(ContactAnalytic, ThePileOf216SpheresStandsStill) { expectStill("sphere_pile.yaml"); }

// 216 balls in columns, each touching its neighbours on every side: one island of 576 pairs, 1,728
// unknowns, past the dense exact solve's 192. Its sweeps stopped short in the first steps (426 were
// needed), the lattice moved 3e-9 m and from 1.3 s on came apart (986 unconverged solves in 3 s).
// Its system now goes to conjugate gradients.
TEST(ContactAnalytic, ALatticeOfBallsTouchingOnEverySideStandsStill) {
  expectStill("ball_lattice.yaml");
  Simulation sim(shipped("ball_lattice.yaml"));
  run(sim, 0.01);
  EXPECT_GE(sim.contactStats().large_solves, 1) << "the island is solved whole";
}

TEST(ContactAnalytic, AStaggeredPyramidOfBoxesStandsStill) {
  const double rounds = expectStill("box_pyramid.yaml");
  // Its sweeps leave 8 to 17 of its 100 corners pressing where the exact answer lifts them; releasing
  // them one a round took 2.3 rounds (factorisations) a step, each about 50 us.
  EXPECT_LT(rounds, 1.0) << "the lifted corners are released together";
}

// The log pile (log_pile.yaml) at friction mu for 3 s: how far the top log came down, m.
double logPileSag(double mu) {
  Scene s = shipped("log_pile.yaml");
  for (auto& [name, m] : s.materials) m.friction = mu;
  Simulation sim(s);
  const double top = body(sim, "top").p.z();
  run(sim, 3.0);
  return top - body(sim, "top").p.z();
}

TEST(ContactAnalytic, ALogPileStandsOnlyWithTheFrictionStaticsNeeds) {
  // Statics: mu >= 2 - sqrt(3) = 0.268 (the contacts lean 30 degrees). Either side of it, and far off.
  const double at_0 = logPileSag(0.0), at_02 = logPileSag(0.2), at_03 = logPileSag(0.3), at_06 = logPileSag(0.6);
  std::printf("log pile, the top log's fall in 3 s: mu 0: %.4f m, 0.2: %.4f m, 0.3: %.2e m, 0.6: %.2e m "
              "(threshold 2 - sqrt 3 = %.4f)\n",
              at_0, at_02, at_03, at_06, 2.0 - std::sqrt(3.0));
  EXPECT_GT(at_0, 0.03) << "without friction the pile falls apart";
  EXPECT_GT(at_02, 0.03) << "below the threshold it falls apart";
  EXPECT_LT(at_03, 1e-9) << "above it, it stands, stuck: no creep";
  EXPECT_LT(at_06, 1e-9);
}

TEST(ContactAnalytic, APegPressedBetweenTwoWallsComesToRestCentred) {
  // A box peg 0.4 mm wider than the slot it is dropped into, so each wall overlaps it by 0.2 mm: no
  // motion closes both overlaps. Slot between two fixed blocks (two shapes of the world), and inside a
  // U channel that is itself a free body on the ground (two free bodies: one pair, two facings). The
  // position correction once tried to close both: it stopped at its sweep limit on every step (the
  // blocks) and pushed the peg 0.42 mm into one block, 1.1 mm deep (3 s). Rigid bodies cannot say how
  // hard the fit squeezes; the peg must come to rest on the floor, centred, every correction converged.
  struct Case {
    const char* name;
    const char* yaml;
    double rest;  // the peg's centre height on its floor
  };
  const Case cases[] = {
      {"between two blocks",
       "  - {name: left, shape: box, size: [0.1, 0.2, 0.2], xyz: [-0.1, 0, 0.1], solid: true, material: m}\n"
       "  - {name: right, shape: box, size: [0.1, 0.2, 0.2], xyz: [0.1, 0, 0.1], solid: true, material: m}\n"
       "bodies:\n",
       0.03},
      {"in a free U channel",
       "  []\n"
       "bodies:\n"
       "  - {name: u, shape: mesh, file: ../models/meshes/u_channel.obj, density: 500, xyz: [0, 0, 0.1], material: m}\n",
       0.08}};
  for (const Case& c : cases) {
    Simulation sim(sceneText(std::string("materials: {m: {friction: 0.5}}\nground: {height: 0, material: m}\nobstacles:\n") +
                             c.yaml +
                             "  - {name: peg, shape: box, size: [0.1004, 0.06, 0.06], mass: 0.5, xyz: [0, 0, 0.15], "
                             "material: m}\n"));
    run(sim, 3.0);
    const FreeBodyState peg = body(sim, "peg");
    const ContactSolveStats& st = sim.contactStats();
    std::printf("peg pressed %s: at x %.1e, z %+.2e m from its floor, %.1e m/s, %lld of %lld corrections and "
                "%lld solves unconverged\n",
                c.name, peg.p.x(), peg.p.z() - c.rest, peg.v.norm(), static_cast<long long>(st.position_unconverged),
                static_cast<long long>(st.solves), static_cast<long long>(st.unconverged));
    EXPECT_NEAR(peg.p.x(), 0.0, 1e-5) << c.name << ": centred";
    EXPECT_NEAR(peg.p.z(), c.rest, 1e-4) << c.name << ": on its floor";
    EXPECT_LT(peg.v.norm() + peg.w.norm(), 1e-3) << c.name << ": at rest";
    EXPECT_EQ(st.position_unconverged, 0) << c.name;
  }
}

TEST(ContactAnalytic, Go1StandsOnItsFeet) {
  Simulation sim(shipped("go1_stand.yaml"));
  run(sim, 5.0);  // settles onto its PD's sag
  const Vector3 base = sim.q().head<3>();
  double sink = 0.0;
  for (int k = 0; k < 10000; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    sink = std::max(sink, sim.contacts().maxPenetration());
  }
  const double drift = (sim.q().head<3>() - base).norm(), weight = sim.model().totalMass() * g;
  const double carried = -forceOnWorld(sim).z();
  std::printf("Go1: %d feet carry %.9f N (m g %.9f N), base drift %.2e m over 10 s, deepest foot %.2e m\n",
              sim.contacts().n, carried, weight, drift, sink);
  EXPECT_EQ(sim.contacts().n, 4);
  EXPECT_NEAR(carried, weight, 1e-6 * weight);
  EXPECT_LT(drift, 1e-4);
  EXPECT_LE(sink, 1e-4);
}

TEST(ContactAnalytic, TalosStandsOnItsSoles) {
  if (!std::ifstream(test::sourceDir() + "/third_party/example-robot-data/robots/talos_data/robots/talos_full_v2.urdf"))
    GTEST_SKIP() << "example-robot-data not fetched";
  Simulation sim(shipped("talos_stand.yaml"));
  run(sim, 3.0);
  const Vector3 base = sim.q().head<3>();
  run(sim, 2.0);
  const double drift = (sim.q().head<3>() - base).norm(), weight = sim.model().totalMass() * g;
  std::printf("Talos: %d sole points carry %.6f N (m g %.6f N), base drift %.2e m over 2 s\n", sim.contacts().n,
              -forceOnWorld(sim).z(), weight, drift);
  EXPECT_EQ(sim.contacts().n, 8) << "each sole's four corners";
  EXPECT_NEAR(-forceOnWorld(sim).z(), weight, 1e-6 * weight);
  EXPECT_LT(drift, 1e-4);
}

TEST(ContactAnalytic, APandaLinkAgainstANonConvexMeshStaysOutOfIt) {
  if (!std::ifstream(test::sourceDir() + "/third_party/example-robot-data/robots/panda_description/urdf/panda.urdf"))
    GTEST_SKIP() << "example-robot-data not fetched";
  Simulation sim(shipped("panda_channel.yaml"));
  double overlap = 0.0;
  int touching = 0;
  for (int k = 0; k < 4000; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    overlap = std::max(overlap, sim.contacts().maxPenetration());
    touching += sim.contacts().n > 0;
  }
  std::printf("Panda against the U channel: in contact %d of 4000 steps, deepest overlap %.2e m\n", touching, overlap);
  EXPECT_GT(touching, 1000) << "the hand is held by the channel";
  EXPECT_LE(overlap, 1e-3);
}

TEST(ContactAnalytic, AWorkcellOfTwoRobotsAndFreeBodiesBehaves) {
  if (!std::ifstream(test::sourceDir() + "/third_party/example-robot-data/robots/go1_description/urdf/go1.urdf"))
    GTEST_SKIP() << "example-robot-data not fetched";
  Simulation sim(shipped("workcell.yaml"));
  const double floor = -0.4, table_top = 0.12, half = 0.04;  // workcell.yaml: the ground, the table, the boxes
  int go1_z = -1;
  for (const ModelPart& part : sim.model().parts)
    if (part.name == "go1") go1_z = part.q_begin + 2;
  ASSERT_GE(go1_z, 0);
  double overlap = 0.0, trunk_at_4 = 0.0;
  Vector3 last_v[2];
  for (int k = 1; k <= 8000; ++k) {
    if (k == 8000) last_v[0] = body(sim, "box_a").v, last_v[1] = body(sim, "box_b").v;
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    overlap = std::max(overlap, sim.contacts().maxPenetration());
    if (k == 4000) trunk_at_4 = sim.q()[go1_z];
  }
  const FreeBodyState ball = body(sim, "ball"), a = body(sim, "box_a"), b = body(sim, "box_b");
  // How far a box turned from its initial upright pose (rad).
  auto turned = [](const FreeBodyState& s) { return Eigen::AngleAxisd(s.R).angle(); };
  std::printf("workcell after 8 s: ball at z %.6f m, boxes at %.6f and %.6f m turned %.2f and %.2f rad, Go1 trunk "
              "moved %.2e m in the last 4 s, deepest overlap %.2e m\n",
              ball.p.z(), a.p.z(), b.p.z(), turned(a), turned(b), std::abs(sim.q()[go1_z] - trunk_at_4), overlap);
  EXPECT_NEAR(ball.p.z(), floor + half, 1e-4) << "the ball was knocked off the table onto the floor";
  EXPECT_NEAR(a.p.z(), table_top + half, 1e-4) << "box_a lies on the table";
  // box_b is knocked over the table's far end (y 0.5): where it ends is chaotic (pinned between the
  // forearm and that edge with EPA's normals; on the floor with the two boxes' separating axes), but
  // never inside the table: above its top, or its centre beyond the table's footprint (x 0.3 .. 0.6,
  // y -0.5 .. 0.5) by more than its half width.
  const bool above = b.p.z() > table_top + half - 1e-4,
             beyond = std::abs(b.p.x() - 0.45) > 0.15 + half - 1e-4 || std::abs(b.p.y()) > 0.5 + half - 1e-4;
  EXPECT_TRUE(above || beyond) << "box_b is not pushed into the table: at " << b.p.transpose();
  if (!above) {
    EXPECT_NEAR(b.p.z(), floor + half, 1e-4) << "off the table, box_b lies on the floor";
  }
  EXPECT_GT(std::max(turned(a), turned(b)), 0.8) << "the arm knocked a box over";
  for (const FreeBodyState& s : {a, b}) EXPECT_LT(s.v.norm() + s.w.norm() * half, 1e-3) << "the boxes rest";
  // Each box's contacts carry its weight and what it still gains in momentum, whatever they are (a
  // box pinched between the forearm and the table's edge can still be settling, at a few um/s, as
  // the arm's joints give under it): m dv = (F_contact - m g) h over the last step.
  for (int k = 0; k < 2; ++k) {
    const char* name = k == 0 ? "box_a" : "box_b";
    const Vector3 gained = 0.3 * (body(sim, name).v - last_v[k]) / sim.scene().dt;
    std::printf("%s: %.2e m/s, contact force %.9f N against weight and momentum's change %.9f N\n", name,
                body(sim, name).v.norm(), contactForceOn(sim, name).norm(), (gained + Vector3(0, 0, 0.3 * g)).norm());
    EXPECT_LT((contactForceOn(sim, name) - gained - Vector3(0, 0, 0.3 * g)).norm(), 1e-6 * 0.3 * g) << name;
  }
  // Nothing resists rolling here, so the ball rolls on along the floor: without slipping.
  const Vector3 slip = ball.v + ball.w.cross(Vector3(0, 0, -half));
  std::printf("the ball rolls at %.3f m/s, its contact point slips at %.2e m/s\n", ball.v.norm(), slip.norm());
  EXPECT_LT(slip.norm(), 1e-6);
  EXPECT_GT(sim.q()[go1_z] - floor, 0.2) << "the Go1 stands";
  EXPECT_LT(std::abs(sim.q()[go1_z] - trunk_at_4), 1e-4);
  EXPECT_LE(overlap, 1e-4);
}

// A slipping friction that the active-set solve fixes runs against its slip. That solve keeps the
// direction the sweeps guessed (up to 90 degrees off the reverse of the slip its answer gives) and
// turns it by Newton's method wherever the turned answer meets every condition. Over the arm's
// shoving of puma_table and the workcell, 8 s each.
TEST(ContactAnalytic, ASlippingFrictionRunsAgainstItsSlip) {
  for (const char* name : {"puma_table.yaml", "workcell.yaml"}) {
    Simulation sim(shipped(name));
    double worst = 0.0;  // rad, over the solves whose every slip was turned
    for (int k = 0; k < 8000; ++k) {
      const int64_t unturned = sim.contactStats().slips_unturned;
      ASSERT_TRUE(sim.step(nullptr));
      if (sim.contactStats().slips_unturned == unturned) worst = std::max(worst, sim.contactStats().slip_angle);
    }
    const ContactSolveStats& s = sim.contactStats();
    std::printf("%s over 8 s: largest angle between a slipping friction and -slip %.1e rad; %ld active-set answers in %ld solves "
                "kept a slip unturned, %ld unconverged\n",
                name, worst, static_cast<long>(s.slips_unturned), static_cast<long>(s.solves),
                static_cast<long>(s.unconverged));
    EXPECT_LE(worst, 1e-9) << name;
  }
}

// The active-set solve changes one guess a round; a guess that comes back to the one two rounds
// before takes the same two turns to the round limit, and the solve stays unconverged. Most of
// puma_table's did so between sticking and slipping: a slipping friction whose load pulled pointed
// along its slip, was stuck, pushed out of its cone, slid again (994 cycles, 110 unconverged solves in
// 8 s; workcell 35, table_clear 7). Now a slipping friction is not judged while its load pulls (the
// pull is), and one stuck once already is turned against its slip, not stuck again. What still cycles
// on puma_table is a touching point toggled under a slipping friction held along its direction.
// One run's count is chaotic (docs/environment.md): with the patches' limit surface this run reads 449
// cycles, where the ensemble of 12 (solve_ensemble.py) fell from 3,998 to 2,352; hence 500.
TEST(ContactAnalytic, TheActiveSetBreaksItsCycles) {
  struct Case {
    const char* name;
    int64_t most_cycles, most_unconverged;
  };
  for (const Case& c : {Case{"puma_table.yaml", 500, 60}, Case{"workcell.yaml", 0, 0}, Case{"table_clear.yaml", 0, 0}}) {
    Simulation sim(shipped(c.name));
    for (int k = 0; k < 8000; ++k) ASSERT_TRUE(sim.step(nullptr));
    const ContactSolveStats& s = sim.contactStats();
    std::printf("%s over 8 s: %ld active-set islands cycled, %ld of %ld solves unconverged\n", c.name,
                static_cast<long>(s.polish_cycles), static_cast<long>(s.unconverged), static_cast<long>(s.solves));
    EXPECT_LE(s.polish_cycles, c.most_cycles) << c.name << " (measured 449 on puma_table; 994 before the cycles were broken)";
    EXPECT_LE(s.unconverged, c.most_unconverged) << c.name << " (measured 45 on puma_table; 110 before the cycles were broken)";
  }
}

// What still cycled on puma_table: a box's corner under a slipping friction, pressed it pulls, let go
// it crosses, and the worst broken condition each round was that same corner (and longer rounds of
// the same kind, across two boxes). Now a change that leads back to a guess the polish has had gives
// way to the next worst broken condition's. Over the ensemble of 12 runs (the first box moved 0 to
// 11 nm, as scripts/bench/solve_ensemble.py moves it), the old rule cycled 1,314 times and left 189
// solves unconverged; this one 584 and 170 (eight such ensembles: 12,002 against 3,817 cycles, 1,749
// against 1,251 unconverged, fewer in each of the eight).
//
// The same runs hold every island where Lemke's method on the linearised cone is asked: its answer once
// failed its check in 18 islands (runs 8, 10 and 11), leaving 2 solves unconverged, where its pivots on
// near-singular redundant normals lost digits; now such an LCP is solved again with a larger
// regularisation (contact_linearised_cone.cc). Where the answer, each slipping friction turned against
// its slip, does not seed an exact answer, the polytope's answer as it is seeds the active set again,
// then that answer with each slipping friction carried out to the cone's edge. Where an island still
// keeps a polytope's answer, the solve goes on from it on the true cone with the sweeps left (run 7's
// island then settles; run 3's sweeps reach 2e-8 m/s at the limit, and it keeps the polytope's).
TEST(ContactAnalytic, TheActiveSetLeavesNoGuessTwice) {
  int64_t cycles = 0, unconverged = 0, lemke_failed = 0, polytope = 0;
  double angle = 0.0;
  for (int nm = 0; nm < 12; ++nm) {
    Scene scene = shipped("puma_table.yaml");
    scene.bodies.at(0).pose.p.x() += 1e-9 * nm;
    Simulation sim(scene);
    for (int k = 0; k < 8000; ++k) {
      ASSERT_TRUE(sim.step(nullptr));
      angle = std::max(angle, sim.contactStats().linearised_angle);
    }
    cycles += sim.contactStats().polish_cycles;
    unconverged += sim.contactStats().unconverged;
    lemke_failed += sim.contactStats().linearised_failed;
    polytope += sim.contactStats().linearised;
  }
  std::printf("puma_table, 12 runs of 8 s: %ld active-set islands cycled, %ld solves unconverged, %ld polytopes where "
              "Lemke's method found no answer, %ld islands left on a polytope (at most %.3f rad from opposing their "
              "slip)\n",
              static_cast<long>(cycles), static_cast<long>(unconverged), static_cast<long>(lemke_failed),
              static_cast<long>(polytope), angle);
  EXPECT_LE(cycles, 800) << "measured 279 (584 before the linearised cone); 1,314 with the worst broken condition's "
                            "change always taken";
  EXPECT_EQ(unconverged, 0) << "2 before Lemke's failed checks were solved again, 170 before the linearised cone; 189 "
                               "with the worst broken condition's change always taken";
  EXPECT_EQ(lemke_failed, 0) << "18 before its failed checks were solved again";
  EXPECT_LE(polytope, 3) << "measured 1 (run 3's); 2 before the solve went on from a polytope's answer on the cone; "
                            "with the first polytope alone 50, 98 with two seeds (no seed on the cone's edge), 253 with "
                            "the answer turned against each slip as the only seed";
  EXPECT_LE(angle, 0.45) << "measured 0.331; 0.48 with the first polytope alone (every 45 degrees)";
}

// Where the active set cannot settle an island (its sliding system not a P-matrix: principal pivoting
// need not end), Lemke's method on the linearised cone answers it, and its answer seeds the active set
// once more (contact_linearised_cone.cc). puma_table's default 8 s left 26 solves unconverged before;
// every island is now settled, exactly or, where the seed did not settle, on the polytope (counted).
TEST(ContactAnalytic, TheLinearisedConeAnswersWhatTheActiveSetCannot) {
  Simulation sim(shipped("puma_table.yaml"));
  for (int k = 0; k < 8000; ++k) ASSERT_TRUE(sim.step(nullptr));
  const ContactSolveStats& s = sim.contactStats();
  std::printf("puma_table over 8 s: %ld of %ld solves unconverged; islands on the linearised cone: %ld exact, %ld on the "
              "polytope, %ld where Lemke's method found no answer\n",
              static_cast<long>(s.unconverged), static_cast<long>(s.solves), static_cast<long>(s.linearised_exact),
              static_cast<long>(s.linearised), static_cast<long>(s.linearised_failed));
  EXPECT_EQ(s.unconverged, 0) << "26 before the linearised cone";
  EXPECT_GT(s.linearised_exact, 10) << "measured 122 (60 with two seeds, 51 with one): the islands the active set alone could not settle";
  EXPECT_EQ(s.linearised_failed, 0);
}

}  // namespace
}  // namespace igms
