// Impacts never add kinetic energy. Each case runs through the whole step; at every step with contact
// the contact solve is also taken alone (ContactSolver on the step's state with A = H: v_free the
// unconstrained velocity, v+ after the impulses), and the kinetic energy it leaves, 1/2 v+^T H v+, is
// held to at most the 1/2 v_free^T H v_free it was given (round-off aside). Newton's restitution law
// applied to several points at once, with friction that sticks or beside a contact that separates,
// can give back more than came in (Kane's rod, Stronge's examples): the solve scales restitution down
// where it would.
//   a rod landing end-first on the ground, e 0.8, friction that sticks;
//   a box landing on an edge, e 0.9;
//   a light ball between two heavy ones, e 1, struck by one of them;
//   Newton's cradle of three and five balls, e 1: the blow passes along the row pair by pair
//   (contact_impacts.h), and only the last ball leaves, at the first one's speed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/contact_solve_probe.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }

struct Impacts {
  int steps_with_contact = 0;
  double largest_gain = 0.0;  // J: the contact solve's largest rise of kinetic energy
  double largest_energy = 0.0;
};

// Steps the scene for `steps`, and at each step with contact takes the contact solve alone.
Impacts measure(Simulation& sim, int steps) {
  test::ContactSolveProbe probe(sim);
  Impacts out;
  for (int k = 0; k < steps; ++k) {
    if (probe.solve(sim.q(), sim.v())) {
      ++out.steps_with_contact;
      const TreeMatrix& H = probe.data.H;
      const double before = 0.5 * probe.v_free.dot(H.symmetricUpperTimes(probe.v_free)),
                   after = 0.5 * probe.v.dot(H.symmetricUpperTimes(probe.v));
      out.largest_gain = std::max(out.largest_gain, after - before);
      out.largest_energy = std::max(out.largest_energy, before);
    }
    EXPECT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  }
  return out;
}

void expectNoGain(const char* what, const std::string& yaml, int steps) {
  Simulation sim(sceneText(yaml));
  const Impacts r = measure(sim, steps);
  std::printf("%-34s %4d steps with contact, largest rise of kinetic energy in a contact solve %+.3e J (of %.3e J)\n",
              what, r.steps_with_contact, r.largest_gain, r.largest_energy);
  EXPECT_GT(r.steps_with_contact, 0) << what;
  EXPECT_LE(r.largest_gain, 1e-12 * r.largest_energy) << what;
}

TEST(ContactImpact, ARodLandingEndFirstGainsNoEnergy) {
  expectNoGain("rod end-first, e 0.8, sticking",
               "ground: {height: 0, material: m}\nmaterials: {m: {friction: 1.0, restitution: 0.8}}\n"
               "bodies: [{name: rod, shape: capsule, radius: 0.01, length: 1.0, mass: 1, xyz: [0, 0, 0.6], "
               "rpy: [0, 0.6, 0], v: [0, 0, -3], material: m}]\n",
               800);
}

TEST(ContactImpact, ABoxLandingOnAnEdgeGainsNoEnergy) {
  expectNoGain("box on an edge, e 0.9",
               "ground: {height: 0, material: m}\nmaterials: {m: {friction: 0.7, restitution: 0.9}}\n"
               "bodies: [{name: box, shape: box, size: [0.3, 0.2, 0.1], mass: 2, xyz: [0, 0, 0.3], "
               "rpy: [0.7854, 0.2, 0], v: [0.5, 0, -2], w: [0, 3, 0], material: m}]\n",
               1500);
}

