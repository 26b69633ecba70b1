// Contact inside one system keeps its total momentum (Newton's third law through the whole step): a
// floating-base robot whose legs strike each other in zero gravity (self-collision), with contact
// and joint impulses internal, keeps the spatial momentum of all its bodies to round-off. The
// Delassus blocks of a self-contact must carry the dofs both links share (the floating base's, a
// common hip), which take the reaction. And a chain deeper than the solver's old fixed buffers (64 dofs
// a side) rests on the ground with its weight carried. And the solve's generalised impulse is J^T of
// the impulses it reports, J from the kinematics alone, on points, patches, pairs of free bodies and
// a self-contact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/environment_model.h"
#include "core/scene/scene.h"
#include "core/simulation/simulation.h"
#include "tests/support/contact_solve_probe.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }

TEST(ContactMomentum, LegsStrikingEachOtherPutNoNetImpulseOnTheRobot) {
  // The quadruped's front legs swung toward each other (lf_hip_abad -6 rad/s, rf_hip_abad +6; the
  // joints come lf, lh, rf, rh, by name), no gravity, a weak joint PD. At each step where they touch,
  // the contact solve alone, on H's factor (A = H): v+ - v = H^-1 J^T lambda, so H (v+ - v) is the
  // generalised impulse, and its base rows, the contact's net spatial impulse on the robot, are zero
  // for a contact inside it.
  Simulation sim(sceneText(
      "robot: {model: ../models/quadruped.urdf, floating_base: true}\ngravity: [0, 0, 0]\n"
      "initial:\n  q: [0, 0, 0, 1, 0, 0, 0,  0, 0.6, -1.2,  0, 0.6, -1.2,  0, 0.6, -1.2,  0, 0.6, -1.2]\n"
      "  v: [0, 0, 0, 0, 0, 0,  -6, 0, 0,  0, 0, 0,  6, 0, 0,  0, 0, 0]\n"
      "controller: {kind: pd, kp: 1, kd: 0.01}\ncontact: {self_collision: true}\n"
      "simulation: {integrator: linearly_implicit, dt: 0.001}\n"));
  test::ContactSolveProbe probe(sim);
  double worst = 0.0, largest = 0.0;
  int touching = 0;
  for (int k = 0; k < 400; ++k) {
    if (probe.solveFrom(sim.q(), sim.v(), sim.v())) {
      ++touching;
      const VectorX impulse = probe.data.H.symmetricUpperTimes(probe.v - sim.v());
      largest = std::max(largest, impulse.norm());
      worst = std::max(worst, impulse.head<6>().norm());
    }
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  }
  std::printf("legs striking each other: in contact %d of 400 steps, the contact's generalised impulse up to %.3e, "
              "its net impulse on the robot up to %.2e\n",
              touching, largest, worst);
  ASSERT_GT(touching, 0) << "the legs meet";
  ASSERT_GT(largest, 1e-2);
  EXPECT_LT(worst, 1e-12 * largest + 1e-15);
}

TEST(ContactMomentum, APatchsPointImpulsesAddUpToTheWrenchItsBodyTook) {
  // A box flat on the floor, sliding and spinning (its patch's friction and torsion both at work):
  // the impulses IGMS_CONTACTS reports per point must add up to the change of the box's momentum
  // (gravity's h m g aside) and their moments about its centre to the change of its spin.
  Simulation sim(sceneText(
      "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5}}\n"
      "bodies: [{name: box, shape: box, size: [0.3, 0.2, 0.1], mass: 2, xyz: [0, 0, 0.05], v: [1, 0.5, 0], "
      "w: [0, 0, 5], material: m}]\n"));
  const double m = 2.0, Iz = m * (0.3 * 0.3 + 0.2 * 0.2) / 12.0, h = sim.scene().dt;
  const ModelPart& part = sim.model().parts.front();
  double force_error = 0.0, moment_error = 0.0, largest_moment = 0.0;
  int sliding = 0;
  for (int k = 0; k < 300; ++k) {
    const FreeBodyState before = freeBodyState(part, sim.q(), sim.v());
    ASSERT_TRUE(sim.step(nullptr));
    const FreeBodyState after = freeBodyState(part, sim.q(), sim.v());
    if (sim.contacts().n == 0 || before.w.norm() < 1e-3) continue;
    ++sliding;
    Vector3 force = Vector3::Zero();
    double moment = 0.0;
    for (int c = 0; c < sim.contacts().n; ++c) {
      const Contact& ct = sim.contacts()[c];
      const Vector3 on_box = ct.body_b >= 0 ? ct.impulse : Vector3(-ct.impulse);  // the box's side
      force += on_box;
      moment += (ct.point - before.p).cross(on_box).z();
    }
    force_error = std::max(force_error, (force - (m * (after.v - before.v) - h * m * sim.model().gravity)).norm());
    moment_error = std::max(moment_error, std::abs(moment - Iz * (after.w.z() - before.w.z())));
    largest_moment = std::max(largest_moment, std::abs(moment));
  }
  std::printf("a sliding, spinning box: %d steps; the points' impulses off the box's change of momentum by %.2e N s, "
              "their moments off its change of spin by %.2e N m s (largest %.3e)\n",
              sliding, force_error, moment_error, largest_moment);
  ASSERT_GT(sliding, 50);
  EXPECT_LT(force_error, 1e-12);
  EXPECT_LT(moment_error, 1e-9 * largest_moment);
}

