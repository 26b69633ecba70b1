// The client's logic on synthetic replies: each fallback policy when replies
// are late or lost, late and out-of-order replies discarded by seq, the
// start-up guard, the server-lost ramp, the resync blend, the scripted device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "haptic_client/device/scripted_device.h"
#include "haptic_client/servo/force_render.h"
#include "haptic_client/servo/servo_record.h"
#include "haptic_client/servo/servo_stats.h"
#include "haptic_client/servo/state_estimate.h"

namespace igms {
namespace {

// One link moving along x at 1 m/s: the state for sim time t.
RobotSample sample(int64_t seq, double t) {
  RobotSample s;
  s.seq = seq;
  s.input_seq = seq;
  s.sim_time = t;
  s.links.assign(1, SE3::Identity());
  s.links[0].p = Vector3(t, 0, 0);
  s.links[0].R = Eigen::AngleAxisd(2.0 * t, Vector3::UnitZ()).toRotationMatrix();  // 2 rad/s
  s.q.assign(1, t);
  return s;
}

double x(const std::vector<SE3>& l) { return l[0].p.x(); }

TEST(StateEstimate, HoldKeepsTheNewestStateWhenTheReplyIsLate) {
  StateEstimate e(1, 1, FallbackPolicy::Hold);
  std::vector<SE3> links(1);
  bool fallback = true;
  EXPECT_FALSE(e.estimate(0.0, links, &fallback)) << "nothing before the first state";
  e.offer(sample(1, 0.001));
  e.offer(sample(2, 0.002));
  ASSERT_TRUE(e.estimate(0.002, links, &fallback));
  EXPECT_FALSE(fallback);
  EXPECT_DOUBLE_EQ(x(links), 0.002);
  ASSERT_TRUE(e.estimate(0.005, links, &fallback));  // three replies lost
  EXPECT_TRUE(fallback);
  EXPECT_DOUBLE_EQ(x(links), 0.002);
}

TEST(StateEstimate, ExtrapolateContinuesAtConstantVelocityAndIsBounded) {
  StateEstimate e(1, 1, FallbackPolicy::Extrapolate);
  std::vector<SE3> links(1);
  bool fallback = false;
  e.offer(sample(1, 0.001));
  e.offer(sample(2, 0.002));
  ASSERT_TRUE(e.estimate(0.004, links, &fallback));
  EXPECT_TRUE(fallback);
  EXPECT_NEAR(x(links), 0.004, 1e-12);
  const Eigen::AngleAxisd r(links[0].R);
  EXPECT_NEAR(r.angle(), 0.008, 1e-9) << "orientation extrapolated too";
  ASSERT_TRUE(e.estimate(1.0, links, &fallback));  // a long outage: at most 10 periods ahead
  EXPECT_NEAR(x(links), 0.012, 1e-12);
}

TEST(StateEstimate, InterpolateRunsOnePeriodBehind) {
  StateEstimate e(1, 1, FallbackPolicy::Interpolate);
  std::vector<SE3> links(1);
  bool fallback = false;
  e.offer(sample(1, 0.001));
  e.offer(sample(2, 0.002));
  ASSERT_TRUE(e.estimate(0.002, links, &fallback));
  EXPECT_FALSE(fallback);
  EXPECT_NEAR(x(links), 0.001, 1e-12) << "one period behind even on time";
  ASSERT_TRUE(e.estimate(0.0025, links, &fallback));
  EXPECT_NEAR(x(links), 0.0015, 1e-12) << "between the last two";
  ASSERT_TRUE(e.estimate(0.010, links, &fallback));
  EXPECT_NEAR(x(links), 0.002, 1e-12) << "never beyond the newest";
}

TEST(StateEstimate, LateAndOutOfOrderRepliesAreDiscardedBySeq) {
  StateEstimate e(1, 1, FallbackPolicy::Hold);
  EXPECT_TRUE(e.offer(sample(5, 0.005)));
  EXPECT_FALSE(e.offer(sample(4, 0.004)));
  EXPECT_FALSE(e.offer(sample(5, 0.005)));
  EXPECT_EQ(e.newest().seq, 5);
  EXPECT_TRUE(e.offer(sample(7, 0.007)));
}

TEST(ForceRender, StartupGuardHoldsForcesOffUntilTheyAreFirstSmall) {
  StartupGuard g(0.5);
  EXPECT_EQ(g.apply(Vector3(5, 0, 0)), Vector3::Zero()) << "starting inside a link: no spike";
  EXPECT_EQ(g.apply(Vector3(3, 0, 0)), Vector3::Zero());
  EXPECT_EQ(g.apply(Vector3(0.1, 0, 0)), Vector3(0.1, 0, 0));
  EXPECT_EQ(g.apply(Vector3(5, 0, 0)), Vector3(5, 0, 0)) << "armed for good";
}

TEST(ForceRender, LossRampGoesDownAndUpWithoutSteps) {
  LossRamp r(0.1);
  double last = r.scale(), worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    const double s = r.update(k >= 20 && k < 150, 1e-3);
    worst = std::max(worst, std::abs(s - last));
    last = s;
    if (k == 130) {
      EXPECT_EQ(s, 0.0) << "fully down while lost";
    }
  }
  EXPECT_DOUBLE_EQ(last, 1.0) << "back up after the server returns";
  EXPECT_LE(worst, 0.0100001) << "1 % per millisecond at most";
}

TEST(ForceRender, ResyncBlendSpreadsAJumpOverItsCycles) {
  ResyncBlend b;
  Vector3 last(0, 0, 0);
  b.resync(10);
  double worst = 0.0;
  for (int k = 0; k < 12; ++k) {
    const Vector3 f = b.apply(Vector3(2, 0, 0), last);
    worst = std::max(worst, (f - last).norm());
    last = f;
  }
  EXPECT_NEAR(last.x(), 2.0, 1e-12);
  EXPECT_LE(worst, 0.2 + 1e-12);
}

std::string writeScript(const std::string& text) {
  const std::string path = ::testing::TempDir() + "/script.yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(ScriptedDevice, FollowsWaypointsSmoothlyAndPressesButtons) {
  const std::string path = writeScript(
      "frame: scene\nwaypoints:\n  - {t: 0.0, xyz: [1, 0, 0]}\n  - {t: 1.0, xyz: [2, 0, 0]}\n"
      "buttons:\n  - {t: 0.5, down: true}\nend: 1.5\n");
  ScriptedDevice d(path, WorkspaceMap{2.0, Vector3(1, 0, 0)}, nullptr);
  EXPECT_NEAR(d.read(0.0).position.x(), 0.0, 1e-12);  // scene 1 = offset: device 0
  const DeviceReading mid = d.read(0.5);
  EXPECT_NEAR(mid.position.x(), 0.25, 1e-12);  // halfway in the scene (1.5) is 0.25 on the device
  EXPECT_EQ(mid.buttons, 1);
  EXPECT_NEAR(d.read(1.0).position.x(), 0.5, 1e-12);
  EXPECT_FALSE(d.finished(1.2));
  EXPECT_TRUE(d.finished(1.5));
}

// A press may name what it pulls (a link or a free body); a name the scene lacks is an error naming the file.
TEST(ScriptedDevice, APressNamesTheBodyItPulls) {
  const auto frames = [](const std::string& name) { return name == "ball" ? 7 : -1; };
  const std::string path = writeScript(
      "frame: scene\nwaypoints:\n  - {t: 0.0, xyz: [0, 0, 0]}\n"
      "buttons:\n  - {t: 0.5, down: true, attach: ball, point: [0, 0, 0.04]}\n  - {t: 1.0, down: false}\n"
      "  - {t: 1.5, down: true}\nend: 2\n");
  ScriptedDevice d(path, WorkspaceMap{1.0, Vector3::Zero()}, nullptr, frames);
  EXPECT_EQ(d.read(0.2).attach_frame, -1);
  const DeviceReading held = d.read(0.7);
  EXPECT_EQ(held.buttons, 1);
  EXPECT_EQ(held.attach_frame, 7);
  EXPECT_NEAR(held.attach_point.z(), 0.04, 1e-15);
  EXPECT_EQ(d.read(1.2).attach_frame, -1) << "released";
  EXPECT_EQ(d.read(1.7).attach_frame, -1) << "a press without attach: the scene's pull link";
  const std::string bad = writeScript(
      "frame: scene\nwaypoints:\n  - {t: 0.0, xyz: [0, 0, 0]}\nbuttons:\n  - {t: 0.5, down: true, attach: cup}\n");
  try {
    ScriptedDevice b(bad, WorkspaceMap{1.0, Vector3::Zero()}, nullptr, frames);
    ADD_FAILURE() << "an unknown body was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no link or free body 'cup'"), std::string::npos) << e.what();
  }
}

