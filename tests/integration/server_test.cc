// igms-server as a process on the LCM bus (udpm, private network namespace):
// the state stream arrives at 1 kHz, a push changes the trajectory, a pull
// drags the end-effector to the device point, bad messages are counted and
// ignored, SIGTERM stops it cleanly.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "channels.h"
#include "igms/command_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "core/simulation/simulation.h"
#include "tests/support/child_process.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

const int64_t kToken = 4242;

std::string url() { return std::string("udpm://239.255.76.67:") + std::getenv("IGMS_TEST_PORT") + "?ttl=0"; }

// Listens to state and status on a thread of its own.
class Listener {
 public:
  Listener() : bus_(url()) {
    bus_.subscribe(channels::kRobotState, &Listener::onState, this)->setQueueCapacity(5000);
    bus_.subscribe(channels::kServerStatus, &Listener::onStatus, this);
    thread_ = std::thread([this] {
      while (!stop_) bus_.handleTimeout(10);
    });
  }
  ~Listener() {
    stop_ = true;
    thread_.join();
  }
  void onState(const lcm::ReceiveBuffer*, const std::string&, const robot_state_t* m) {
    std::lock_guard<std::mutex> l(mutex);
    if (m->seq <= last.seq && count > 0) ++out_of_order;
    last = *m;
    ++count;
  }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const server_status_t* m) {
    std::lock_guard<std::mutex> l(mutex);
    status = *m;
    ++statuses;
    slip_angle_max = std::max(slip_angle_max, m->contact_slip_angle_max);
    linearised_angle_max = std::max(linearised_angle_max, m->contact_linearised_angle_max);
  }
  bool waitForStatus(int n, double seconds) {
    return waitUntil(seconds, [&] { return statuses >= n; });
  }
  // A status past this simulated time (the status's sim_time), within 8 s of wall time.
  bool waitForSimTime(double t) {
    return waitUntil(8.0, [&] { return status.sim_time > t; });
  }
  template <typename Done>
  bool waitUntil(double seconds, Done done) {
    for (int k = 0; k < seconds * 100; ++k) {
      {
        std::lock_guard<std::mutex> l(mutex);
        if (done()) return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  std::mutex mutex;
  robot_state_t last;
  server_status_t status;
  int count = 0, statuses = 0, out_of_order = 0;
  double slip_angle_max = 0.0;  // over every status received
  double linearised_angle_max = 0.0;

 private:
  lcm::LCM bus_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

ChildProcess startServerOn(const std::string& scene_path) {
  return ChildProcess({std::getenv("IGMS_SERVER_BIN"), "--scene", scene_path, "--lcm-url", url(), "--session-token",
                       std::to_string(kToken), "--quiet", "--output-dir", ::testing::TempDir()});
}

ChildProcess startServer(const std::string& scene) { return startServerOn(sourceDir() + "/scenes/" + scene); }

// A copy of a shipped scene in the test's folder, each `edits` pair's first text replaced by its second
// (a model's relative path made absolute, say).
std::string editedScene(const std::string& scene, const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = readFile(sourceDir() + "/scenes/" + scene);
  for (const auto& [from, to] : edits) {
    const size_t at = text.find(from);
    if (at == std::string::npos) ADD_FAILURE() << scene << " has no '" << from << "'";
    else text.replace(at, from.size(), to);
  }
  const std::string path = ::testing::TempDir() + "/edited_" + scene;
  std::ofstream(path) << text;
  return path;
}

haptic_input_t input(int64_t seq, int8_t mode, const Vector3& tip) {
  haptic_input_t m{};
  m.utime = seq;
  m.seq = seq;
  m.client_id = 1;
  m.session_token = kToken;
  m.mode = mode;
  for (int k = 0; k < 3; ++k) m.tip_position[k] = tip[k];
  m.tip_radius = 0.01;
  return m;
}

int linkIndex(const server_status_t& s, const std::string& name) {
  for (int k = 0; k < s.nlinks; ++k)
    if (s.link_names[k] == name) return k;
  return -1;
}

Vector3 linkPosition(const robot_state_t& s, int link) {
  return Vector3(s.link_poses[link][0], s.link_poses[link][1], s.link_poses[link][2]);
}

TEST(Server, StreamsStateAtOneKilohertzAndStopsOnSigterm) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(2, 10.0)) << "no status from the server";
  int before;
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    before = listener.count;
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));
  int after;
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    after = listener.count;
    EXPECT_EQ(listener.out_of_order, 0);
    EXPECT_EQ(listener.last.nq, 6);
    EXPECT_EQ(listener.last.nlinks, 8);
    EXPECT_GT(listener.status.rate_hz, 950.0);
    EXPECT_EQ(listener.status.contact_solves, 0) << "no contact in this scene";
  }
  const double rate = (after - before) / 2.0;
  EXPECT_GT(rate, 900.0) << "states per second received";
  EXPECT_LT(rate, 1100.0);
  EXPECT_EQ(server.stop(), 0) << "clean exit on SIGTERM";
}