TEST(ContactImpact, ALightBallBetweenTwoHeavyOnesGainsNoEnergy) {
  expectNoGain("light ball between heavy ones, e 1",
               "gravity: [0, 0, 0]\nmaterials: {m: {friction: 0.3, restitution: 1.0}}\n"
               "bodies:\n"
               "  - {name: a, shape: sphere, radius: 0.05, mass: 10, xyz: [-0.102, 0, 0], v: [1, 0, 0.2], material: m}\n"
               "  - {name: b, shape: sphere, radius: 0.02, mass: 0.1, xyz: [0.0, 0.0, 0.0], material: m}\n"
               "  - {name: c, shape: sphere, radius: 0.05, mass: 10, xyz: [0.07, 0.002, 0.0], material: m}\n",
               400);
}

// Newton's cradle of n balls in a row, the first moving in at 1 m/s, 2 mm from the second; the others
// `gap` apart (0: touching; a nanometre: apart, so their pairs wait outside the solve until struck).
std::string cradle(int n, double gap = 0.0) {
  std::string y = "gravity: [0, 0, 0]\nmaterials: {steel: {friction: 0.0, restitution: 1.0}}\nbodies:\n";
  for (int k = 0; k < n; ++k) {
    char x[64];
    std::snprintf(x, sizeof x, "%.17g", k == 0 ? -0.102 : (0.1 + gap) * (k - 1));
    y += "  - {name: b" + std::to_string(k) + ", shape: sphere, radius: 0.05, mass: 1, xyz: [" + x + ", 0, 0]" +
         (k == 0 ? ", v: [1, 0, 0]" : "") + ", material: steel}\n";
  }
  return y;
}

TEST(ContactImpact, NewtonsCradleSendsOnlyTheLastBallAway) {
  for (const auto& [n, gap] : {std::pair{3, 0.0}, {5, 0.0}, {3, 1e-9}, {5, 1e-9}}) {
    Simulation sim(sceneText(cradle(n, gap)));
    const Impacts r = measure(sim, 300);
    double p = 0.0, e = 0.0, resting = 0.0, last = 0.0;
    std::printf("cradle of %d, %g m apart, e 1, after 0.3 s:", n, gap);
    for (const ModelPart& part : sim.model().parts) {
      const FreeBodyState s = freeBodyState(part, sim.q(), sim.v());
      p += s.v.x();
      e += 0.5 * s.v.squaredNorm();
      std::printf(" %+.6f", s.v.x());
      if (&part == &sim.model().parts.back()) last = s.v.x();
      else resting = std::max(resting, s.v.norm());
    }
    std::printf(" m/s; momentum %.12f, energy %.12f, largest rise in a solve %+.2e J\n", p, e, r.largest_gain);
    EXPECT_NEAR(p, 1.0, 1e-9) << n;
    EXPECT_NEAR(e, 0.5, 1e-9) << n << ": e = 1 keeps the energy";
    EXPECT_LE(r.largest_gain, 1e-12) << n;
    // The goal: only the last ball leaves, at the first one's speed, within 1 %.
    EXPECT_NEAR(last, 1.0, 0.01) << n;
    EXPECT_LT(resting, 0.01) << n;
  }
}

// A pair apart inside the margin and not closing waits outside the solve, without rows; when the
// others' impulses push it across within the step, it is let in and the solve taken again. A plastic
// blow (e 0): a at 4 m/s strikes b, which would move 2 mm in the step toward c, 1 mm away.
TEST(ContactImpact, APairStruckAcrossItsGapIsLetInWithinTheStep) {
  Simulation sim(sceneText(
      "gravity: [0, 0, 0]\nsimulation: {dt: 0.001}\nmaterials: {m: {friction: 0.0, restitution: 0.0}}\nbodies:\n"
      "  - {name: a, shape: sphere, radius: 0.05, mass: 1, xyz: [-0.1, 0, 0], v: [4, 0, 0], material: m}\n"
      "  - {name: b, shape: sphere, radius: 0.05, mass: 1, xyz: [0, 0, 0], material: m}\n"
      "  - {name: c, shape: sphere, radius: 0.05, mass: 1, xyz: [0.101, 0, 0], material: m}\n"));
  ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  const auto& parts = sim.model().parts;
  const FreeBodyState a = freeBodyState(parts[0], sim.q(), sim.v()), b = freeBodyState(parts[1], sim.q(), sim.v()),
                      c = freeBodyState(parts[2], sim.q(), sim.v());
  std::printf("struck across a 1 mm gap: let in %lld, b-c gap %+.3e m, velocities %+.6f %+.6f %+.6f m/s\n",
              static_cast<long long>(sim.contactStats().let_in), (c.p - b.p).norm() - 0.1, a.v.x(), b.v.x(), c.v.x());
  EXPECT_GE(sim.contactStats().let_in, 1);
  EXPECT_GE((c.p - b.p).norm() - 0.1, -1e-9) << "b does not pass into c";
  EXPECT_GT(c.v.x(), 0.5) << "c takes part of the blow in the same step";
  EXPECT_NEAR(a.v.x() + b.v.x() + c.v.x(), 4.0, 1e-9) << "momentum";
}

