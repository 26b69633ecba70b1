// The server's bus side: haptic inputs and commands from LCM. Every message
// is first checked (bus::MessageVerifier: its signature on a signed bus) and
// decoded (bus/subscription.h); what fails is counted and goes no further. Inputs are
// validated (InputGate: rejected and counted by reason) and each client's
// newest admitted one is handed to the step lock-free in that client's hand
// slot (hand_slots.h); commands are queued for the
// loop to apply between steps. Runs on whichever thread calls
// lcm::LCM::handle (the bus thread, or the loop itself in lockstep).
#pragma once

#include <atomic>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>
#include <vector>

#include "bus/message_verifier.h"
#include "bus/subscription.h"
#include "igms/command_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "server/transport/hand_slots.h"
#include "server/transport/input_gate.h"

namespace igms {

// A command as it arrived: with its signature's time (the sender's wall clock, us; 0 unsigned).
struct ReceivedCommand {
  command_t command;
  int64_t signed_us = 0;
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
  // A hand slot whose client has sent nothing for this long is given to a new client.
  static constexpr double kSlotReclaimS = 1.0;

  BusReceiver(lcm::LCM& bus, bus::MessageVerifier& verifier);
  // A model (a scene was loaded) and a session token: inputs are judged against them.
  void startSession(const Model& model, int64_t token);
  // A reset: the same model, a new token, the clients' sequence numbers forgotten.
  void newSession(int64_t token);

  const HandSlots& hands() const { return hands_; }
  // The clients heard this session (for the status).
  std::vector<ClientRecord> clients();
  // Moves the queued commands into *out without waiting; false when the
  // receiver holds its lock right now (the loop tries again next step).
  bool takeCommands(std::deque<ReceivedCommand>* out);
  BusCounters counters();
  const bus::MessageVerifier& verifier() const { return verifier_; }

 private:
  void onInput(const haptic_input_t& msg);
  void onCommand(const command_t* cmd, const bus::Verdict& checked);  // cmd null: it did not decode

  bus::MessageVerifier& verifier_;  // used on the receiving thread only
  std::mutex mutex_;  // guards gate_, commands_, counters_ (never taken by the step itself)
  std::unique_ptr<InputGate> gate_;
  std::deque<ReceivedCommand> commands_;
  BusCounters counters_;
  HandSlots hands_;
  std::array<int32_t, kMaxHands> slot_client_;  // -1: free (guarded by mutex_)
  std::array<double, kMaxHands> slot_arrived_{};
  void freeSlots() { slot_client_.fill(-1); }
  std::unique_ptr<bus::Subscription<haptic_input_t>> inputs_;  // last: they call into the rest
  std::unique_ptr<bus::Subscription<command_t>> commands_in_;
};

}  // namespace igms
