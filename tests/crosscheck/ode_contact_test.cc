// Contact against ODE 0.16 (Debian), an independent simulator with a contact
// solver of its own (the LCP of dWorldStep, Dantzig's method), on the same scenes
// of free bodies (tools/ode_ref/ode_contact_scene.h: dContactApprox1, fdir1 along
// the slip, ERP 0.2 and CFM 1e-10 set). Both are first-order time steppers with
// hard Coulomb contact, so at the same step they should agree closely:
//   the sliding box's x(t) within 1e-9 m step for step (6e-11 m here), a diagonal launch as far;
//   the box on the 20 deg slope: igms sticks (1e-12 m/s);
//   the ball's rebound (e = 0.5) within 3 %, the sphere rolling down 15 deg within 1e-6;
//   balls on meshes (ODE's trimesh of the mesh's triangles): resting on a cube and in a bowl's
//   cavity at the triangles' surface in both, within ODE's rest overlap.
// What ODE does differently is reported, not asserted (its creep, its impact time): these tests are
// igms's, with ODE as the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"
#include "tools/ode_ref/ode_contact_scene.h"

namespace igms {
namespace {

constexpr double g = 9.81;

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }
Scene shipped(const char* name) { return loadScene(test::sourceDir() + "/scenes/" + name); }

// igms's free body k: world position and velocity.
Vector3 igmsPosition(const Simulation& sim, int k) {
  return sim.q().segment<3>(sim.model().parts[static_cast<size_t>(k)].q_begin);
}
Vector3 igmsVelocity(const Simulation& sim, int k) {
  return freeBodyState(sim.model().parts[static_cast<size_t>(k)], sim.q(), sim.v()).v;
}

// Both engines, step by step, for n steps of the scene's dt; `after` sees each step's end.
template <typename After>
void stepBoth(Simulation& sim, OdeContactScene& ode, int n, After&& after) {
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    ode.step(sim.scene().dt);
    after(k);
  }
}
void stepBoth(Simulation& sim, OdeContactScene& ode, int n) {
  stepBoth(sim, ode, n, [](int) {});
}

TEST(OdeContact, TheSlidingBoxFollowsOdesPathAndStopsWhereItDoes) {
  const Scene scene = shipped("box_slide.yaml");
  Simulation sim(scene);
  OdeContactScene ode(resolveScene(scene));
  double worst = 0.0;
  stepBoth(sim, ode, 400, [&](int) { worst = std::max(worst, (igmsPosition(sim, 0) - ode.pose(0).p).norm()); });
  const double travel = igmsPosition(sim, 0).x();
  std::printf("sliding box: igms stops at %.6f mm, ODE at %.6f mm; x(t) apart by %.2e m at most (%.2e of the travel)\n",
              1e3 * travel, 1e3 * ode.pose(0).p.x(), worst, worst / travel);
  EXPECT_LT(worst, 1e-9) << "the same Coulomb deceleration, step for step (6e-11 m apart here)";
}

TEST(OdeContact, ADiagonalSlideGoesAsFarInBoth) {
  Scene scene = shipped("box_slide.yaml");
  scene.bodies[0].velocity = Vector3(std::sqrt(0.5), std::sqrt(0.5), 0.0);
  Simulation sim(scene);
  OdeContactScene ode(resolveScene(scene));
  stepBoth(sim, ode, 400);
  const Vector3 a = igmsPosition(sim, 0), b = ode.pose(0).p;
  std::printf("diagonal slide: igms %.6f mm along (%.2e across), ODE %.6f mm along (%.2e across)\n",
              1e3 * std::hypot(a.x(), a.y()), std::abs(a.x() - a.y()), 1e3 * std::hypot(b.x(), b.y()),
              std::abs(b.x() - b.y()));
  EXPECT_NEAR(std::hypot(a.x(), a.y()), std::hypot(b.x(), b.y()), 1e-9) << "fdir1 along the slip: ODE's pyramid is isotropic here";
  EXPECT_LT(std::abs(a.x() - a.y()), 1e-9) << "igms slides straight";
}

TEST(OdeContact, TheBoxOnTheSlopeSticksInBoth) {
  const Scene scene = shipped("box_slope.yaml");
  Simulation sim(scene);
  OdeContactScene ode(resolveScene(scene));
  stepBoth(sim, ode, 500);
  const Vector3 a0 = igmsPosition(sim, 0), b0 = ode.pose(0).p;
  stepBoth(sim, ode, 5000);
  const double creep_igms = (igmsPosition(sim, 0) - a0).norm() / 5.0, creep_ode = (ode.pose(0).p - b0).norm() / 5.0;
  std::printf("box on 20 deg, mu 1, over 5 s: igms creeps %.2e m/s, ODE %.2e m/s\n", creep_igms, creep_ode);
  EXPECT_LT(creep_igms, 1e-12) << "a true stick (1e-18 m/s here); ODE's creep is printed, not asserted: it is ODE's";
}

