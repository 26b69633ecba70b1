// Free bodies against conservation laws and Euler's equations, through the whole step (the scene,
// the environment model, the linearly-implicit and semi-implicit Euler steps, in scenes where contact
// is possible: core/integrate/free_body_motion.h):
//   the free top, I = (1, 1, 0.3) kg m^2, spinning at 50 rad/s about its symmetry axis with a 2 rad/s
//     wobble in zero gravity: energy and world angular momentum kept to round-off for 10 s and for a
//     minute, the wobble neither grows nor decays (the explicit gyroscopic term made it 415 000 J from
//     377 J in 10 s);
//   a body with its centre of mass off its frame (a mesh): energy, angular momentum about the centre
//     of mass and linear momentum kept while it tumbles;
//   the same top on the floor while it flies: a ballistic arc, then the floor;
//   a box thrown onto the floor with spin: its total energy never rises, step by step, through the
//     flight, the impacts and the slide, and it comes to rest on a face;
//   a body spun about its intermediate axis flips (Dzhanibekov): its flips are periodic with the
//     period of Euler's equations integrated here by classical RK4 at 1 us (the DOP853 comparison is
//     free_body_accuracy_test.py's).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/integrate/free_body_motion.h"
#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }

const ModelPart& partNamed(const Simulation& sim, const std::string& name) {
  for (const ModelPart& part : sim.model().parts)
    if (part.name == name) return part;
  throw std::runtime_error("no part " + name);
}

// A free body's mechanical quantities, from its state and its inertia (about the centre of mass).
struct Mechanics {
  double kinetic = 0.0, potential = 0.0;
  Vector3 momentum = Vector3::Zero();          // linear, world
  Vector3 spin = Vector3::Zero();              // angular momentum about the centre of mass, world
  Vector3 w_body = Vector3::Zero();            // body angular velocity
  Vector3 com = Vector3::Zero();
  double energy() const { return kinetic + potential; }
};

Mechanics mechanics(const Simulation& sim, const std::string& name) {
  const ModelPart& part = partNamed(sim, name);
  const SpatialInertia& I = sim.model().inertia[static_cast<size_t>(part.body_begin)];
  const FreeBodyState s = freeBodyState(part, sim.q(), sim.v());
  const Vector3 c = I.com();
  const Matrix3 Ic = I.inertiaAboutCom();
  Mechanics out;
  out.w_body = sim.v().segment<3>(part.dof_begin + 3);
  const Vector3 u = s.v + s.w.cross(s.R * c);  // the centre of mass's world velocity
  out.com = s.p + s.R * c;
  out.kinetic = 0.5 * I.m * u.squaredNorm() + 0.5 * out.w_body.dot(Ic * out.w_body);
  out.potential = -I.m * sim.model().gravity.dot(out.com);
  out.momentum = I.m * u;
  out.spin = s.R * (Ic * out.w_body);
  return out;
}

constexpr char kTop[] =
    "gravity: [0, 0, 0]\nground: {height: -5}\nsimulation: {integrator: %s, dt: 0.001}\n"
    "bodies: [{name: top, shape: cylinder, radius: 0.2, length: 0.05, mass: 1, inertia: [1, 1, 0.3, 0, 0, 0], "
    "xyz: [0, 0, 0], w: [2, 0, 50]}]\n";

struct Drift {
  double energy = 0.0, momentum = 0.0, wobble = 0.0;
};

Drift spinTop(const char* integrator, double seconds, const char* scene = kTop) {
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml, scene, integrator);
  Simulation sim(sceneText(yaml));
  const Mechanics m0 = mechanics(sim, "top");
  Drift d;
  const int steps = static_cast<int>(std::lround(seconds / sim.scene().dt));
  for (int k = 0; k < steps; ++k) {
    EXPECT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    const Mechanics m = mechanics(sim, "top");
    d.energy = std::max(d.energy, std::abs(m.energy() - m0.energy()) / m0.energy());
    d.momentum = std::max(d.momentum, (m.spin - m0.spin).norm() / m0.spin.norm());
    d.wobble = std::max(d.wobble, std::abs(m.w_body.head<2>().norm() - 2.0));
  }
  EXPECT_EQ(sim.contacts().n, 0) << "nothing touched the top";
  return d;
}

