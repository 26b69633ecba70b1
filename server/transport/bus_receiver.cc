#include "server/transport/bus_receiver.h"

#include "channels.h"
#include "core/realtime/clock.h"
#include "safe_decode.h"

namespace igms {

BusReceiver::BusReceiver(lcm::LCM& bus) {
  bus.subscribe(channels::kHapticInput, &BusReceiver::onInput, this)->setQueueCapacity(1000);
  bus.subscribe(channels::kCommand, &BusReceiver::onCommand, this)->setQueueCapacity(100);
}

void BusReceiver::startSession(const Model& model, int64_t token) {
  std::lock_guard<std::mutex> lock(mutex_);
  gate_ = std::make_unique<InputGate>(model, token);
}

void BusReceiver::newSession(int64_t token) {
  std::lock_guard<std::mutex> lock(mutex_);
  gate_->newSession(token);
}

void BusReceiver::onInput(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  haptic_input_t msg;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!gate_) return;
  if (!safeDecode(rbuf->data, rbuf->data_size, &msg)) {
    gate_->countUndecodable();
    return;
  }
  TimedInput in;
  RejectReason why;
  if (!gate_->admit(msg, &in.input, &why)) return;
  in.arrived = monotonicSeconds();
  input_.write(in);
  ++counters_.inputs_accepted;
}

void BusReceiver::onCommand(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  command_t cmd;
  const bool decoded = safeDecode(rbuf->data, rbuf->data_size, &cmd);
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.commands_received;
  if (!decoded || commands_.size() >= kMaxQueuedCommands) {
    ++counters_.commands_refused;
    return;
  }
  commands_.push_back(std::move(cmd));
}

bool BusReceiver::takeCommands(std::deque<command_t>* out) {
  if (!mutex_.try_lock()) return false;
  out->swap(commands_);
  mutex_.unlock();
  return true;
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
