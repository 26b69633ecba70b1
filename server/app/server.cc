#include "server/app/server.h"

#include <semaphore.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>
#include <random>
#include <thread>
#include <unistd.h>
#include <vector>

#include "channels.h"
#include "igms/command_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "igms/session_info_t.hpp"
#include "igms_build_info.h"
#include "igms/trajectory_t.hpp"
#include "server/collision/collision_world.h"
#include "server/loop/snapshot.h"
#include "server/transport/input_gate.h"
#include "core/realtime/clock.h"
#include "core/realtime/latest_value.h"

namespace igms {
namespace {

// The newest admitted input, with the time it arrived.
struct TimedInput {
  InteractionInput input;
  double arrived = 0.0;  // monotonic s
};

// Everything the bus thread shares with the simulation.
struct Shared {
  Shared() { sem_init(&input_ready, 0, 0); }
  ~Shared() { sem_destroy(&input_ready); }
  sem_t input_ready;  // posted per admitted input or command: lockstep wakes at once (no lock)
  LatestValue<TimedInput> input;
  std::mutex mutex;  // guards gate, commands (never taken by the step itself)
  std::unique_ptr<InputGate> gate;
  std::deque<command_t> commands;
  std::atomic<int64_t> accepted{0};
};

class Session;

// Publishing thread: snapshots -> robot_state_t, collisions, status.
class Publisher {
 public:
  Publisher(lcm::LCM& bus, Simulation& sim, SnapshotRing& ring, Shared& shared, const ServerOptions& options)
      : bus_(bus), sim_(sim), ring_(ring), shared_(shared), options_(options),
        world_(sim.model(), sim.scene().obstacles) {
    const Model& m = sim.model();
    msg_.nq = m.nq;
    msg_.nv = m.nv;
    msg_.q.resize(static_cast<size_t>(m.nq));
    msg_.v.resize(static_cast<size_t>(m.nv));
    msg_.qdd.resize(static_cast<size_t>(m.nv));
    msg_.tau.resize(static_cast<size_t>(m.nv));
    msg_.nlinks = static_cast<int32_t>(m.frames.size());
    msg_.link_poses.assign(m.frames.size(), std::vector<double>(7, 0.0));
    buffer_.resize(static_cast<size_t>(msg_.getEncodedSize()) + 64);
    info_.build_version = IGMS_BUILD_VERSION;
    info_.scene_path = sim.scene().source;
    info_.scene_text = sim.scene().text;
    info_.model_path = sim.scene().model_path;
    try {
      info_.model_hash = textHash(readModelFile(sim.scene().model_path));
    } catch (const std::exception&) {
      info_.model_hash = "unreadable";
    }
    info_.clock = options.clock == ServerOptions::Clock::Lockstep ? "lockstep" : "realtime";
    info_.dt = sim.scene().dt;
    for (const auto& f : m.frames) link_names_.push_back(f.name);
    components_ = sim.activeComponents();
  }

  // threaded: a publishing thread of its own (realtime); else the caller
  // pumps (lockstep: one thread receives, steps and publishes).
  void start(bool threaded) {
    sem_init(&ready_, 0, 0);
    if (threaded) thread_ = std::thread([this] { loop(); });
    next_status_ = monotonicSeconds() + 0.1;
    window_start_ = monotonicSeconds();
  }
  void finish() {
    done_ = true;
    sem_post(&ready_);
    if (thread_.joinable()) thread_.join();
    pump();
    sem_destroy(&ready_);
  }
  // Publishes what the ring holds, and the status when due. Returns whether
  // anything was published.
  bool pump() {
    if (info_due_.exchange(false)) {
      info_.utime = wallMicros();
      info_.session_token = info_token_;
      bus_.publish(channels::kSessionInfo, &info_);
    }
    bool any = false;
    while (const Snapshot* s = ring_.beginRead()) {
      publishState(*s);
      ring_.endRead();
      any = true;
    }
    if (monotonicSeconds() >= next_status_) {
      publishStatus();
      next_status_ += 0.1;
    }
    return any;
  }
  // The simulation thread's wake-up call after each snapshot (a futex post, no lock).
  void notify() { sem_post(&ready_); }

  std::atomic<int64_t> ring_drops{0};
  std::atomic<int64_t> overruns{0};
  std::atomic<int64_t> steps{0};
  std::string state = "running";
  std::mutex state_mutex;
  std::string message;
  int64_t collisions = 0;
  double first_collision = -1.0, min_distance = 1e9;