// A snake of n links (0.05 m apart, each a 2 cm ball of 0.1 kg, hinged about z) on a floating base.
std::string snakeUrdf(int n) {
  std::string u = "<robot name=\"snake\">";
  for (int k = 0; k < n; ++k) {
    u += "<link name=\"l" + std::to_string(k) +
         "\"><inertial><mass value=\"0.1\"/><inertia ixx=\"1.6e-5\" iyy=\"1.6e-5\" izz=\"1.6e-5\" ixy=\"0\" "
         "ixz=\"0\" iyz=\"0\"/></inertial><collision><geometry><sphere radius=\"0.02\"/></geometry></collision></link>";
    if (k > 0)
      u += "<joint name=\"j" + std::to_string(k) + "\" type=\"revolute\"><parent link=\"l" + std::to_string(k - 1) +
           "\"/><child link=\"l" + std::to_string(k) +
           "\"/><origin xyz=\"0.05 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" "
           "velocity=\"10\"/></joint>";
  }
  return u + "</robot>";
}

TEST(ContactMomentum, ASnakeDeeperThanTheSolversOldBuffersRestsOnTheGround) {
  // 150 links in one chain: a contact at its tail involves 155 dofs (the solver kept 128 on its stack).
  const std::string path = ::testing::TempDir() + "/snake150.urdf";
  std::ofstream(path) << snakeUrdf(150);
  std::string q = "[0, 0, 0.02, 1, 0, 0, 0";  // the base on the ground, the snake straight
  for (int k = 1; k < 150; ++k) q += ", 0";
  Simulation sim(sceneText("robot: {model: " + path + ", floating_base: true}\nground: {height: 0}\n"
                           "initial: {q: " + q + "]}\ncontroller: {kind: pd, kp: 5, kd: 0.2}\n"
                           "simulation: {integrator: linearly_implicit, dt: 0.001}\n"));
  for (int k = 0; k < 500; ++k) ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  double carried = 0.0;
  for (int c = 0; c < sim.contacts().n; ++c) carried += std::abs(sim.contacts()[c].impulse.z()) / sim.scene().dt;
  const double weight = sim.model().totalMass() * 9.81;
  std::printf("150-link snake on the ground: %d contacts carry %.9f N (m g %.9f N), fastest dof %.2e\n",
              sim.contacts().n, carried, weight, sim.v().cwiseAbs().maxCoeff());
  EXPECT_EQ(sim.contacts().n, 150);
  EXPECT_NEAR(carried, weight, 1e-6 * weight);
  EXPECT_LT(sim.v().cwiseAbs().maxCoeff(), 1e-6) << "at rest";
}