TEST(OdeContact, TheBallReboundsAndTheSphereRollsAsInOde) {
  {
    const Scene scene = sceneText(
        "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5, restitution: 0.5}}\n"
        "bodies: [{name: ball, shape: sphere, radius: 0.05, mass: 0.2, xyz: [0, 0, 1.05], material: m}]\n");
    Simulation sim(scene);
    OdeContactScene ode(resolveScene(scene));
    double apex_igms = 0.0, apex_ode = 0.0;
    stepBoth(sim, ode, 1200, [&](int k) {
      if (k > 500) {
        apex_igms = std::max(apex_igms, igmsPosition(sim, 0).z() - 0.05);
        apex_ode = std::max(apex_ode, ode.pose(0).p.z() - 0.05);
      }
    });
    std::printf("ball from 1 m, e = 0.5: igms rebounds to %.5f m, ODE to %.5f m (e^2 = 0.25)\n", apex_igms, apex_ode);
    EXPECT_NEAR(apex_igms, 0.25, 0.0025);
    EXPECT_NEAR(apex_ode, apex_igms, 0.03 * apex_igms) << "ODE bounces from where it found the overlap";
  }
  {
    const double theta = 15.0 * M_PI / 180.0, r = 0.05;
    char yaml[512];
    std::snprintf(yaml, sizeof yaml,
                  "ground: {height: 0, rpy: [0, %.17g, 0]}\nbodies: [{name: b, shape: sphere, radius: %g, mass: 1, "
                  "xyz: [%.17g, 0, %.17g]}]\n",
                  theta, r, r * std::sin(theta), r * std::cos(theta));
    const Scene scene = sceneText(yaml);
    Simulation sim(scene);
    OdeContactScene ode(resolveScene(scene));
    stepBoth(sim, ode, 1000);
    const double expected = 5.0 / 7.0 * g * std::sin(theta);
    const double a_igms = igmsVelocity(sim, 0).norm(), a_ode = ode.velocity(0).norm();
    std::printf("sphere rolling down 15 deg, after 1 s: igms %.9f m/s, ODE %.9f m/s (analytic %.9f), apart %.2e\n",
                a_igms, a_ode, expected, std::abs(a_ode / a_igms - 1.0));
    EXPECT_NEAR(a_igms, expected, 5.5e-4 * expected);
    EXPECT_NEAR(a_ode, a_igms, 1e-6 * a_igms) << "1e-11 apart here";
  }
}

TEST(OdeContact, BallsRestOnAMeshCubeAndInAMeshBowlAsInOde) {
  // ball_on_mesh: a 6 cm ball 2 mm over a mesh cube whose top is at z = 0.4, a 3 cm pebble dropped
  // 0.35 m into a bowl whose cavity holds it at z = 0.08. ODE takes each mesh as a trimesh of its
  // triangles (core/geometry/shape_surface.h), which igms's contact reads as its exact surface too.
  const Scene scene = shipped("ball_on_mesh.yaml");
  Simulation sim(scene);
  OdeContactScene ode(resolveScene(scene));
  ASSERT_EQ(ode.bodies(), 2);
  // The pebble rolls on in the bowl (nothing damps rolling): each engine's lowest point in the last second.
  double low_igms[2] = {1.0, 1.0}, low_ode[2] = {1.0, 1.0};
  stepBoth(sim, ode, 4000, [&](int step) {
    for (int k = 0; step >= 3000 && k < 2; ++k) {
      low_igms[k] = std::min(low_igms[k], igmsPosition(sim, k).z());
      low_ode[k] = std::min(low_ode[k], ode.pose(k).p.z());
    }
  });
  const double rest[2] = {0.46, 0.08};
  for (int k = 0; k < 2; ++k) {
    std::printf("%s on its mesh, lowest in the 4th second: igms z = %.6f m, ODE z = %.6f m (the surface's %.2f); "
                "speeds at 4 s %.1e, %.1e m/s\n",
                ode.name(k).c_str(), low_igms[k], low_ode[k], rest[k], igmsVelocity(sim, k).norm(), ode.velocity(k).norm());
    EXPECT_NEAR(low_igms[k], rest[k], 1e-4) << ode.name(k);
    EXPECT_NEAR(low_ode[k], rest[k], 1e-3) << ode.name(k) << ": ODE rests at the trimesh's surface, less its overlap";
  }
  EXPECT_LT(igmsVelocity(sim, 0).norm(), 1e-9) << "the ball on the cube is at rest";
  EXPECT_LT(ode.velocity(0).norm(), 1e-9);
}

}  // namespace
}  // namespace igms