  // What a replay needs: at the start of a session, after a reset, and every
  // second. Any thread may ask; the publishing side sends it.
  void requestSessionInfo(int64_t token) {
    info_token_ = token;
    info_due_ = true;
  }

  void publishStatus() {
    server_status_t s;
    s.utime = wallMicros();
    s.seq = status_seq_++;
    {
      std::lock_guard<std::mutex> lock(shared_.mutex);
      s.session_token = shared_.gate->token();
      s.inputs_received = shared_.gate->received();
      s.inputs_rejected = shared_.gate->rejectedTotal();
      for (int k = 0; k < kRejectReasons; ++k) s.rejected_by_reason[k] = shared_.gate->rejected()[k];
    }
    s.inputs_dropped = std::max<int64_t>(0, shared_.accepted.load() - consumed_inputs.load());
    s.scene = sim_.scene().source;
    {
      std::lock_guard<std::mutex> lock(state_mutex);
      s.state = state;
      s.message = message;
    }
    s.sim_time = last_sim_time_;
    s.steps = steps.load();
    const double now = monotonicSeconds();
    const double window = now - window_start_;
    s.rate_hz = window > 0 ? static_cast<double>(window_steps_) / window : 0.0;
    std::vector<double> t = step_times_;
    std::sort(t.begin(), t.end());
    auto pct = [&](double p) { return t.empty() ? 0.0 : t[std::min(t.size() - 1, static_cast<size_t>(p * t.size()))]; };
    s.step_us_p50 = pct(0.5);
    s.step_us_p99 = pct(0.99);
    s.step_us_max = t.empty() ? 0.0 : t.back();
    s.overruns = overruns.load();
    s.forces_clamped = forces_clamped.load();
    s.collisions = collisions;
    s.first_collision_time = first_collision;
    s.min_obstacle_distance = min_distance;
    s.ncomponents = static_cast<int32_t>(components_.size());
    s.components = components_;
    s.nlinks = static_cast<int32_t>(link_names_.size());
    s.link_names = link_names_;
    bus_.publish(channels::kServerStatus, &s);
    if (status_seq_ % 10 == 1) requestSessionInfo(s.session_token);
    window_start_ = now;
    window_steps_ = 0;
    step_times_.clear();
    if (!options_.quiet) {
      std::fprintf(stderr,
                   "igms-server: t=%.2f s  steps=%lld  rate=%.0f Hz  step p50/p99/max=%.1f/%.1f/%.1f us  overruns=%lld"
                   "  inputs=%lld rejected=%lld  collisions=%lld  min_dist=%.3f m  %s\n",
                   s.sim_time, static_cast<long long>(s.steps), s.rate_hz, s.step_us_p50, s.step_us_p99,
                   s.step_us_max, static_cast<long long>(s.overruns), static_cast<long long>(s.inputs_received),
                   static_cast<long long>(s.inputs_rejected), static_cast<long long>(collisions), min_distance,
                   s.state.c_str());
    }
  }

  std::atomic<int64_t> consumed_inputs{0};
  std::atomic<int64_t> forces_clamped{0};

