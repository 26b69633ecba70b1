// igms-server (lockstep) + igms-haptic (scripted device) as two processes on
// udpm inside the private namespace: a push moves the touched link away, a
// pull brings the end-effector to the held point, and under lost, bursty and
// stalled replies the client keeps its rate with a continuous force.
#include <gtest/gtest.h>

#include <signal.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <thread>

#include "channels.h"
#include "igms/client_status_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "core/simulation/simulation.h"
#include "tests/support/child_process.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

std::string url() { return std::string("udpm://239.255.76.67:") + std::getenv("IGMS_TEST_PORT") + "?ttl=0"; }

// The largest single step of the rendered force we accept, N. The loss-free
// push demo's largest step is about 0.3 N.
constexpr double kMaxForceStep = 1.0;

struct Session {
  std::vector<robot_state_t> states;
  client_status_t last_status;
  bool saw_server_lost = false;
  double min_force_scale = 1.0;
  int client_exit = -1;
};

class Recorder {
 public:
  Recorder() : bus_(url()) {
    bus_.subscribe(channels::kRobotState, &Recorder::onState, this)->setQueueCapacity(10000);
    bus_.subscribe(channels::kClientStatus, &Recorder::onStatus, this);
    thread_ = std::thread([this] {
      while (!stop_) bus_.handleTimeout(10);
    });
  }
  ~Recorder() {
    stop_ = true;
    thread_.join();
  }
  void onState(const lcm::ReceiveBuffer*, const std::string&, const robot_state_t* m) {
    std::lock_guard<std::mutex> l(mutex);
    session.states.push_back(*m);
    const double f2 = m->interaction_force[0] * m->interaction_force[0] +
                      m->interaction_force[1] * m->interaction_force[1] +
                      m->interaction_force[2] * m->interaction_force[2];
    if (m->mode != 0 && f2 > 4.0) in_contact = true;  // pushing or pulling with more than 2 N
  }
  std::atomic<bool> in_contact{false};
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const client_status_t* m) {
    std::lock_guard<std::mutex> l(mutex);
    session.last_status = *m;
    session.saw_server_lost |= m->state == "server_lost";
    session.min_force_scale = std::min(session.min_force_scale, m->force_scale);
  }
  std::mutex mutex;
  Session session;

 private:
  lcm::LCM bus_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

enum class Disturbance { None, StallServer, StallInContact, PoisonStatus };

// A server_status_t whose first string's length field is 0: LCM 1.3.1's decoder throws on it.
std::vector<uint8_t> poisonedStatus() {
  server_status_t st{};
  st.scene = "x";
  std::vector<uint8_t> buf(static_cast<size_t>(st.getEncodedSize()));
  st.encode(buf.data(), 0, static_cast<int>(buf.size()));
  for (size_t k = 32; k < 36; ++k) buf[k] = 0;  // fingerprint, utime, seq, session_token: then scene's length
  return buf;
}