// Issue 42: the contact solve's statistics reach the server's status. A pyramid of boxes has contacts
// at every step; every solve converges (the solver's tolerance is 1e-10 m/s).
TEST(Server, TheStatusCountsTheContactSolves) {
  Listener listener;
  ChildProcess server = startServer("box_pyramid.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  listener.waitForSimTime(2.0);
  std::lock_guard<std::mutex> l(listener.mutex);
  const server_status_t& st = listener.status;
  ASSERT_GT(st.sim_time, 2.0);
  EXPECT_GE(st.contact_solves, st.steps - 1) << "a solve every step";
  EXPECT_EQ(st.contact_unconverged, 0);
  EXPECT_EQ(st.contact_position_unconverged, 0);
  EXPECT_EQ(st.contact_candidates_dropped, 0) << "ten boxes are well within detection's buffers";
  EXPECT_EQ(st.proxy_substep_limited, 0) << "no hand";
  EXPECT_GE(st.contact_sweeps_max, 1);
  EXPECT_GE(st.contact_residual_max, 0.0);
  EXPECT_LE(st.contact_residual_max, 1e-10);
}

// A solve counted converged can keep a slipping friction the active set could not turn against its slip;
// the status says so. puma_table's first such answer comes at step 2440 (1.54 rad from opposing the
// slip), none before: the count and the angle reach the status, and read 0 until then.
TEST(Server, TheStatusCountsTheSlipsLeftUnturned) {
  Listener listener;
  ChildProcess server = startServer("puma_table.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  ASSERT_TRUE(listener.waitUntil(8.0, [&] { return listener.status.sim_time > 2.2; }));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    ASSERT_LT(listener.status.sim_time, 2.44) << "the status period is 0.1 s";
    EXPECT_GT(listener.status.contact_solves, 0);
    EXPECT_EQ(listener.status.contact_slips_unturned, 0);
    EXPECT_LT(listener.slip_angle_max, 1e-6);
  }
  ASSERT_TRUE(listener.waitUntil(8.0, [&] { return listener.status.sim_time > 2.6; }));
  std::lock_guard<std::mutex> l(listener.mutex);
  EXPECT_GE(listener.status.contact_slips_unturned, 1);
  EXPECT_GT(listener.slip_angle_max, 1.5);
  EXPECT_LE(listener.slip_angle_max, M_PI);
  EXPECT_EQ(listener.status.contact_unconverged, 0) << "26 in 8 s before the linearised cone";
}

// An island the active set could not settle even from the linearised cone's answers keeps the last
// polytope's answer; the status counts it. puma_table's default run has none since each of three
// polytopes' answers seeds the active set three ways (contact_active_set.cc); with box_a moved 111 nm
// along x (as scripts/bench/solve_ensemble.py moves it) the first comes at step 2438 (0.433 rad from
// opposing its slip), none before: the count and the angle reach the status, and read 0 until then.
TEST(Server, TheStatusCountsTheIslandsLeftOnThePolytope) {
  Listener listener;
  ChildProcess server = startServerOn(editedScene(
      "puma_table.yaml", {{"../models/puma560.urdf", sourceDir() + "/models/puma560.urdf"},
                          {"name: box_a, shape: box, size: [0.08, 0.08, 0.08], mass: 0.3, xyz: [0.42,",
                           "name: box_a, shape: box, size: [0.08, 0.08, 0.08], mass: 0.3, xyz: [0.420000111,"}}));
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  ASSERT_TRUE(listener.waitUntil(8.0, [&] { return listener.status.sim_time > 2.25; }));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    ASSERT_LT(listener.status.sim_time, 2.438) << "the status period is 0.1 s";
    EXPECT_GT(listener.status.contact_solves, 0);
    EXPECT_EQ(listener.status.contact_linearised, 0);
    EXPECT_EQ(listener.linearised_angle_max, 0.0);
  }
  ASSERT_TRUE(listener.waitUntil(8.0, [&] { return listener.status.sim_time > 2.6; }));
  std::lock_guard<std::mutex> l(listener.mutex);
  EXPECT_GE(listener.status.contact_linearised, 1);
  EXPECT_GT(listener.linearised_angle_max, 0.3) << "0.433 rad";
  EXPECT_LE(listener.linearised_angle_max, M_PI);
  EXPECT_EQ(listener.status.contact_unconverged, 0);
}