 private:
  void publishState(const Snapshot& s) {
    msg_.utime = s.utime;
    msg_.seq = s.seq;
    msg_.sim_time = s.sim_time;
    msg_.input_seq = s.outcome.input_seq;
    msg_.input_client = s.outcome.input_client;
    std::copy(s.q.begin(), s.q.end(), msg_.q.begin());
    std::copy(s.v.begin(), s.v.end(), msg_.v.begin());
    std::copy(s.qdd.begin(), s.qdd.end(), msg_.qdd.begin());
    std::copy(s.tau.begin(), s.tau.end(), msg_.tau.begin());
    msg_.mode = static_cast<int8_t>(s.outcome.mode);
    for (int k = 0; k < 3; ++k) {
      msg_.interaction_force[k] = s.outcome.force_on_robot[k];
      msg_.interaction_point[k] = s.outcome.force_point[k];
    }
    for (size_t f = 0; f < s.link_poses.size(); ++f) {
      const SE3& X = s.link_poses[f];
      Eigen::Quaterniond quat(X.R);
      if (quat.w() < 0) quat.coeffs() *= -1.0;
      auto& row = msg_.link_poses[f];
      row[0] = X.p.x(); row[1] = X.p.y(); row[2] = X.p.z();
      row[3] = quat.w(); row[4] = quat.x(); row[5] = quat.y(); row[6] = quat.z();
    }
    if (!world_.empty()) {
      const CollisionReport c = world_.check(s.link_poses);
      msg_.min_obstacle_distance = c.min_distance;
      msg_.in_collision = c.in_collision;
      min_distance = std::min(min_distance, c.min_distance);
      if (c.in_collision) {
        ++collisions;
        if (first_collision < 0) {
          first_collision = s.sim_time;
          if (!options_.quiet)
            std::fprintf(stderr, "igms-server: collision at t=%.3f s: %s hits %s\n", s.sim_time,
                         c.closest_link.c_str(), c.closest_obstacle.c_str());
        }
      }
    } else {
      msg_.min_obstacle_distance = 1e9;
      msg_.in_collision = false;
    }
    msg_.step_us = s.step_us;
    // Encode into our buffer, publish raw bytes (unless a fault drops it).
    const int n = msg_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    const bool faults = options_.fault_drop > 0 || options_.fault_burst_ms > 0 || options_.fault_delay_us > 0;
    if (n > 0 && faults) bus_.publish(channels::kRobotStateTruth, buffer_.data(), static_cast<unsigned>(n));
    if (n > 0 && !faultDrops()) {
      if (options_.fault_delay_us > 0)
        std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int64_t>(options_.fault_delay_us)));
      bus_.publish(channels::kRobotState, buffer_.data(), static_cast<unsigned>(n));
    }
    last_sim_time_ = s.sim_time;
    step_times_.push_back(s.step_us);
    ++window_steps_;
  }

  bool faultDrops() {
    if (options_.fault_drop > 0 && uniform_(rng_) < options_.fault_drop) return true;
    if (options_.fault_burst_ms > 0) {
      const double phase = std::fmod(monotonicSeconds() - fault_epoch_, 1.0);
      if (phase < options_.fault_burst_ms * 1e-3) return true;
    }
    return false;
  }

  void loop() {
    for (;;) {
      const bool any = pump();
      if (done_ && !ring_.beginRead()) break;
      if (!any) {
        timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 20000000L;  // wake for the status at least every 20 ms
        if (until.tv_nsec >= 1000000000L) {
          until.tv_nsec -= 1000000000L;
          ++until.tv_sec;
        }
        sem_timedwait(&ready_, &until);
      }
    }
  }

  lcm::LCM& bus_;
  Simulation& sim_;
  SnapshotRing& ring_;
  Shared& shared_;
  const ServerOptions& options_;
  CollisionWorld world_;
  robot_state_t msg_;
  session_info_t info_;
  std::atomic<bool> info_due_{false};
  std::atomic<int64_t> info_token_{0};
  std::vector<uint8_t> buffer_;
  std::vector<std::string> link_names_, components_;
  std::vector<double> step_times_;
  int64_t status_seq_ = 0, window_steps_ = 0;
  double window_start_ = 0.0, last_sim_time_ = 0.0, next_status_ = 0.0;
  std::atomic<bool> done_{false};
  std::thread thread_;
  sem_t ready_;
  std::mt19937 rng_{12345};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  double fault_epoch_ = monotonicSeconds();
};

// The bus thread's handlers.
class BusHandler {
 public:
  explicit BusHandler(Shared& s) : shared_(s) {}
  void onInput(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    haptic_input_t msg;
    std::lock_guard<std::mutex> lock(shared_.mutex);
    if (!shared_.gate) return;
    if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
      shared_.gate->countUndecodable();
      return;
    }
    TimedInput in;
    RejectReason why;
    if (!shared_.gate->admit(msg, &in.input, &why)) return;
    in.arrived = monotonicSeconds();
    shared_.input.write(in);
    ++shared_.accepted;
    sem_post(&shared_.input_ready);
  }
  void onCommand(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    command_t cmd;
    if (cmd.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    std::lock_guard<std::mutex> lock(shared_.mutex);
    shared_.commands.push_back(cmd);
    sem_post(&shared_.input_ready);
  }

 private:
  Shared& shared_;
};

