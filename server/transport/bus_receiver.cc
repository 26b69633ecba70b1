#include "server/transport/bus_receiver.h"

#include "channels.h"
#include "core/realtime/clock.h"
#include "safe_decode.h"

namespace igms {

BusReceiver::BusReceiver(lcm::LCM& bus, bus::MessageVerifier& verifier) : verifier_(verifier) {
  freeSlots();
  bus.subscribe(channels::kHapticInput, &BusReceiver::onInput, this)->setQueueCapacity(1000);
  bus.subscribe(channels::kCommand, &BusReceiver::onCommand, this)->setQueueCapacity(100);
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

void BusReceiver::onInput(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const bus::Verdict checked = verifier_.check(channel, static_cast<const uint8_t*>(rbuf->data), rbuf->data_size);
  if (!checked.accepted) return;  // counted by the verifier
  haptic_input_t msg;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!gate_) return;
  if (!safeDecode(rbuf->data, checked.payload_bytes, &msg)) {
    gate_->countUndecodable();
    return;
  }
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

void BusReceiver::onCommand(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const bus::Verdict checked = verifier_.check(channel, static_cast<const uint8_t*>(rbuf->data), rbuf->data_size);
  if (!checked.accepted) return;  // counted by the verifier: applies nothing
  command_t cmd;
  const bool decoded = safeDecode(rbuf->data, checked.payload_bytes, &cmd);
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.commands_received;
  if (!decoded || commands_.size() >= kMaxQueuedCommands) {
    ++counters_.commands_refused;
    return;
  }
  commands_.push_back({std::move(cmd), checked.signed_us});
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