TEST(ScriptedDevice, OrientationWaypointsMakeASixDofDevice) {
  const std::string path = writeScript(
      "frame: scene\nwaypoints:\n  - {t: 0.0, xyz: [0, 0, 0], rpy: [0, 0, 0]}\n"
      "  - {t: 1.0, xyz: [0, 0, 0], rpy: [0, 0, 0.4]}\n  - {t: 2.0, xyz: [0, 0, 0]}\nmax_torque: 0.8\nend: 2\n");
  ScriptedDevice d(path, WorkspaceMap{1.0, Vector3::Zero()}, nullptr);
  EXPECT_NEAR(d.limits().max_torque, 0.8, 1e-12);
  const DeviceReading start = d.read(0.0);
  EXPECT_TRUE(start.has_orientation);
  d.read(0.499);
  const DeviceReading mid = d.read(0.5);
  // Halfway in time is halfway in angle (the smooth blend is symmetric), about z.
  const Eigen::AngleAxisd a(mid.orientation);
  EXPECT_NEAR(a.angle(), 0.2, 1e-9);
  EXPECT_NEAR(std::abs(a.axis().z()), 1.0, 1e-9);
  // Its angular velocity is the blend's slope: 0.4 rad * 1.5 / s at the middle, about +z.
  EXPECT_NEAR(mid.angular_velocity.z(), 0.6, 2e-3);
  EXPECT_NEAR(Eigen::AngleAxisd(d.read(1.5).orientation).angle(), 0.4, 1e-9) << "a waypoint without rpy keeps it";
  // Without rpy anywhere the device is 3-dof.
  ScriptedDevice plain(writeScript("frame: scene\nwaypoints:\n  - {t: 0.0, xyz: [0, 0, 0]}\nend: 1\n"),
                       WorkspaceMap{1.0, Vector3::Zero()}, nullptr);
  EXPECT_FALSE(plain.read(0.0).has_orientation);
  EXPECT_EQ(plain.limits().max_torque, 0.0);
}