// The same blow with two sweeps allowed: they and the exact solve settle a and b (2 m/s each), the
// pair b-c let in after them gets none, and the solve is unconverged. Its residual says how far off
// it is, b crossing into c at 2 m/s against a gap the step closes at 1 m/s: 1 m/s, not the 0 it read
// when the pass that let the pair in ran no sweep.
TEST(ContactImpact, ASolveThatStopsWithAPairLetInReportsItsCrossing) {
  Simulation sim(sceneText(
      "gravity: [0, 0, 0]\nsimulation: {dt: 0.001}\ncontact: {iterations: 2}\n"
      "materials: {m: {friction: 0.0, restitution: 0.0}}\nbodies:\n"
      "  - {name: a, shape: sphere, radius: 0.05, mass: 1, xyz: [-0.1, 0, 0], v: [4, 0, 0], material: m}\n"
      "  - {name: b, shape: sphere, radius: 0.05, mass: 1, xyz: [0, 0, 0], material: m}\n"
      "  - {name: c, shape: sphere, radius: 0.05, mass: 1, xyz: [0.101, 0, 0], material: m}\n"));
  ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
  const ContactSolveStats& s = sim.contactStats();
  std::printf("two sweeps, a pair let in: let in %lld, unconverged %lld, residual %.3e m/s\n",
              static_cast<long long>(s.let_in), static_cast<long long>(s.unconverged), s.residual);
  ASSERT_GE(s.let_in, 1);
  ASSERT_EQ(s.unconverged, 1);
  EXPECT_NEAR(s.residual, 1.0, 1e-6) << "the crossing the solve left";
}

// Two balls in at 1 m/s against three at rest, all touching: the last two leave, the first three stay.
TEST(ContactImpact, TwoBallsInSendTwoBallsOut) {
  std::string y = "gravity: [0, 0, 0]\nmaterials: {steel: {friction: 0.0, restitution: 1.0}}\nbodies:\n";
  for (int k = 0; k < 5; ++k)
    y += "  - {name: b" + std::to_string(k) + ", shape: sphere, radius: 0.05, mass: 1, xyz: [" +
         std::to_string(k < 2 ? 0.1 * k - 0.202 : 0.1 * (k - 2)) + ", 0, 0]" + (k < 2 ? ", v: [1, 0, 0]" : "") +
         ", material: steel}\n";
  Simulation sim(sceneText(y));
  const Impacts r = measure(sim, 300);
  std::printf("two in, five balls, e 1, after 0.3 s:");
  for (int k = 0; k < 5; ++k) {
    const FreeBodyState s = freeBodyState(sim.model().parts[static_cast<size_t>(k)], sim.q(), sim.v());
    std::printf(" %+.6f", s.v.x());
    EXPECT_NEAR(s.v.x(), k < 3 ? 0.0 : 1.0, 0.01) << "ball " << k;
  }
  std::printf(" m/s, largest rise in a solve %+.2e J\n", r.largest_gain);
  EXPECT_LE(r.largest_gain, 1e-12);
}