TEST(FreeBody, TheFreeTopKeepsItsEnergyAndAngularMomentum) {
  for (const char* integrator : {"linearly_implicit", "semi_implicit_euler"}) {
    const Drift d = spinTop(integrator, 10.0);
    std::printf("free top, %s, 10 s at 1 ms: energy within %.2e, angular momentum within %.2e, wobble |w_xy| - 2 "
                "within %.2e rad/s\n",
                integrator, d.energy, d.momentum, d.wobble);
    // The goals are 1e-3 and 1e-6; the scheme keeps both to round-off (1e-13 here).
    EXPECT_LT(d.energy, 1e-10) << integrator;
    EXPECT_LT(d.momentum, 1e-10) << integrator;
    EXPECT_LT(d.wobble, 1e-8) << integrator << ": a symmetric top's wobble keeps its size";
  }
}

TEST(FreeBody, TheFreeTopSpinsForAMinuteAtConstantEnergy) {
  const Drift d = spinTop("linearly_implicit", 60.0);
  std::printf("free top, 60 s: energy within %.2e, angular momentum within %.2e\n", d.energy, d.momentum);
  EXPECT_LT(d.energy, 1e-10);
  EXPECT_LT(d.momentum, 1e-10);
}

TEST(FreeBody, TheFreeTopInASceneWithoutContactToo) {
  // No ground: the step takes no contact solve at all (the integrators' other branch).
  const char* scene =
      "gravity: [0, 0, 0]\nsimulation: {integrator: %s, dt: 0.001}\n"
      "bodies: [{name: top, shape: cylinder, radius: 0.2, length: 0.05, mass: 1, inertia: [1, 1, 0.3, 0, 0, 0], "
      "xyz: [0, 0, 0], w: [2, 0, 50]}]\n";
  const Drift d = spinTop("linearly_implicit", 10.0, scene);
  std::printf("free top without contact: energy within %.2e, angular momentum within %.2e\n", d.energy, d.momentum);
  EXPECT_LT(d.energy, 1e-10);
  EXPECT_LT(d.momentum, 1e-10);
}

TEST(FreeBody, AMeshTumblingAboutItsOffsetCentreOfMassKeepsItsMomenta) {
  // The U channel's centre of mass is off its frame and its inertia is not diagonal.
  Simulation sim(sceneText(
      "gravity: [0, 0, 0]\nground: {height: -5}\n"
      "bodies: [{name: u, shape: mesh, file: ../models/meshes/u_channel.obj, density: 500, xyz: [0, 0, 0], "
      "v: [0.3, -0.2, 0.1], w: [3, -7, 11]}]\n"));
  const ModelPart& part = partNamed(sim, "u");
  ASSERT_GT(sim.model().inertia[static_cast<size_t>(part.body_begin)].com().norm(), 1e-3) << "an offset centre of mass";
  const Mechanics m0 = mechanics(sim, "u");
  const Vector3 u0 = m0.momentum / sim.model().inertia[static_cast<size_t>(part.body_begin)].m;
  double energy = 0.0, spin = 0.0, momentum = 0.0, path = 0.0;
  for (int k = 1; k <= 5000; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    const Mechanics m = mechanics(sim, "u");
    energy = std::max(energy, std::abs(m.energy() - m0.energy()) / m0.energy());
    spin = std::max(spin, (m.spin - m0.spin).norm() / m0.spin.norm());
    momentum = std::max(momentum, (m.momentum - m0.momentum).norm() / m0.momentum.norm());
    // The centre of mass goes straight at its initial velocity.
    path = std::max(path, (m.com - (m0.com + k * sim.scene().dt * u0)).norm());
  }
  std::printf("tumbling U channel, 5 s: energy within %.2e, spin %.2e, momentum %.2e, centre of mass off its line by "
              "%.2e m\n",
              energy, spin, momentum, path);
  EXPECT_LT(energy, 1e-10);
  EXPECT_LT(spin, 1e-10);
  EXPECT_LT(momentum, 1e-12);
  EXPECT_LT(path, 1e-12);
}

TEST(FreeBody, AThrownSpinningBoxNeverGainsEnergy) {
  Simulation sim(sceneText(
      "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.6}}\n"
      "bodies: [{name: box, shape: box, size: [0.3, 0.2, 0.1], mass: 2, xyz: [0, 0, 0.8], rpy: [0.3, 0.2, 0.1], "
      "v: [1.5, 0.5, 4], w: [12, -25, 30], material: m}]\n"));
  double previous = mechanics(sim, "box").energy(), worst_rise = 0.0, lowest = 1e9;
  int worst_step = -1, impacts = 0;
  bool was_touching = false;
  for (int k = 1; k <= 4000; ++k) {
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    const double e = mechanics(sim, "box").energy();
    if (e - previous > worst_rise) {
      worst_rise = e - previous;
      worst_step = k;
    }
    previous = e;
    const bool touching = sim.contacts().n > 0;
    impacts += touching && !was_touching;
    was_touching = touching;
    lowest = std::min(lowest, -sim.contacts().maxPenetration());
  }
  const Mechanics end = mechanics(sim, "box");
  std::printf("thrown box: %d impacts, largest rise of energy in a step %.3e J (step %d), at 4 s kinetic %.3e J, "
              "deepest overlap %.2e m\n",
              impacts, worst_rise, worst_step, end.kinetic, -lowest);
  EXPECT_GE(impacts, 1);
  EXPECT_LE(worst_rise, 1e-12) << "energy never rises (round-off aside)";
  EXPECT_LT(end.kinetic, 1e-12) << "at rest";
  EXPECT_LE(-lowest, 1e-4);
}