// The paper's nominal motion takes the PUMA's wrist (joint5) to 115 deg, past its URDF limit of 100 deg,
// from t = 2.33 s; its scenes keep the limits off (the paper modelled none), and the status says where the
// motion leaves the robot's range.
TEST(Server, TheStatusNamesTheJointsThatWentBeyondTheirLimits) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  listener.waitForSimTime(4.0);
  std::lock_guard<std::mutex> l(listener.mutex);
  const server_status_t& st = listener.status;
  ASSERT_GT(st.sim_time, 4.0);
  ASSERT_EQ(st.nlimited, 1);
  EXPECT_EQ(st.limited_joints[0], "joint5");
  EXPECT_NEAR(st.limit_excess[0], 2.0047 - 1.7453, 0.01) << "the wrist's farthest, beyond 100 deg";
  EXPECT_GT(st.limit_steps[0], 500);
}

TEST(Server, PushChangesTheTrajectoryAndPullDragsTheEndEffector) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  robot_state_t s;
  server_status_t status;
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    s = listener.last;
    status = listener.status;
  }
  // The same scene without input, in process: where the nominal run would be.
  Simulation nominal(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  const int link3 = linkIndex(status, "link3"), ee = linkIndex(status, "ee_link");
  ASSERT_GE(link3, 0);
  // Push: the tip sphere (1 cm) 4 mm into the top of link 3's collision cylinder (5 cm radius), for
  // 300 ms. A push engages at most 5 mm deep (proxy.h), and a push that touches nothing holds nothing.
  const SE3 cylinder = nominal.model().frame(nominal.model().frameIndex("link3")).collisions.at(0).placement;
  int64_t seq = 1;
  for (int k = 0; k < 300; ++k) {
    {
      std::lock_guard<std::mutex> l(listener.mutex);
      s = listener.last;
    }
    const double* x = s.link_poses[static_cast<size_t>(link3)].data();
    const SE3 link{Eigen::Quaterniond(x[3], x[4], x[5], x[6]).toRotationMatrix(), Vector3(x[0], x[1], x[2])};
    haptic_input_t m = input(seq++, haptic_input_t::MODE_PUSH, (link * cylinder).p + Vector3(0.0, 0.0, 0.056));
    m.contact_link = "link3";
    bus.publish(channels::kHapticInput, &m);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    s = listener.last;
  }
  while (nominal.time() < s.sim_time - 1e-9) nominal.step(nullptr);
  double diff = 0.0;
  for (int j = 0; j < 6; ++j) diff = std::max(diff, std::abs(s.q[j] - nominal.q()[j]));
  EXPECT_GT(diff, 0.01) << "the push moved the robot off its nominal trajectory";
  // Pull: hold the device 3 cm from the end-effector for 2 s.
  const Vector3 target = linkPosition(s, ee) + Vector3(0.0, 0.03, 0.02);
  for (int k = 0; k < 2000; ++k) {
    haptic_input_t m = input(seq++, haptic_input_t::MODE_PULL, target);
    bus.publish(channels::kHapticInput, &m);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    s = listener.last;
  }
  EXPECT_EQ(s.mode, haptic_input_t::MODE_PULL);
  EXPECT_LE((linkPosition(s, ee) - target).norm(), 5e-3) << "the end-effector follows the held device point";
  EXPECT_GT(s.input_seq, 0);
  EXPECT_EQ(server.stop(), 0);
}