int64_t randomToken() {
  std::random_device rd;
  return (static_cast<int64_t>(rd()) << 31) ^ static_cast<int64_t>(rd()) ^ getpid();
}

}  // namespace

int runServer(const ServerOptions& options, const std::atomic<bool>& stop) {
  std::string scene_path = options.scene_path;
  lcm::LCM bus(options.lcm_url.empty() ? channels::kDefaultUrl : options.lcm_url);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-server: cannot open LCM at %s\n", options.lcm_url.c_str());
    return 2;
  }
  Shared shared;
  BusHandler handler(shared);
  bus.subscribe(channels::kHapticInput, &BusHandler::onInput, &handler)->setQueueCapacity(1000);
  bus.subscribe(channels::kCommand, &BusHandler::onCommand, &handler)->setQueueCapacity(100);
  // Realtime: a bus thread receives while the simulation keeps its deadlines.
  // Lockstep: the simulation thread receives, steps and publishes itself:
  // two thread hand-offs fewer on the round trip.
  const bool lockstep = options.clock == ServerOptions::Clock::Lockstep;
  std::atomic<bool> bus_stop{false};
  std::thread bus_thread;
  if (!lockstep)
    bus_thread = std::thread([&] {
      while (!bus_stop) bus.handleTimeout(20);
    });
  int64_t token = options.session_token ? options.session_token : randomToken();
  int exit_code = 0;
  bool reload = true;
  bool paused = options.start_paused;
  while (reload && !stop) {
    reload = false;
    std::unique_ptr<Simulation> sim;
    try {
      sim = std::make_unique<Simulation>(loadScene(scene_path));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "igms-server: %s\n", e.what());
      exit_code = 2;
      break;
    }
    {
      std::lock_guard<std::mutex> lock(shared.mutex);
      shared.gate = std::make_unique<InputGate>(sim->model(), token);
    }
    if (!options.quiet) {
      std::fprintf(stderr, "igms-server: scene %s, model %s (nq %d, nv %d), %s clock at %.0f Hz, session %lld\n",
                   scene_path.c_str(), sim->scene().model_path.c_str(), sim->model().nq, sim->model().nv,
                   options.clock == ServerOptions::Clock::Realtime ? "realtime" : "lockstep", sim->scene().rate_hz,
                   static_cast<long long>(token));
      std::string comps;
      for (const auto& c : sim->activeComponents()) comps += " " + c;
      std::fprintf(stderr, "igms-server: active:%s\n", comps.c_str());
    }
    SnapshotRing ring(sim->model(), 512);
    Publisher publisher(bus, *sim, ring, shared, options);
    publisher.requestSessionInfo(token);
    publisher.start(!lockstep);
    auto publishSnapshot = [&](int32_t step_us) {
      if (Snapshot* slot = ring.beginWrite()) {
        takeSnapshot(*sim, wallMicros(), step_us, *slot);
        ring.endWrite();
        publisher.notify();
      } else {
        ++publisher.ring_drops;
      }
    };
    auto setState = [&](const std::string& state, const std::string& message) {
      std::lock_guard<std::mutex> lock(publisher.state_mutex);
      publisher.state = state;
      publisher.message = message;
    };
    setState(paused ? "paused" : options.clock == ServerOptions::Clock::Lockstep ? "lockstep" : "running", "");
    publishSnapshot(0);  // the initial state

    uint64_t consumed_version = 0;
    TimedInput latest;
    const double period = 1.0 / sim->scene().rate_hz;
    timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    bool running = true;
    int steps_requested = 0;
    while (running && !stop) {
      // Commands, between steps (never inside one).
      std::deque<command_t> todo;
      if (shared.mutex.try_lock()) {
        todo.swap(shared.commands);
        shared.mutex.unlock();
      }
      for (const command_t& c : todo) {
        switch (c.kind) {
          case command_t::START: paused = false; setState(options.clock == ServerOptions::Clock::Lockstep ? "lockstep" : "running", ""); break;
          case command_t::PAUSE: paused = true; setState("paused", ""); break;
          case command_t::STEP: ++steps_requested; break;
          case command_t::RESET: {
            sim->reset();
            token = randomToken();
            publisher.requestSessionInfo(token);
            std::lock_guard<std::mutex> lock(shared.mutex);
            shared.gate->newSession(token);
            break;
          }
          case command_t::LOAD_SCENE: scene_path = c.text; reload = true; running = false; break;
          case command_t::SET_TRAJECTORY: {
            std::vector<double> t(c.trajectory.t.begin(), c.trajectory.t.end());
            std::vector<VectorX> p;
            for (const auto& row : c.trajectory.q) p.push_back(Eigen::Map<const VectorX>(row.data(), static_cast<int>(row.size())));
            try {
              sim->setNominalTrajectory(t, p);
            } catch (const std::exception& e) {
              setState("running", std::string("SET_TRAJECTORY rejected: ") + e.what());
            }
            break;
          }
          case command_t::SET_GAINS:
            if (c.nvalues == 3 && c.values[0] > 0 && c.values[1] > 0 && c.values[2] >= 0)
              sim->setGains(c.values[0], c.values[1], c.values[2]);
            break;
          case command_t::SAVE_TRAJECTORY:
            try {
              sim->saveEditedTrajectory(c.text);
            } catch (const std::exception& e) {
              setState("running", e.what());
            }
            break;
          case command_t::SHUTDOWN: running = false; break;
          default: break;
        }
      }
      if (!running) break;

      bool do_step = !paused || steps_requested > 0;
      if (lockstep) {
        // One step per new input (or STEP command), received on this thread.
        if (shared.input.version() == consumed_version && steps_requested == 0) {
          publisher.pump();  // the status, when due
          bus.handleTimeout(20);
          continue;
        }
        do_step = true;
      }
      if (do_step) {
        if (steps_requested > 0) --steps_requested;
        // The newest input, held for input_hold after it arrived.
        const uint64_t version = shared.input.read(&latest);
        if (version != consumed_version) {
          consumed_version = version;
          ++publisher.consumed_inputs;
        }
        const bool fresh = version > 0 && (lockstep || monotonicSeconds() - latest.arrived <= options.input_hold);
        const double t0 = monotonicSeconds();
        const bool ok = sim->step(fresh ? &latest.input : nullptr);
        const int32_t step_us = static_cast<int32_t>((monotonicSeconds() - t0) * 1e6);
        if (sim->outcome().clamped) ++publisher.forces_clamped;
        ++publisher.steps;
        publishSnapshot(step_us);
        if (lockstep) publisher.pump();
        if (!ok) {
          std::fprintf(stderr, "igms-server: %s\n", sim->divergenceReport().c_str());
          setState("diverged", sim->divergenceReport());
          exit_code = 1;
          running = false;
        }
        if (options.duration > 0 && sim->time() >= options.duration - 1e-9) running = false;
      }
      if (!lockstep) {
        // Absolute deadlines: a late step is counted, and the next one still aims at its own deadline.
        next.tv_nsec += static_cast<long>(period * 1e9);
        while (next.tv_nsec >= 1000000000L) {
          next.tv_nsec -= 1000000000L;
          ++next.tv_sec;
        }
        timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        if (now.tv_sec > next.tv_sec || (now.tv_sec == next.tv_sec && now.tv_nsec > next.tv_nsec)) {
          if (do_step) ++publisher.overruns;
        } else {
          clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
        }
      }
    }
    if (!options.save_edited.empty() && !reload) {
      try {
        sim->saveEditedTrajectory(options.save_edited);
        if (!options.quiet) std::fprintf(stderr, "igms-server: edited trajectory saved to %s\n", options.save_edited.c_str());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "igms-server: %s\n", e.what());
      }
    }
    if (exit_code == 0 && !reload) setState("stopped", "");
    publisher.finish();
    publisher.publishStatus();  // the final status
    if (!reload) {
      // Publish the edited trajectory on the bus too.
      trajectory_t traj;
      traj.utime = wallMicros();
      traj.nq = sim->model().nq;
      for (int j = 0; j < sim->model().nq; ++j) traj.joint_names.push_back("q" + std::to_string(j));
      for (int k = 0; k < sim->editedCount(); ++k) {
        traj.t.push_back(sim->editedTime(k));
        const VectorX row = sim->editedPoint(k);
        traj.q.emplace_back(row.data(), row.data() + row.size());
      }
      traj.npoints = static_cast<int32_t>(traj.t.size());
      bus.publish(channels::kEditedTrajectory, &traj);
    }
  }
  bus_stop = true;
  if (bus_thread.joinable()) bus_thread.join();
  return exit_code;
}

}  // namespace igms