TEST(ScriptedDevice, SimulatedHandFeelsTheRenderedForce) {
  const std::string path = writeScript(
      "frame: device\nhand: {mass: 0.3, k: 400, b: 25}\nwaypoints:\n  - {t: 0.0, xyz: [0, 0, 0]}\n"
      "  - {t: 1.0, xyz: [0, 0, 0]}\n");
  ScriptedDevice free_hand(path, WorkspaceMap{}, nullptr), pushed(path, WorkspaceMap{}, nullptr);
  for (int k = 0; k <= 1000; ++k) {
    free_hand.read(k * 1e-3);
    pushed.write(Vector3(2.0, 0, 0));  // the rendered force pushes the hand
    pushed.read(k * 1e-3);
  }
  EXPECT_NEAR(free_hand.read(1.0).position.x(), 0.0, 1e-12);
  EXPECT_NEAR(pushed.read(1.0).position.x(), 2.0 / 400.0, 2e-4) << "the hand gives way by F / k";
}

// A link-relative waypoint is read where the link is when the script starts toward it; one that repeats
// the waypoint before it (same link, point, offset) is a hold and stays where that one was, however far the
// link has moved since. Before the rule the hold was re-read from the moved link, and a 15 cm pull became 30.
TEST(ScriptedDevice, ARepeatedLinkWaypointHoldsWhereTheOneBeforeIt) {
  const std::string path = writeScript(
      "frame: scene\nwaypoints:\n  - {t: 0.0, link: arm, offset: [0, 0, 0]}\n"
      "  - {t: 1.0, link: arm, offset: [0.15, 0, 0]}\n  - {t: 2.0, link: arm, offset: [0.15, 0, 0]}\n"
      "  - {t: 3.0, link: arm, offset: [0.15, 0, 0.1]}\nend: 3.0\n");
  double link_x = 0.0;  // the link follows the device (a pull drags it): wherever it was last told
  ScriptedDevice d(path, WorkspaceMap{}, [&](const std::string& name, SE3* X) {
    if (name != "arm") return false;
    *X = SE3::Identity();
    X->p = Vector3(link_x, 0, 0);
    return true;
  });
  for (int k = 0; k <= 2000; ++k) {
    const DeviceReading r = d.read(k * 1e-3);
    link_x = r.position.x() - 0.01;  // 1 cm behind the hand
  }
  EXPECT_NEAR(d.read(2.0).position.x(), 0.15, 1e-9) << "held at the 15 cm the script says, not 30";
  // The next waypoint is not a repeat: it is read from the link where it is now (0.14 m), plus its offset.
  for (int k = 2001; k <= 3000; ++k) d.read(k * 1e-3);
  EXPECT_NEAR(d.read(3.0).position.x(), 0.14 + 0.15, 1e-9);
  EXPECT_NEAR(d.read(3.0).position.z(), 0.1, 1e-9);
}