TEST(Server, BadMessagesAreRejectedByReasonAndTheServerKeepsRunning) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  haptic_input_t nan_input = input(10, haptic_input_t::MODE_PUSH, Vector3(0.1, 0.1, 0.1));
  nan_input.tip_position[1] = NAN;
  haptic_input_t token = input(11, haptic_input_t::MODE_NONE, Vector3::Zero());
  token.session_token = 1;
  haptic_input_t link = input(12, haptic_input_t::MODE_PUSH, Vector3::Zero());
  link.contact_link = "no_such_link";
  haptic_input_t range = input(13, haptic_input_t::MODE_NONE, Vector3(1e6, 0, 0));
  haptic_input_t good = input(20, haptic_input_t::MODE_NONE, Vector3::Zero());
  haptic_input_t stale = input(19, haptic_input_t::MODE_NONE, Vector3::Zero());
  const uint8_t garbage[7] = {1, 2, 3, 4, 5, 6, 7};
  for (const haptic_input_t* m : {&nan_input, &token, &link, &range, &good, &stale}) {
    bus.publish(channels::kHapticInput, m);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  bus.publish(channels::kHapticInput, garbage, sizeof garbage);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  std::lock_guard<std::mutex> l(listener.mutex);
  const server_status_t& st = listener.status;
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_NONFINITE], 1);
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_TOKEN], 1);
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_UNKNOWN_LINK], 1);
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_RANGE], 1);
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_STALE], 1);
  EXPECT_EQ(st.rejected_by_reason[server_status_t::REJECT_UNDECODABLE], 1);
  EXPECT_EQ(st.inputs_rejected, 6);
  EXPECT_EQ(st.state, "running");
  EXPECT_EQ(st.commands_received, 0);
  EXPECT_TRUE(std::isfinite(listener.last.q[0]));
}

}  // namespace
}  // namespace igms::test

namespace igms::test {
namespace {

TEST(Server, UnknownAndUndecodableCommandsAreCountedAndChangeNothing) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  command_t unknown{};
  unknown.kind = 77;
  unknown.auth = std::to_string(kToken);
  bus.publish(channels::kCommand, &unknown);
  const uint8_t garbage[5] = {9, 8, 7, 6, 5};
  bus.publish(channels::kCommand, garbage, sizeof garbage);
  command_t gains{};
  gains.kind = command_t::SET_GAINS;
  gains.nvalues = 3;
  gains.values = {-1.0, 800.0, 10.0};  // a negative stiffness
  gains.auth = std::to_string(kToken);
  bus.publish(channels::kCommand, &gains);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  std::lock_guard<std::mutex> l(listener.mutex);
  EXPECT_EQ(listener.status.commands_received, 3);
  EXPECT_EQ(listener.status.commands_rejected, 3);
  EXPECT_EQ(listener.status.state, "running");
  EXPECT_NE(listener.status.message.find("SET_GAINS"), std::string::npos) << listener.status.message;
  EXPECT_TRUE(std::isfinite(listener.last.q[0]));
}

// LCM 1.3.1's decoders throw std::length_error on a string whose length
// field is 0: one such datagram used to abort the server (exit 134).
TEST(Server, ZeroLengthStringsOnInputAndCommandAreRejectedAndCounted) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  auto zeroString = [](auto msg, size_t length_offset) {
    std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    for (size_t k = 0; k < 4; ++k) buf[length_offset + k] = 0;  // the string's length field
    return buf;
  };
  // command_t: fingerprint 8, utime 8, seq 8, kind 1, then text's length.
  command_t c{};
  c.kind = command_t::SAVE_TRAJECTORY;
  c.text = "x";
  const auto bad_command = zeroString(c, 25);
  // haptic_input_t: ... tip_radius, buttons, then contact_link's length at byte 154.
  const auto bad_input = zeroString(input(30, haptic_input_t::MODE_NONE, Vector3::Zero()), 154);
  bus.publish(channels::kCommand, bad_command.data(), static_cast<unsigned>(bad_command.size()));
  bus.publish(channels::kHapticInput, bad_input.data(), static_cast<unsigned>(bad_input.size()));
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  EXPECT_TRUE(server.running()) << "the server survived both";
  std::lock_guard<std::mutex> l(listener.mutex);
  EXPECT_EQ(listener.status.commands_rejected, 1);
  EXPECT_EQ(listener.status.rejected_by_reason[server_status_t::REJECT_UNDECODABLE], 1);
  EXPECT_EQ(listener.status.state, "running");
}