Session run(const std::string& script, std::vector<std::string> server_extra = {},
            Disturbance disturbance = Disturbance::None, const char* clock = "lockstep", int stall_at_ms = 1500,
            const std::string& scene = "puma_wall.yaml") {
  Recorder recorder;
  std::vector<std::string> server_args{std::getenv("IGMS_SERVER_BIN"), "--scene", sourceDir() + "/scenes/" + scene,
                                       "--lcm-url", url(), "--clock", clock, "--quiet"};
  server_args.insert(server_args.end(), server_extra.begin(), server_extra.end());
  ChildProcess server(server_args);
  ChildProcess client({std::getenv("IGMS_CLIENT_BIN"), "--scene", sourceDir() + "/scenes/" + scene, "--device",
                       "scripted:" + sourceDir() + "/scenes/" + script, "--lcm-url", url(), "--quiet"});
  if (disturbance == Disturbance::StallInContact) {
    for (int k = 0; k < 1000 && !recorder.in_contact; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(stall_at_ms));
    kill(server.pid(), SIGSTOP);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(server.pid(), SIGCONT);
  } else if (disturbance == Disturbance::StallServer) {
    std::this_thread::sleep_for(std::chrono::milliseconds(stall_at_ms));
    kill(server.pid(), SIGSTOP);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(server.pid(), SIGCONT);
  } else if (disturbance == Disturbance::PoisonStatus) {
    lcm::LCM bus(url());
    const std::vector<uint8_t> poison = poisonedStatus();
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    for (int k = 0; k < 3; ++k) bus.publish(channels::kServerStatus, poison.data(), static_cast<unsigned>(poison.size()));
  }
  Session out;
  out.client_exit = client.wait(std::chrono::seconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  server.stop();
  std::lock_guard<std::mutex> l(recorder.mutex);
  out.states = recorder.session.states;
  out.last_status = recorder.session.last_status;
  out.saw_server_lost = recorder.session.saw_server_lost;
  out.min_force_scale = recorder.session.min_force_scale;
  return out;
}

double maxForce(const Session& s, int8_t mode, double from = -1.0, double to = 1e9) {
  double m = 0.0;
  for (const auto& st : s.states)
    if (st.mode == mode && st.sim_time >= from && st.sim_time <= to)
      m = std::max(m, std::sqrt(st.interaction_force[0] * st.interaction_force[0] +
                                st.interaction_force[1] * st.interaction_force[1] +
                                st.interaction_force[2] * st.interaction_force[2]));
  return m;
}

void expectRateKept(const Session& s, const char* what) {
  EXPECT_EQ(s.client_exit, 0) << what;
  EXPECT_GE(s.last_status.cycles, 2490) << what << ": the client ran its whole script";
  EXPECT_LE(s.last_status.max_force_step, kMaxForceStep + 1e-9) << what << ": the rendered force stayed continuous";
  std::printf("%-28s cycles %lld  misses %lld (max %lld in a row)  fallbacks %lld  rtt p50/p99 %.0f/%.0f us  "
              "max force step %.3f N\n",
              what, static_cast<long long>(s.last_status.cycles), static_cast<long long>(s.last_status.deadline_misses),
              static_cast<long long>(s.last_status.max_consecutive_misses),
              static_cast<long long>(s.last_status.fallbacks), s.last_status.rtt_us_p50, s.last_status.rtt_us_p99,
              s.last_status.max_force_step);
}

TEST(Client, PushMovesTheTouchedLinkOffItsPath) {
  const Session s = run("push_demo.yaml");
  expectRateKept(s, "push, no faults");
  ASSERT_FALSE(s.states.empty());
  EXPECT_GT(maxForce(s, haptic_input_t::MODE_PUSH), 1.0) << "the tip pressed on the robot";
  // Against the in-process nominal run at the same simulated time.
  const robot_state_t& last = s.states.back();
  Simulation nominal(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  InteractionInput none;
  while (nominal.time() < last.sim_time - 1e-9) nominal.step(&none);
  double diff = 0.0;
  for (int j = 0; j < 6; ++j) diff = std::max(diff, std::abs(last.q[j] - nominal.q()[j]));
  EXPECT_GT(diff, 0.005) << "the push edited the trajectory";
  // Misses without faults come from the machine's scheduling, not the bus: on the shared 2-core VM
  // one build measured 4.6 % to 17 % from run to run, two builds run alternately 5 % to 39 % (the
  // pull below the same), and clean-clone CI runs (this test alone: RUN_SERIAL) 31 % and 65 %. The
  // rate holds either way (above). A broken reply path misses every cycle.
  EXPECT_LT(s.last_status.deadline_misses, 0.9 * s.last_status.cycles);
}

TEST(Client, PullBringsTheEndEffectorToTheHeldDevicePoint) {
  const Session s = run("pull_demo.yaml");
  expectRateKept(s, "pull, no faults");
  EXPECT_GT(maxForce(s, haptic_input_t::MODE_PULL), 0.5);
  // While the device holds still (1.6 s to 2.4 s), |F| = k |x_ph - x|: the spring's stretch.
  double worst = 0.0;
  int n = 0;
  for (const auto& st : s.states) {
    if (st.mode != haptic_input_t::MODE_PULL || st.sim_time < 1.6 || st.sim_time > 2.4) continue;
    const double f = std::sqrt(st.interaction_force[0] * st.interaction_force[0] +
                               st.interaction_force[1] * st.interaction_force[1] +
                               st.interaction_force[2] * st.interaction_force[2]);
    worst = std::max(worst, f / 800.0);  // k of scenes/puma_wall.yaml
    ++n;
  }
  EXPECT_GT(n, 500);
  EXPECT_LE(worst, 5e-3) << "end-effector within 5 mm of the held point";
}

TEST(Client, KeepsItsRateAndAContinuousForceWhenRepliesAreLost) {
  const Session clean = run("push_demo.yaml");
  for (const auto& [what, args] : std::vector<std::pair<const char*, std::vector<std::string>>>{
           {"10% of replies dropped", {"--fault-drop", "0.1"}},
           {"30% of replies dropped", {"--fault-drop", "0.3"}},
           {"20 ms bursts every second", {"--fault-burst-ms", "20"}}}) {
    const Session s = run("push_demo.yaml", args);
    expectRateKept(s, what);
    EXPECT_GT(s.last_status.fallbacks, 0) << what;
    EXPECT_GT(s.last_status.states_missed, 0) << what << ": the lost states are counted";
    // How far the edited trajectory moved from the loss-free run's.
    if (!s.states.empty() && !clean.states.empty()) {
      double d = 0.0;
      for (int j = 0; j < 6; ++j) d = std::max(d, std::abs(s.states.back().q[j] - clean.states.back().q[j]));
      std::printf("%-28s final joint deviation from the loss-free run: %.4f rad\n", what, d);
    }
  }
}

TEST(Client, StalledServerRampsTheForceDownAndTheClientResumes) {
  const Session s = run("push_demo.yaml", {}, Disturbance::StallServer);
  expectRateKept(s, "server stopped 300 ms");
  EXPECT_TRUE(s.saw_server_lost);
  EXPECT_LT(s.min_force_scale, 0.01) << "the force ramped down to zero";
  EXPECT_EQ(s.last_status.state, "finished");
  EXPECT_GE(s.last_status.max_consecutive_misses, 100);
}

TEST(Client, PullKeepsItsRateAndAContinuousForceWhenRepliesAreLost) {
  for (const auto& [what, args] : std::vector<std::pair<const char*, std::vector<std::string>>>{
           {"pull, 10% of replies dropped", {"--fault-drop", "0.1"}},
           {"pull, 30% of replies dropped", {"--fault-drop", "0.3"}},
           {"pull, 20 ms bursts", {"--fault-burst-ms", "20"}}}) {
    const Session s = run("pull_demo.yaml", args);
    expectRateKept(s, what);
    EXPECT_GT(s.last_status.fallbacks, 0) << what;
    EXPECT_GT(maxForce(s, haptic_input_t::MODE_PULL), 0.5) << what;
  }
}

// Grabbing with the spring already stretched 3 cm: the engage is bounded too.
TEST(Client, AGrabWithTheSpringStretchedReachesTheHandGradually) {
  const Session s = run("pull_grab_stretched.yaml");
  expectRateKept(s, "grab with the spring stretched 3 cm");
  EXPECT_GT(maxForce(s, haptic_input_t::MODE_PULL), 5.0) << "the spring engaged stretched";
  std::printf("grab: largest force on the robot %.2f N, cycles the 1 N bound cut %lld\n",
              maxForce(s, haptic_input_t::MODE_PULL), static_cast<long long>(s.last_status.force_slew_limited));
}

// The server stopped for 300 ms while the hand pushes (realtime and lockstep)
// or pulls, 50 ms into the contact: the hand feels the force ramp down and
// sinks, and the push it stored up does not reach the robot when the server
// returns (it did: 22 to 40 N, the scene's clamp, against 7 N). The client
// ends a push when it declares the server lost; the server brings a coupling
// back in over 100 ms after a gap in the inputs.
TEST(Client, AStallDuringContactDeliversNoStoredUpForceToTheRobot) {
  struct Case {
    const char* what;
    const char* script;
    const char* clock;
    int8_t mode;
  };
  // The paper's scene and scripts: their pushes touch the robot whatever the server's clock.
  for (const Case& c : {Case{"push, realtime server stopped in contact", "paper_push.yaml", "realtime", 1},
                        Case{"push, lockstep server stopped in contact", "paper_push.yaml", "lockstep", 1},
                        Case{"pull, realtime server stopped while pulling", "paper_pull.yaml", "realtime", 2}}) {
    const Session calm = run(c.script, {}, Disturbance::None, c.clock, 0, "puma_obstacle.yaml");
    const Session s = run(c.script, {}, Disturbance::StallInContact, c.clock, 50, "puma_obstacle.yaml");
    expectRateKept(s, c.what);
    EXPECT_TRUE(s.saw_server_lost) << c.what;
    double gap_at = -1.0;
    for (size_t k = 1; k < s.states.size() && gap_at < 0; ++k)
      if (s.states[k].utime - s.states[k - 1].utime > 200000) gap_at = s.states[k - 1].sim_time;
    ASSERT_GT(gap_at, 0.0) << c.what << ": the stall shows in the states";
    // Right after the gap (the 100 ms of the server's resume ramp) is where a stored-up push would land; and whatever force
    // comes back (a pull's spring is as stretched as the hand left it) comes back as a ramp, not a step: during
    // the server's 100 ms resume ramp it rises by at most 1 N a step. (After the ramp the force follows the hand
    // again, as sampled: a client starved by a loaded machine catches up with jumps of the script, and in
    // lockstep those reach the robot as steps of up to 2 N, stall or no stall.) A push that ends drops to zero
    // in one step, as every released push does: only rises count.
    const double undisturbed = maxForce(calm, c.mode), before = maxForce(s, c.mode, 0.0, gap_at),
                 right_after = maxForce(s, c.mode, gap_at + 1e-6, gap_at + 0.1);
    double largest_step = 0.0, last = -1.0;
    for (const auto& st : s.states) {
      if (st.sim_time <= gap_at || st.sim_time > gap_at + 0.1) continue;
      const double f = st.mode == c.mode ? std::sqrt(st.interaction_force[0] * st.interaction_force[0] +
                                                     st.interaction_force[1] * st.interaction_force[1] +
                                                     st.interaction_force[2] * st.interaction_force[2])
                                         : 0.0;
      if (last >= 0.0) largest_step = std::max(largest_step, f - last);
      last = f;
    }
    std::printf("%-44s largest force on the robot: %.2f N without a stall; with it %.2f N before, %.2f N in the "
                "100 ms after (the resume ramp), rising by at most %.2f N a step\n",
                c.what, undisturbed, before, right_after, largest_step);
    EXPECT_GT(before, 2.0) << c.what << ": the stall came in contact";
    EXPECT_LE(largest_step, 1.0) << c.what << ": what comes back, comes back as a ramp";
    // A push's stored-up depth is not delivered at all on the realtime clock (the server's default). Lockstep
    // applies every input in order, so the ones the client sent in the 50 ms before it declared the server
    // lost still arrive: a few newtons more. "before" covers the push's first 50 ms only, and the push goes
    // on rising after the ramp as it does without a stall (7.0 to 9.4 N from run to run: CI saw 7.15 N before
    // and 8.26 N after, with 9.36 N undisturbed): the bound is the larger of the two. A stored-up push
    // reached 22 to 40 N.
    if (c.mode == haptic_input_t::MODE_PUSH) {
      EXPECT_LE(right_after, std::max(before, undisturbed) + (std::string(c.clock) == "lockstep" ? 4.0 : 1.0))
          << c.what << ": nothing stored up is delivered";
    }
  }
}

// Stopped while it waits for a server that never came: a clean exit that says so (it used to compare the
// missing server's link count with the scene's: "not the same scene?"). The stop comes once the client says
// it waits: a fixed 500 ms was once too short for a loaded CI machine to start it, and SIGTERM's default
// action ended it before its handler was in place (stop() read -1, and it said nothing).
TEST(Client, StoppedBeforeAnyServerAppearsItSaysSoAndExitsCleanly) {
  const std::string err = ::testing::TempDir() + "/client_no_server.err";
  std::remove(err.c_str());
  ChildProcess client({"/bin/sh", "-c",
                       std::string("exec ") + std::getenv("IGMS_CLIENT_BIN") + " --scene " + sourceDir() +
                           "/scenes/puma_wall.yaml --device scripted:" + sourceDir() +
                           "/scenes/push_demo.yaml --lcm-url '" + url() + "' 2> " + err});
  auto said_so_far = [&] {
    std::ifstream in(err);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(8);
  while (said_so_far().find("waiting up to") == std::string::npos && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_NE(said_so_far().find("waiting up to"), std::string::npos) << said_so_far();
  EXPECT_EQ(client.stop(), 0);
  const std::string said = said_so_far();
  EXPECT_NE(said.find("stopped before any server appeared"), std::string::npos) << said;
  EXPECT_EQ(said.find("not the same scene"), std::string::npos) << said;
}

// One such datagram on the status channel used to abort the client, which in a
// real set-up holds a force device.
TEST(Client, AnUndecodableStatusIsIgnoredAndTheSessionRunsOn) {
  const Session s = run("push_demo.yaml", {}, Disturbance::PoisonStatus);
  expectRateKept(s, "undecodable status x3");
  EXPECT_EQ(s.last_status.state, "finished");
}

}  // namespace
}  // namespace igms::test