// The generalised impulse the solve gave, H (v+ - v_free) (the probe's A = H), against J^T of the
// impulses it reports: each point's [impulse; moment] through its two bodies' point Jacobians, formed
// from the kinematics alone (not the rows' X = L^-T J^T, their chains of entries, W or the solve's
// accumulator). \return the largest relative error over the steps where something touched.
double generalisedImpulseError(Simulation& sim, int steps, int* touching) {
  test::ContactSolveProbe probe(sim);
  const Model& model = sim.model();
  std::vector<int> frame_of(static_cast<size_t>(model.nb), -1);  // a frame on each body
  for (int f = static_cast<int>(model.frames.size()) - 1; f >= 0; --f)
    if (model.frames[static_cast<size_t>(f)].body >= 0) frame_of[static_cast<size_t>(model.frames[static_cast<size_t>(f)].body)] = f;
  Matrix6X J(6, model.nv);
  double worst = 0.0;
  *touching = 0;
  for (int k = 0; k < steps; ++k) {
    if (probe.solve(sim.q(), sim.v())) {
      VectorX tau = VectorX::Zero(model.nv);
      for (int c = 0; c < probe.set.n; ++c) {
        const Contact& ct = probe.set[c];
        Vector6 wrench;
        wrench << ct.impulse, ct.moment;
        for (const auto& [body, sign] : {std::pair<int, double>{ct.body_b, 1.0}, {ct.body_a, -1.0}}) {
          if (body < 0) continue;
          const int f = frame_of[static_cast<size_t>(body)];
          pointJacobian(model, probe.data, f, framePose(model, probe.data, f).inverse().act(ct.point), J);
          tau += sign * J.transpose() * wrench;
        }
      }
      const VectorX impulse = probe.data.H.symmetricUpperTimes(probe.v - probe.v_free);
      if (tau.norm() > 1e-9) {
        ++*touching;
        worst = std::max(worst, (impulse - tau).norm() / tau.norm());
      }
    }
    EXPECT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  }
  return worst;
}

TEST(ContactMomentum, TheGeneralisedImpulseIsTheJacobiansTransposeOfTheReportedImpulses) {
  // Go1's four feet on the ground (points; each foot's entries one path from the base), Talos's two
  // soles (patches, friction at their centroids, torsion), a tower of boxes (pairs between two free
  // bodies), the quadruped's legs striking each other (one tree: a pair's entries branch) and a box
  // whose inertia has products.
  const std::string dir = test::sourceDir() + "/scenes/";
  struct Case {
    std::string name;
    Scene scene;
    int touching;  // steps in contact at least, of 300
  };
  std::vector<Case> cases;
  cases.push_back({"go1_stand", loadScene(dir + "go1_stand.yaml"), 300});
  cases.push_back({"talos_stand", loadScene(dir + "talos_stand.yaml"), 300});
  cases.push_back({"box_tower", loadScene(dir + "box_tower.yaml"), 300});
  cases.push_back({"quadruped legs striking", sceneText(
      "robot: {model: ../models/quadruped.urdf, floating_base: true}\ngravity: [0, 0, 0]\n"
      "initial:\n  q: [0, 0, 0, 1, 0, 0, 0,  0, 0.6, -1.2,  0, 0.6, -1.2,  0, 0.6, -1.2,  0, 0.6, -1.2]\n"
      "  v: [0, 0, 0, 0, 0, 0,  -6, 0, 0,  0, 0, 0,  6, 0, 0,  0, 0, 0]\n"
      "controller: {kind: pd, kp: 1, kd: 0.01}\ncontact: {self_collision: true}\n"
      "simulation: {integrator: linearly_implicit, dt: 0.001}\n"), 2});  // the strike is brief
  // A box whose inertia has products (body axes not its principal axes: its block of L is not the
  // identity, so its chains must move X), dropped tilted: it lands on a corner, falls onto a face and
  // slides. (The check reads 8.5e-12, above the other cases' round-off: likely its patch's points a few
  // um off one plane, measured only for the spinning case. Skipping its chains reads 7.2e-2. Spinning
  // as well, it reads 1.5e-6: see docs/environment.md.)
  cases.push_back({"box with products of inertia", sceneText(
      "ground: {height: 0}\nbodies:\n"
      "  - {name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1.0, xyz: [0, 0, 0.16], rpy: [0.4, 0.3, 0],\n"
      "     v: [1, 0.3, 0], inertia: [0.0067, 0.0080, 0.0060, 0.0025, -0.0015, 0.0020]}\n"
      "simulation: {integrator: linearly_implicit, dt: 0.001}\n"), 200});
  for (Case& c : cases) {
    Simulation sim(c.scene);
    int touching = 0;
    const double error = generalisedImpulseError(sim, 300, &touching);
    std::printf("%s: in contact %d of 300 steps; H (v+ - v_free) off J^T of the reported impulses by %.2e (relative)\n",
                c.name.c_str(), touching, error);
    EXPECT_GE(touching, c.touching) << c.name;
    EXPECT_LT(error, 1e-10) << c.name;
  }
}

}  // namespace
}  // namespace igms