TEST(Server, LockstepTakesOneStepPerInputAndRecordsItsSeq) {
  Listener listener;
  ChildProcess server({std::getenv("IGMS_SERVER_BIN"), "--scene", sourceDir() + "/scenes/puma_wall.yaml", "--lcm-url",
                       url(), "--session-token", std::to_string(kToken), "--clock", "lockstep", "--quiet"});
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  for (int64_t seq = 1; seq <= 50; ++seq) {
    haptic_input_t m = input(seq, haptic_input_t::MODE_NONE, Vector3::Zero());
    bus.publish(channels::kHapticInput, &m);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_EQ(listener.last.seq, 50) << "one step per input";
    EXPECT_EQ(listener.last.input_seq, 50);
    EXPECT_NEAR(listener.last.sim_time, 0.05, 1e-9);
    EXPECT_EQ(listener.status.state, "lockstep");
  }
  // The state after 50 steps is the in-process simulation's after 50 steps.
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  InteractionInput none;
  for (int k = 0; k < 50; ++k) sim.step(&none);
  std::lock_guard<std::mutex> l(listener.mutex);
  for (int j = 0; j < 6; ++j) EXPECT_EQ(listener.last.q[j], sim.q()[j]) << "bit-identical re-simulation";
}

TEST(Server, CommandsPauseStepResetAndSaveTheEditedTrajectory) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  // Each command is sent, then the test waits (up to 5 s) for the status that shows it took effect:
  // a fixed wait failed in CI when the status came later than 400 ms on a loaded machine.
  auto send = [&](int8_t kind, const std::string& text = "") {
    command_t c{};
    c.kind = kind;
    c.text = text;
    {
      std::lock_guard<std::mutex> l(listener.mutex);
      c.auth = std::to_string(listener.status.session_token);  // a reset changes it
    }
    bus.publish(channels::kCommand, &c);
  };
  auto statusesAfter = [&](int n) {
    int seen;
    {
      std::lock_guard<std::mutex> l(listener.mutex);
      seen = listener.statuses;
    }
    return listener.waitForStatus(seen + n, 5.0);
  };
  send(command_t::PAUSE);
  ASSERT_TRUE(listener.waitUntil(5.0, [&] { return listener.status.state == "paused"; })) << "PAUSE took no effect";
  int64_t paused_steps;
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    paused_steps = listener.status.steps;  // read after the state changed: final
  }
  ASSERT_TRUE(listener.waitUntil(5.0, [&] { return listener.last.seq == paused_steps; }))
      << "the last state published is the paused step's";
  ASSERT_TRUE(statusesAfter(3));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_EQ(listener.status.steps, paused_steps) << "paused: no steps";
    EXPECT_EQ(listener.last.seq, paused_steps) << "paused: no states";
    EXPECT_EQ(listener.status.state, "paused");
  }
  send(command_t::STEP);
  EXPECT_TRUE(listener.waitUntil(5.0, [&] { return listener.last.seq == paused_steps + 1; })) << "one step";
  ASSERT_TRUE(statusesAfter(3));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_EQ(listener.last.seq, paused_steps + 1) << "one step, no more";
    EXPECT_EQ(listener.status.steps, paused_steps + 1);
  }
  // A SET_TRAJECTORY that fails (one point) is rejected with a reason; the server stays paused.
  command_t bad{};
  bad.kind = command_t::SET_TRAJECTORY;
  bad.trajectory.npoints = 1;
  bad.trajectory.nq = 6;
  bad.trajectory.joint_names.assign(6, "q");
  bad.trajectory.t = {0.0};
  bad.trajectory.q = {std::vector<double>(6, 0.0)};
  bad.auth = std::to_string(kToken);
  bus.publish(channels::kCommand, &bad);
  EXPECT_TRUE(listener.waitUntil(5.0, [&] { return listener.status.commands_rejected == 1; }));
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_EQ(listener.status.state, "paused") << "a rejected command leaves the state alone";
    EXPECT_NE(listener.status.message.find("SET_TRAJECTORY"), std::string::npos) << listener.status.message;
  }
  const std::string path = ::testing::TempDir() + "/server_edited.yaml";
  std::remove(path.c_str());
  send(command_t::SAVE_TRAJECTORY, path);
  for (int k = 0; k < 500 && readFile(path).find("waypoints:") == std::string::npos; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_NE(readFile(path).find("waypoints:"), std::string::npos);
  std::remove(path.c_str());
  int64_t old_token;
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    old_token = listener.status.session_token;
  }
  send(command_t::RESET);
  EXPECT_TRUE(listener.waitUntil(5.0, [&] { return listener.status.session_token != old_token; }))
      << "a reset starts a new session";
  send(command_t::START);  // with the new session's token
  EXPECT_TRUE(listener.waitUntil(5.0, [&] { return listener.status.state == "running"; }));
  std::lock_guard<std::mutex> l(listener.mutex);
  EXPECT_LT(listener.last.sim_time, 0.5);
  EXPECT_EQ(listener.status.commands_rejected, 1) << "the START with the new token was accepted";
}