// A cradle standing on the floor (friction 0.3 there, the balls rolling in): right after the blow the
// last ball leaves at the first one's speed, the first stops (its spin then drives it on: the floor's
// business, not the blow's).
TEST(ContactImpact, ACradleOnTheFloorPassesTheBlowAlong) {
  std::string y = "ground: {height: 0, material: floor}\n"
                  "materials: {steel: {friction: 0.0, restitution: 1.0}, floor: {friction: 0.3, restitution: 0.0}}\n"
                  "bodies:\n";
  for (int k = 0; k < 3; ++k)
    y += "  - {name: b" + std::to_string(k) + ", shape: sphere, radius: 0.05, mass: 1, xyz: [" +
         std::to_string(k == 0 ? -0.102 : 0.1 * (k - 1)) + ", 0, 0.05]" + (k == 0 ? ", v: [1, 0, 0], w: [0, 20, 0]" : "") +
         ", material: steel}\n";
  Simulation sim(sceneText(y));
  int k = 0;
  for (; k < 100; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    if (freeBodyState(sim.model().parts[2], sim.q(), sim.v()).v.x() > 0.5) break;
  }
  ASSERT_LT(k, 100) << "the blow never reached the last ball";
  double v[3];
  for (int b = 0; b < 3; ++b) v[b] = freeBodyState(sim.model().parts[static_cast<size_t>(b)], sim.q(), sim.v()).v.x();
  std::printf("cradle on the floor, the step of the blow (%d): %+.6f %+.6f %+.6f m/s\n", k + 1, v[0], v[1], v[2]);
  EXPECT_NEAR(v[2], 1.0, 0.01);
  EXPECT_LT(std::abs(v[0]), 0.01);
  EXPECT_LT(std::abs(v[1]), 0.01);
}

// The warm start is compared with a cold one: a box resting on the floor, then lifted (its velocity
// set to 0.2 m/s up, still within the margin): the last step's impulses, which carried its weight,
// would pull it down; they cost more than none, and are dropped. Resting again, they are kept.
TEST(ContactSolve, AWarmStartWorseThanColdIsDropped) {
  Simulation sim(sceneText("ground: true\nbodies: [{name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 2, "
                           "xyz: [0, 0, 0.1]}]\n"));
  test::ContactSolveProbe probe(sim);
  const ContactSolver& solver = probe.solver;
  const ContactSet& set = probe.set;
  const VectorX& v = probe.v;
  auto solveAt = [&](const VectorX& velocity) { probe.solve(sim.q(), velocity); };
  const VectorX rest = VectorX::Zero(sim.model().nv);
  for (int k = 0; k < 3; ++k) solveAt(rest);
  ASSERT_EQ(set.n, 4);
  EXPECT_EQ(solver.stats().warm_dropped, 0) << "resting: the warm start is the answer";
  double carried = 0.0;
  for (int k = 0; k < set.n; ++k) carried += set[k].impulse.z();
  EXPECT_NEAR(-carried, 2 * 9.81 * sim.scene().dt, 1e-9) << "the box's weight (impulses on the ground)";
  VectorX lifted = rest;
  lifted[2] = 0.2;  // its base's z velocity
  solveAt(lifted);
  ASSERT_EQ(set.n, 4);
  EXPECT_EQ(solver.stats().warm_dropped, 1) << "lifted: the weight's impulses would pull it back";
  EXPECT_EQ(solver.stats().iterations, 1) << "from zero, one sweep finds nothing to do";
  for (int k = 0; k < set.n; ++k) EXPECT_EQ(set[k].impulse.norm(), 0.0) << "it leaves: no impulse";
  EXPECT_NEAR(v[2], 0.2 - 9.81 * sim.scene().dt, 1e-12);
}

}  // namespace
}  // namespace igms
