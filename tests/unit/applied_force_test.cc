// Issue 43, item 1: the force a step reports is the force it applied. A body
// on a frictionless floor, pushed sideways by a tip, changes its horizontal
// momentum by exactly the applied push over the step (the floor's impulses
// are vertical), so m (v+ - v) / h is an independent measure of what the step
// applied. The tip starts at the body's surface and accelerates at 1 m/s^2,
// so the push lasts (a tip at constant speed would knock the body away: no
// friction holds it back) and covers 5 cm/s to 1.5 m/s. The linearly-implicit
// step takes the push spring at the end of the step; the step had reported
// its value at the start, off by k_p h times the approach speed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

struct Case {
  const char* body;  // its YAML
  double half;       // its half-width along x
  double y;          // the tip's offset from the centre (a ball's push points at its centre: none)
};

// The largest |reported - applied| over the push (x and y), and where.
struct Measured {
  double worst = 0.0, worst_speed = 0.0, max_push = 0.0, max_speed = 0.0;
  int steps = 0;
};

// A free body's velocity coordinates are its body frame's: its centre's world velocity is R v.
Vector3 worldVelocity(const Simulation& sim, int body_v) {
  const int iq = static_cast<int>(sim.model().nq) - 7;
  const Eigen::Quaterniond r(sim.q()[iq + 3], sim.q()[iq + 4], sim.q()[iq + 5], sim.q()[iq + 6]);
  return r.normalized() * Vector3(sim.v().segment<3>(body_v));
}

Measured push(const Case& c, bool pull = false) {
  const std::string yaml = std::string("ground: {height: 0, material: ice}\n"
                                       "materials: {ice: {friction: 0.0}}\n"
                                       "bodies:\n  - ") +
                           c.body +
                           "\ninteraction:\n  push: {k_p: 3000, max_force: 100, tip_radius: 0.01}\n"
                           "  pull: {k: 800, b: 20, max_force: 100, max_stretch: 0.5}\n"
                           "simulation: {integrator: linearly_implicit, dt: 0.001, rate_hz: 1000}\n";
  Simulation sim(parseScene(yaml, "push.yaml", test::sourceDir() + "/scenes"));
  const double h = 0.001, m = 1.0, a = 1.0;
  const int body = static_cast<int>(sim.model().nv) - 6;  // the one free body: v[body..body+2] linear
  InteractionInput in;
  in.mode = pull ? InteractionMode::Pull : InteractionMode::Push;
  in.tip_radius = 0.01;
  in.client = 1;
  if (pull) {  // grabbed at a point off its centre: the spring-damper turns it too
    in.attach_frame = static_cast<int>(sim.model().frames.size()) - 1;
    in.attach_point = Vector3(0.03, 0.02, 0.0);
  }
  Measured out;
  for (int k = 0; k < 1500; ++k) {
    const double t = h * k;
    in.tip_position = pull ? Vector3(0.5 * a * t * t + 0.02, 0.01 * std::sin(10 * t), 0.1)
                           : Vector3(-c.half - in.tip_radius + 0.5 * a * t * t, c.y, 0.1);
    in.tip_velocity = Vector3(a * t, 0, 0);
    in.seq = k + 1;
    const Vector3 p0 = worldVelocity(sim, body);
    if (!sim.step(&in)) ADD_FAILURE() << "diverged";
    const Vector3 reported = sim.outcome().force_on_robot;
    const Vector3 applied = m * (worldVelocity(sim, body) - p0) / h;
    const double error = std::max(std::abs(reported.x() - applied.x()), std::abs(reported.y() - applied.y()));
    if (reported.norm() > 0.0) ++out.steps;
    if (error > out.worst) {
      out.worst = error;
      out.worst_speed = a * t;
    }
    out.max_push = std::max(out.max_push, reported.x());
    out.max_speed = std::max(out.max_speed, sim.v()[body]);
  }
  return out;
}

const Case kBox{"{name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1.0, xyz: [0, 0, 0.1], material: ice}", 0.1, 0.01};
const Case kBall{"{name: ball, shape: sphere, radius: 0.1, mass: 1.0, xyz: [0, 0, 0.1], material: ice}", 0.1, 0.0};

TEST(AppliedForce, TheReportedPushIsTheOneTheStepApplied) {
  for (const Case* c : {&kBox, &kBall}) {
    const char* name = c == &kBox ? "box" : "ball";
    const Measured r = push(*c);
    std::printf("%s: pushed in %d steps up to %.2f m/s, largest push %.3f N, |reported - m dv/h| <= %.3g N "
                "(at tip speed %.3f m/s)\n",
                name, r.steps, r.max_speed, r.max_push, r.worst, r.worst_speed);
    EXPECT_GT(r.steps, 1200) << name << ": the push lasts";
    EXPECT_GT(r.max_speed, 1.0) << name;
    EXPECT_LE(r.worst, 1e-9) << name;
  }
}

// The pull's spring-damper (eq. 4) on a ball grabbed off its centre: its damping is taken at the end of
// the step too, and reported as applied.
TEST(AppliedForce, TheReportedPullIsTheOneTheStepApplied) {
  const Measured r = push(kBall, /*pull=*/true);
  std::printf("pulled ball: %d steps up to %.2f m/s, largest pull %.3f N, |reported - m dv/h| <= %.3g N\n", r.steps,
              r.max_speed, r.max_push, r.worst);
  EXPECT_GT(r.steps, 1400);
  EXPECT_LE(r.worst, 1e-9);
}

}  // namespace
}  // namespace igms
