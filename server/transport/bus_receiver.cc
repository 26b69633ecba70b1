#include "server/transport/bus_receiver.h"

#include "channels.h"
#include "core/realtime/clock.h"

namespace igms {

BusReceiver::BusReceiver(lcm::LCM& bus, bus::MessageVerifier& verifier) : verifier_(verifier) {
  freeSlots();
  inputs_ = bus::subscribe<haptic_input_t>(
      bus, verifier, channels::kHapticInput, [this](const haptic_input_t& m, const bus::Verdict&) { onInput(m); },
      1000, [this](const bus::Verdict&) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (gate_) gate_->countUndecodable();
      });
  commands_in_ = bus::subscribe<command_t>(
      bus, verifier, channels::kCommand, [this](const command_t& m, const bus::Verdict& v) { onCommand(&m, v); }, 100,
      [this](const bus::Verdict& v) { onCommand(nullptr, v); });
}

void BusReceiver::startSession(const Model& model, int64_t token) {
  std::lock_guard<std::mutex> lock(mutex_);
  gate_ = std::make_unique<InputGate>(model, token);
  freeSlots();
}

void BusReceiver::newSession(int64_t token) {
  std::lock_guard<std::mutex> lock(mutex_);
  gate_->newSession(token);
  freeSlots();
}

void BusReceiver::onInput(const haptic_input_t& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!gate_) return;
  TimedInput in;
  RejectReason why;
  const double now = monotonicSeconds();
  if (!gate_->admit(msg, &in.input, &why, now)) return;
  in.arrived = now;
  // The client's slot; else a free one; else one whose client has gone quiet.
  int slot = -1;
  for (int k = 0; k < kMaxHands && slot < 0; ++k)
    if (slot_client_[static_cast<size_t>(k)] == msg.client_id) slot = k;
  for (int k = 0; k < kMaxHands && slot < 0; ++k)
    if (slot_client_[static_cast<size_t>(k)] < 0 || now - slot_arrived_[static_cast<size_t>(k)] > kSlotReclaimS)
      slot = k;
  if (slot < 0) {
    gate_->rejectHandsFull(msg.client_id);
    return;
  }
  slot_client_[static_cast<size_t>(slot)] = msg.client_id;
  slot_arrived_[static_cast<size_t>(slot)] = now;
  hands_[static_cast<size_t>(slot)].write(in);
  ++counters_.inputs_accepted;
}

void BusReceiver::onCommand(const command_t* cmd, const bus::Verdict& checked) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.commands_received;
  if (!cmd || commands_.size() >= kMaxQueuedCommands) {
    ++counters_.commands_refused;
    return;
  }
  commands_.push_back({*cmd, checked.signed_us});
}

bool BusReceiver::takeCommands(std::deque<ReceivedCommand>* out) {
  if (!mutex_.try_lock()) return false;
  out->swap(commands_);
  mutex_.unlock();
  return true;
}

std::vector<ClientRecord> BusReceiver::clients() {
  std::lock_guard<std::mutex> lock(mutex_);
  return gate_ ? gate_->clients() : std::vector<ClientRecord>{};
}

BusCounters BusReceiver::counters() {
  std::lock_guard<std::mutex> lock(mutex_);
  BusCounters c = counters_;
  if (gate_) {
    c.inputs_received = gate_->received();
    c.inputs_rejected = gate_->rejectedTotal();
    c.rejected_by_reason = gate_->rejected();
    c.inputs_missed = gate_->missed();
  }
  return c;
}

}  // namespace igms
