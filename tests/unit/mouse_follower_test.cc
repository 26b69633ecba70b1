// The web device's tip follows 60 Hz mouse targets at 1 kHz with bounded
// steps: the push force against a surface (k_p times the penetration)
// changes by at most k_p * kMaxSpeed * dt per cycle, a drag starts with a
// jump, a released push backs out until nothing pushes back, then parks.
#include <gtest/gtest.h>

#include "haptic_client/device/mouse_follower.h"

namespace {

using igms::MouseFollower;
using igms::Vector3;

constexpr double kDt = 0.001;
constexpr double kKp = 2000.0;  // scenes/puma_obstacle.yaml's push stiffness

// A floor at z = 0 pushing back on a tip sphere of radius 1 cm.
Vector3 floorForce(const Vector3& tip) {
  const double depth = 0.01 - tip.z();
  return Vector3(0, 0, depth > 0 ? kKp * depth : 0.0);
}

TEST(MouseFollower, DragStartsWithAJumpAndFollowsInBoundedSteps) {
  const Vector3 parked(0, 0, 1.5);
  MouseFollower f(parked);
  MouseFollower::Target t;
  EXPECT_EQ(f.update(t, kDt, Vector3::Zero()), parked);
  EXPECT_TRUE(f.parked());
  t.active = true;
  t.seq = t.drag_seq = 1;
  t.tip = t.drag_start = Vector3(0.1, 0, 0.03);
  EXPECT_EQ(f.update(t, kDt, Vector3::Zero()), t.tip);  // the picked point, at once
  // A fast mouse: 1.5 cm steps at 60 Hz toward and into the floor (0.9 m/s).
  Vector3 last = f.position(), last_v = f.velocity(), last_force = floorForce(last);
  double worst_step = 0, worst_dv = 0, worst_force_step = 0;
  for (int cycle = 0; cycle < 2500; ++cycle) {
    if (cycle % 16 == 0 && cycle < 320) {
      ++t.seq;
      t.tip += Vector3(0.015, 0, -0.0025);
    }
    const Vector3 x = f.update(t, kDt, last_force);
    worst_step = std::max(worst_step, (x - last).norm());
    worst_dv = std::max(worst_dv, (f.velocity() - last_v).norm());
    const Vector3 force = floorForce(x);
    worst_force_step = std::max(worst_force_step, (force - last_force).norm());
    last = x;
    last_v = f.velocity();
    last_force = force;
  }
  EXPECT_LE(worst_step, MouseFollower::kMaxSpeed * kDt + 1e-12);
  EXPECT_LE(worst_dv, MouseFollower::kMaxAccel * kDt + 1e-12);
  EXPECT_LE(worst_force_step, 0.5 + 1e-9) << "k_p * kMaxSpeed * dt";
  EXPECT_GT(last_force.z(), 10.0) << "the tip did press into the floor";
  EXPECT_LT((f.position() - t.tip).norm(), 1e-3) << "and settled on the target";
}

TEST(MouseFollower, AReleasedPushBacksOutUntilNothingPushesThenParks) {
  const Vector3 parked(0, 0, 1.5);
  MouseFollower f(parked);
  MouseFollower::Target t;
  t.active = true;
  t.seq = t.drag_seq = 1;
  t.tip = t.drag_start = Vector3(0, 0, 0.02);  // touching the floor from above
  f.update(t, kDt, Vector3::Zero());
  t.seq = 2;
  t.tip = Vector3(0, 0, -0.01);  // 2 cm in
  Vector3 force = Vector3::Zero();
  for (int i = 0; i < 500; ++i) force = floorForce(f.update(t, kDt, force));
  ASSERT_NEAR(force.z(), 40.0, 0.5);
  t.active = false;
  t.seq = 3;
  double worst = 0;
  int cycles = 0;
  while (!f.parked() && cycles < 2000) {
    const Vector3 next = floorForce(f.update(t, kDt, force));
    if (!f.parked()) worst = std::max(worst, (next - force).norm());
    force = next;
    ++cycles;
  }
  EXPECT_TRUE(f.parked());
  EXPECT_EQ(f.position(), parked);
  EXPECT_LE(worst, 0.5 + 1e-9) << "the force faded while backing out";
  EXPECT_LT(cycles, 300) << "backing out 2 cm takes about 0.1 s";
}

TEST(MouseFollower, AReleasedPullParksAtOnce) {
  const Vector3 parked(0, 0, 1.5);
  MouseFollower f(parked);
  MouseFollower::Target t;
  t.active = t.pull = true;
  t.seq = t.drag_seq = 1;
  t.tip = t.drag_start = Vector3(0.3, 0.2, 0.4);
  f.update(t, kDt, Vector3::Zero());
  t.active = false;
  t.seq = 2;
  EXPECT_EQ(f.update(t, kDt, Vector3(1, 0, 0)), parked);  // the client blends the spring off
}

// A busy machine hands the loop the drag's second target before it saw the first (the jump): the
// tip still starts at the picked point, not on its way down from the parked place. (CI's browser
// push came down on the box's top from 1.5 m above and moved it 1-2 cm.)
TEST(MouseFollower, ADragStartsAtItsJumpWhenTheLoopSawOnlyALaterTarget) {
  const Vector3 parked(0, 0, 1.5);
  MouseFollower f(parked);
  MouseFollower::Target t;
  f.update(t, kDt, Vector3::Zero());
  t.active = true;
  t.drag_seq = 7;
  t.drag_start = Vector3(0.1, 0, 0.03);  // the jump, seq 7, never read by the loop
  t.seq = 8;
  t.tip = Vector3(0.1, 0.004, 0.03);     // the target after it
  const Vector3 x = f.update(t, kDt, Vector3::Zero());
  EXPECT_LT((x - t.drag_start).norm(), MouseFollower::kMaxSpeed * kDt + 1e-12);
  // The same drag's later targets do not jump again.
  for (int i = 0; i < 100; ++i) {
    ++t.seq;
    t.tip += Vector3(0, 0, -0.001);
    const Vector3 last = f.position();
    EXPECT_LE((f.update(t, kDt, Vector3::Zero()) - last).norm(), MouseFollower::kMaxSpeed * kDt + 1e-12);
  }
  // A new drag starts at its own jump.
  t.drag_seq = t.seq + 1;
  t.seq += 2;
  t.drag_start = t.tip = Vector3(-0.2, 0.1, 0.3);
  EXPECT_EQ(f.update(t, kDt, Vector3::Zero()), t.drag_start);
}

}  // namespace
