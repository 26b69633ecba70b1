// The server's bus side: haptic inputs and commands from LCM. Inputs are
// validated (InputGate: rejected and counted by reason) and the newest
// admitted one is handed to the step lock-free; commands are queued for the
// loop to apply between steps. Runs on whichever thread calls
// lcm::LCM::handle (the bus thread, or the loop itself in lockstep).
#pragma once

#include <atomic>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>

#include "core/realtime/latest_value.h"
#include "igms/command_t.hpp"
#include "server/transport/input_gate.h"

namespace igms {

// The newest admitted input, with the time it arrived.
struct TimedInput {
  InteractionInput input;
  double arrived = 0.0;  // monotonic s
};

// What the status reports about the bus.
struct BusCounters {
  int64_t inputs_received = 0, inputs_rejected = 0, inputs_accepted = 0, inputs_missed = 0;
  std::array<int64_t, kRejectReasons> rejected_by_reason{};
  int64_t commands_received = 0, commands_refused = 0;  // refused: undecodable, or the queue was full
};

class BusReceiver {
 public:
  static constexpr size_t kMaxQueuedCommands = 100;

  explicit BusReceiver(lcm::LCM& bus);
  // A model (a scene was loaded) and a session token: inputs are judged against them.
  void startSession(const Model& model, int64_t token);
  // A reset: the same model, a new token, the clients' sequence numbers forgotten.
  void newSession(int64_t token);

  const LatestValue<TimedInput>& input() const { return input_; }
  // Moves the queued commands into *out without waiting; false when the
  // receiver holds its lock right now (the loop tries again next step).
  bool takeCommands(std::deque<command_t>* out);
  BusCounters counters();

  void onInput(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onCommand(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

 private:
  std::mutex mutex_;  // guards gate_, commands_, counters_ (never taken by the step itself)
  std::unique_ptr<InputGate> gate_;
  std::deque<command_t> commands_;
  BusCounters counters_;
  LatestValue<TimedInput> input_;
};

}  // namespace igms