TEST(Server, CommandsNeedTheTokenAndStayInTheirFolders) {
  Listener listener;
  ChildProcess server = startServer("puma_wall.yaml");
  ASSERT_TRUE(listener.waitForStatus(1, 10.0));
  lcm::LCM bus(url());
  auto send = [&](int8_t kind, const std::string& auth, const std::string& text, const std::string& expect) {
    command_t c{};
    c.kind = kind;
    c.text = text;
    c.auth = auth;
    bus.publish(channels::kCommand, &c);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_NE(listener.status.message.find(expect), std::string::npos) << listener.status.message;
    EXPECT_EQ(listener.status.state, "running") << "nothing a refused command asked for happened";
  };
  const std::string token = std::to_string(kToken);
  send(command_t::SHUTDOWN, "", "", "not authorized");
  send(command_t::RESET, token + "0", "", "not authorized");
  send(command_t::PAUSE, "123", "", "not authorized");
  send(command_t::SAVE_TRAJECTORY, token, "../escaped.yaml", "not in the output folder");
  send(command_t::SAVE_TRAJECTORY, token, "/etc/igms_escaped.yaml", "not in the output folder");
  send(command_t::LOAD_SCENE, token, "/etc/passwd", "not a scene file in a scene folder");
  send(command_t::LOAD_SCENE, token, "../../../../etc/hostname", "not a scene file in a scene folder");
  {
    std::lock_guard<std::mutex> l(listener.mutex);
    EXPECT_EQ(listener.status.commands_rejected, 7);
  }
  EXPECT_TRUE(server.running());
  // With the token, inside the output folder: done.
  command_t save{};
  save.kind = command_t::SAVE_TRAJECTORY;
  save.text = "inside_output_dir.yaml";
  save.auth = token;
  bus.publish(channels::kCommand, &save);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::string saved = ::testing::TempDir() + "/inside_output_dir.yaml";
  EXPECT_NE(readFile(saved).find("waypoints:"), std::string::npos);
  std::remove(saved.c_str());
}

}  // namespace
}  // namespace igms::test