// Euler's equations for a body at rest in space otherwise: w' = I^-1 (-w x I w), by classical RK4.
Vector3 eulerRate(const Vector3& I, const Vector3& w) {
  return Vector3((I.y() - I.z()) * w.y() * w.z() / I.x(), (I.z() - I.x()) * w.z() * w.x() / I.y(),
                 (I.x() - I.y()) * w.x() * w.y() / I.z());
}

// The times the body's w about its intermediate axis (y) changes sign from positive to negative.
std::vector<double> referenceFlips(const Vector3& I, Vector3 w, double seconds) {
  const double h = 1e-6;
  std::vector<double> out;
  for (long k = 0; k * h < seconds; ++k) {
    const Vector3 k1 = eulerRate(I, w), k2 = eulerRate(I, w + 0.5 * h * k1), k3 = eulerRate(I, w + 0.5 * h * k2),
                  k4 = eulerRate(I, w + h * k3);
    const Vector3 next = w + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    if (w.y() > 0.0 && next.y() <= 0.0) out.push_back((k + w.y() / (w.y() - next.y())) * h);
    w = next;
  }
  return out;
}

TEST(FreeBody, ABodySpunNearItsIntermediateAxisFlipsWithEulersPeriod) {
  const Vector3 I(1.0, 2.0, 3.0), w0(0.1, 5.0, 0.1);
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml,
                "gravity: [0, 0, 0]\nground: {height: -5}\n"
                "bodies: [{name: t, shape: box, size: [0.1, 0.1, 0.1], mass: 1, inertia: [%g, %g, %g, 0, 0, 0], "
                "w: [%g, %g, %g]}]\n",
                I.x(), I.y(), I.z(), w0.x(), w0.y(), w0.z());
  Simulation sim(sceneText(yaml));
  const double seconds = 20.0;
  std::vector<double> flips;
  double wy = w0.y();
  const int steps = static_cast<int>(std::lround(seconds / sim.scene().dt));
  for (int k = 1; k <= steps; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    const double now = mechanics(sim, "t").w_body.y();
    if (wy > 0.0 && now <= 0.0) flips.push_back((k - 1 + wy / (wy - now)) * sim.scene().dt);
    wy = now;
  }
  const std::vector<double> truth = referenceFlips(I, w0, seconds);
  ASSERT_GE(truth.size(), 2u);
  ASSERT_EQ(flips.size(), truth.size()) << "as many flips as Euler's equations make";
  const double period = (flips.back() - flips.front()) / static_cast<double>(flips.size() - 1);
  const double expected = (truth.back() - truth.front()) / static_cast<double>(truth.size() - 1);
  std::printf("Dzhanibekov: %zu flips, period %.6f s (RK4 at 1 us: %.6f s, %+.2e)\n", flips.size(), period, expected,
              period / expected - 1.0);
  EXPECT_NEAR(period, expected, 1e-5 * expected) << "the issue's goal is 1 %; the explicit gyroscopic term was 1.9e-4 off";
}

TEST(FreeBody, TheMidpointStepKeepsBothInvariantsExactly) {
  // One step of each rotation scheme on its own, at a large h w (0.5 rad a step).
  const Matrix3 I = Vector3(1.0, 2.0, 3.5).asDiagonal();
  const Vector3 w(3.0, -10.0, 2.0);
  Vector3 wm;
  const Vector3 mid = FreeBodyMotion::midpoint(I, w, 0.05, &wm);
  EXPECT_NEAR(mid.dot(I * mid), w.dot(I * w), 1e-12 * w.dot(I * w)) << "energy";
  EXPECT_NEAR((I * mid).norm(), (I * w).norm(), 1e-12 * (I * w).norm()) << "|L| in the body";
  const Vector3 be = FreeBodyMotion::backwardEuler(I, w, 0.05);
  EXPECT_LT(be.dot(I * be), w.dot(I * w)) << "backward Euler loses energy, never gains it";
}

}  // namespace
}  // namespace igms