// haptic_truth checks the slew limit's largest step (1 N) from the record's CSV, between forces near
// 10 N: nine digits gave 1.00000003 N for a step of exactly 1 N. The record must round-trip.
TEST(ServoRecord, ItsCsvGivesBackEveryForceBitForBit) {
  ServoRecord record(2);
  ServoRecordRow a, b;
  a.rendered = Vector3(1e-15, -0.1, -10.1779044703917);
  b.rendered = a.rendered + Vector3(0.0, 0.0, 1.0);
  b.t = 0.001;
  record.add(a);
  record.add(b);
  const std::string path = ::testing::TempDir() + "servo_record_test.csv";
  std::string error;
  ASSERT_TRUE(record.write(path, &error)) << error;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // the header
  for (const ServoRecordRow& row : {a, b}) {
    ASSERT_TRUE(std::getline(in, line));
    double v[15];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1],
                          &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &v[9], &v[10], &v[11], &v[12], &v[13],
                          &v[14]),
              15);
    EXPECT_EQ(Vector3(v[12], v[13], v[14]), row.rendered);
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace igms

TEST(Histogram, ReportsOverflowAsOverflowNotAsTheLastBin) {
  igms::Histogram h(10.0);  // 10 us bins: 200 ms
  for (int i = 0; i < 98; ++i) h.add(100.0);
  h.add(250'000.0);  // 250 ms: beyond the range
  h.add(1'000'000.0);
  EXPECT_EQ(h.count(), 100);
  EXPECT_EQ(h.overflow(), 2);
  EXPECT_DOUBLE_EQ(h.percentile(0.5), 100.0);
  EXPECT_TRUE(std::isinf(h.percentile(0.99)));  // the 99th of 100 samples lies in the overflow
  EXPECT_DOUBLE_EQ(h.max(), 1'000'000.0);       // exact, not 199 990 us
  EXPECT_EQ(igms::quantileText(h, 0.99, 1e-3), "> 200");
  EXPECT_EQ(igms::quantileText(h, 0.5), "100");
  igms::Histogram empty;
  EXPECT_EQ(empty.percentile(0.5), 0.0);
}
