#include "server/app/server.h"

#include <unistd.h>

#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <openssl/rand.h>
#include <stdexcept>
#include <thread>

#include "bus/bus_key.h"
#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "channels.h"
#include "core/realtime/clock.h"
#include "core/realtime/deadline.h"
#include "core/realtime/realtime_priority.h"
#include "igms/trajectory_t.hpp"
#include "server/app/publishing_thread.h"
#include "server/app/state_publisher.h"
#include "server/app/status_reporter.h"
#include "server/loop/command_handler.h"
#include "server/loop/stepper.h"
#include "server/transport/bus_receiver.h"

namespace igms {
namespace {

// 63 bits from OpenSSL's generator (std::random_device need not be a cryptographic source), never 0.
int64_t randomToken() {
  uint64_t bits = 0;
  if (RAND_bytes(reinterpret_cast<unsigned char*>(&bits), sizeof bits) != 1)
    throw std::runtime_error("no random bytes for the session token (OpenSSL)");
  return static_cast<int64_t>(bits >> 1) | 1;
}

const char* runningWord(const ServerOptions& o) {
  return o.clock == ServerOptions::Clock::Lockstep ? "lockstep" : "running";
}

// Realtime: a thread of its own receives while the loop keeps its deadlines.
// Lockstep: none; the loop receives itself.
class BusThread {
 public:
  BusThread(lcm::LCM& bus, bool start) {
    if (start) thread_ = std::thread([this, &bus] {
        while (!stop_) bus.handleTimeout(20);
      });
  }
  ~BusThread() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Everything one scene runs with, composed.
struct SceneParts {
  SceneParts(bus::SignedPublisher& bus, BusReceiver& receiver, std::unique_ptr<Simulation> s, const ServerOptions& o)
      : sim(std::move(s)),
        contact_rows(o.contact_rate > 0 && sim->contactModel() ? sim->contactModel()->capacity() : 0),
        ring(sim->model(), 512, contact_rows),
        states(bus, sim->model(), sim->geometry(), FaultInjection{o.fault_drop, o.fault_burst_ms, o.fault_delay_us},
               o.quiet),
        contacts(bus, contact_rows),
        status(bus, *sim, o.clock == ServerOptions::Clock::Lockstep ? "lockstep" : "realtime", receiver, loop, o.quiet,
               o.clock == ServerOptions::Clock::Lockstep ? Stepper::kLockstepQuietS : o.input_hold),
        publishing(ring, states, contacts, status),
        stepper(*sim, receiver.hands(), ring, loop, o.clock == ServerOptions::Clock::Lockstep, o.input_hold,
                contact_rows > 0 ? contactPeriodSteps(sim->scene().rate_hz, o.contact_rate) : 0) {}
  std::unique_ptr<Simulation> sim;
  LoopStatus loop;
  int contact_rows;
  SnapshotRing ring;
  StatePublisher states;
  ContactPublisher contacts;
  StatusReporter status;
  PublishingThread publishing;
  Stepper stepper;
};

void printStart(const Simulation& sim, const std::string& scene_path, const ServerOptions& o, int64_t token) {
  std::string models;
  for (const RobotSpec& r : sim.scene().robots) models += (models.empty() ? "" : ", ") + r.model_path;
  if (!sim.scene().bodies.empty())
    models += (models.empty() ? "" : ", ") + std::to_string(sim.scene().bodies.size()) + " free bodies";
  std::fprintf(stderr, "igms-server: scene %s, model %s (nq %d, nv %d), %s clock at %.0f Hz, session %lld\n",
               scene_path.c_str(), models.c_str(), sim.model().nq, sim.model().nv,
               o.clock == ServerOptions::Clock::Realtime ? "realtime" : "lockstep", sim.scene().rate_hz,
               static_cast<long long>(token));
  std::string comps;
  for (const auto& c : sim.activeComponents()) comps += " " + c;
  std::fprintf(stderr, "igms-server: active:%s\n", comps.c_str());
}

void printWarnings(const Simulation& sim) {
  for (const std::string& w : sim.resolved().warnings) std::fprintf(stderr, "igms-server: warning: %s\n", w.c_str());
}

// Applies the commands that arrived, between steps.
void applyCommands(BusReceiver& receiver, SceneParts& p, LoopControl& control, const ServerOptions& o,
                   int64_t& token) {
  std::deque<ReceivedCommand> todo;
  if (!receiver.takeCommands(&todo)) return;
  for (const ReceivedCommand& received : todo) {
    command_t c;
    const CommandResult allowed = authorizeCommand(received.command, received.signed_us, token, o.commands, &c);
    if (!allowed.accepted) {
      ++p.loop.commands_rejected;
      p.loop.setMessage("command rejected: " + allowed.message);
      continue;
    }
    const CommandResult r = applyCommand(c, *p.sim, control);
    if (!r.accepted) {
      ++p.loop.commands_rejected;
      p.loop.setMessage("command rejected: " + r.message);
      continue;
    }
    if (control.new_session) {
      control.new_session = false;
      token = randomToken();
      receiver.newSession(token);
      p.status.requestSessionInfo(token);
    }
    p.loop.setState(control.paused ? "paused" : runningWord(o));
    if (!control.running) break;
  }
}

// Steps until stopped, a command ends the scene, the duration is reached,
// or the simulation diverges. Returns the exit code.
int runLoop(lcm::LCM& bus, BusReceiver& receiver, SceneParts& p, LoopControl& control, const ServerOptions& o,
            int64_t& token, const std::atomic<bool>& stop) {
  const bool lockstep = o.clock == ServerOptions::Clock::Lockstep;
  PeriodicDeadline deadline(1.0 / p.sim->scene().rate_hz);
  bool late = false;  // realtime: the next step starts after its deadline (catching up)
  while (control.running && !stop) {
    applyCommands(receiver, p, control, o, token);
    if (!control.running) break;
    bool do_step = !control.paused || control.steps_requested > 0;
    if (lockstep) {
      // One step per new set of inputs, one from each client taking part (or per STEP command),
      // received on this thread.
      if (!p.stepper.lockstepReady() && control.steps_requested == 0) {
        p.publishing.pump();  // the status, when due
        bus.handleTimeout(p.stepper.inputPending() ? 1 : 20);  // an input waiting for the others': look often
        continue;
      }
      do_step = true;
    }
    if (do_step) {
      if (control.steps_requested > 0) --control.steps_requested;
      const bool ok = p.stepper.step(late);
      if (lockstep) p.publishing.pump();
      if (!ok) {
        std::fprintf(stderr, "igms-server: %s\n", p.sim->divergenceReport().c_str());
        p.loop.setState("diverged", p.sim->divergenceReport());
        return 1;
      }
      if (o.duration > 0 && p.sim->time() >= o.duration - 1e-9) return 0;
    }
    if (!lockstep) {
      deadline.advance();
      late = deadline.passed();
      if (late) {
        if (do_step) ++p.loop.overruns;  // late: counted; the next step still aims at its own deadline
      } else {
        deadline.sleep();
      }
    }
  }
  return 0;
}

void publishEditedTrajectory(bus::SignedPublisher& bus, const Simulation& sim) {
  trajectory_t traj;
  traj.utime = wallMicros();
  static const EditedTrajectory kNone;
  const EditedTrajectory& edited = sim.robots() > 0 ? sim.robot(0).edited() : kNone;  // the first robot's q
  traj.nq = edited.count() > 0 ? static_cast<int32_t>(edited.point(0).size()) : 0;
  for (int j = 0; j < traj.nq; ++j) traj.joint_names.push_back("q" + std::to_string(j));
  for (int k = 0; k < edited.count(); ++k) {
    traj.t.push_back(edited.time(k));
    const VectorX row = edited.point(k);
    traj.q.emplace_back(row.data(), row.data() + row.size());
  }
  traj.npoints = static_cast<int32_t>(traj.t.size());
  bus.publish(channels::kEditedTrajectory, traj);
}

// One scene from load to its end. Returns the exit code.
int runScene(const std::string& scene_path, lcm::LCM& bus, bus::SignedPublisher& out, BusReceiver& receiver,
             LoopControl& control, const ServerOptions& o, int64_t& token, const std::atomic<bool>& stop) {
  std::unique_ptr<Simulation> sim;
  try {
    sim = std::make_unique<Simulation>(loadScene(scene_path));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-server: %s\n", e.what());
    return 2;
  }
  if (const std::string why = stateTooLarge(sim->model(), scene_path); !why.empty()) {
    std::fprintf(stderr, "igms-server: %s\n", why.c_str());
    return 2;
  }
  receiver.startSession(sim->model(), token);
  if (!o.quiet) printStart(*sim, scene_path, o, token);
  printWarnings(*sim);  // even with --quiet: a silent no-op is worse than a line
  SceneParts p(out, receiver, std::move(sim), o);
  p.status.requestSessionInfo(token);
  p.publishing.start(o.clock == ServerOptions::Clock::Realtime);
  p.loop.setState(control.paused ? "paused" : runningWord(o));
  p.stepper.snapshot(0);  // the initial state
  const int code = runLoop(bus, receiver, p, control, o, token, stop);
  if (!control.reload && !o.save_edited.empty()) {
    try {
      p.sim->saveEdited(0, o.save_edited);  // the first robot's
      if (!o.quiet) std::fprintf(stderr, "igms-server: edited trajectory saved to %s\n", o.save_edited.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "igms-server: %s\n", e.what());
    }
  }
  if (code == 0 && !control.reload) p.loop.setState("stopped");
  p.publishing.finish();
  if (!control.reload) publishEditedTrajectory(out, *p.sim);  // the publishing thread has finished
  return code;
}

}  // namespace

int runServer(const ServerOptions& options, const std::atomic<bool>& stop) {
  std::optional<bus::BusKey> key;
  try {
    key = bus::busKeyFor("igms-server", options.key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-server: %s\n", e.what());
    return 2;
  }
  ServerOptions o = options;
  o.commands.signed_bus = key.has_value();
  o.commands.started_us = bus::wallClockMicros();
  lcm::LCM bus(o.lcm_url.empty() ? channels::kDefaultUrl : o.lcm_url);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-server: cannot open LCM at %s\n", o.lcm_url.c_str());
    return 2;
  }
  // One publisher: the publishing thread's (the loop's in lockstep, and after the scene ends).
  bus::SignedPublisher out(bus, key);
  bus::MessageVerifier verifier(key, "igms-server");
  if (o.accept_replay) verifier.acceptReplays();
  BusReceiver receiver(bus, verifier);
  // Before any thread starts, so that every thread inherits it: a loop on SCHED_FIFO whose
  // receiving or publishing thread an ordinary load can hold back still steps on late inputs.
  if (o.rt_priority > 0) requestRealtimeAndSay("igms-server", "every thread", o.rt_priority);
  BusThread bus_thread(bus, o.clock == ServerOptions::Clock::Realtime);
  int64_t token = o.session_token ? o.session_token : randomToken();
  LoopControl control;
  control.paused = o.start_paused;
  std::string scene_path = o.scene_path;
  for (;;) {
    control.running = true;
    control.reload = false;
    const int code = runScene(scene_path, bus, out, receiver, control, o, token, stop);
    if (code != 0 || !control.reload || stop) {
      if (!o.quiet || verifier.keyed() || verifier.counts().refusedTotal() > 0)  // keyed: always the one line
        std::fprintf(stderr, "igms-server: bus: %s\n", verifier.summary().c_str());
      return code;
    }
    scene_path = control.scene_path;
  }
}

}  // namespace igms
