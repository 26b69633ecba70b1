// The one way a program takes messages off the bus. Every message is checked
// by the program's verifier before anything reads it (a refusal is counted
// there, message_verifier.h). A typed subscription then decodes what was
// accepted with safeDecode: LCM's generated decoders throw, and a message
// that does not decode is counted here and handed to no one. So no receive
// path can skip the check, decode unguarded or lose a refusal uncounted.
//
//   auto states = bus::subscribe<robot_state_t>(lcm, verifier, channels::kRobotState,
//       [&](const robot_state_t& m, const bus::Verdict& v) { ... });
//   auto all = bus::subscribeRaw(lcm, verifier, ".*",
//       [&](const std::string& channel, const lcm::ReceiveBuffer& m, const bus::Verdict& v) { ... });
//
// The handler runs on the thread that calls lcm::LCM::handle, as LCM's own
// handlers do. A typed subscription decodes into one message it keeps, so a
// message's arrays keep their capacity from one arrival to the next: nothing
// allocates for a message no larger than the last. A subscription
// unsubscribes when destroyed; it must not outlive its lcm::LCM or verifier.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <utility>

#include "bus/message_verifier.h"
#include "safe_decode.h"

namespace igms::bus {

// The messages of a channel (or a channel regex) as bytes, as they arrived: the handler gets the
// whole message (with the signature's trailer, to record or forward as it is; LCM's receive time)
// and the verdict, whose payload_bytes is the LCM message without the trailer. Only accepted messages, unless the program
// watches refusals too (a logger records them, a spy counts them): then `refused` gets those.
using RawHandler = std::function<void(const std::string& channel, const lcm::ReceiveBuffer& message, const Verdict&)>;
struct RawOptions {
  int queue_capacity = 0;  // LCM's queue for this subscription (0: LCM's default)
  RawHandler refused;      // told of each refused message (after the verifier counted it)
  // Channels not wanted are not checked at all, so not counted (a logger's or spy's filter).
  std::function<bool(const std::string& channel)> wanted;
};

class RawSubscription {
 public:
  using Handler = RawHandler;
  using Options = RawOptions;

  RawSubscription(lcm::LCM& lcm, MessageVerifier& verifier, const std::string& channel, Handler handler,
                  Options options = {})
      : lcm_(lcm), verifier_(verifier), handler_(std::move(handler)), options_(std::move(options)) {
    subscription_ = lcm_.subscribeFunction<RawSubscription*>(channel, &RawSubscription::arrived, this);
    if (subscription_ && options_.queue_capacity > 0) subscription_->setQueueCapacity(options_.queue_capacity);
  }
  ~RawSubscription() {
    if (subscription_) lcm_.unsubscribe(subscription_);
  }
  RawSubscription(const RawSubscription&) = delete;
  RawSubscription& operator=(const RawSubscription&) = delete;

  bool good() const { return subscription_ != nullptr; }

 private:
  static void arrived(const lcm::ReceiveBuffer* rbuf, const std::string& channel, RawSubscription* self) {
    if (self->options_.wanted && !self->options_.wanted(channel)) return;
    const Verdict checked = self->verifier_.check(channel, static_cast<const uint8_t*>(rbuf->data), rbuf->data_size);
    if (checked.accepted) self->handler_(channel, *rbuf, checked);
    else if (self->options_.refused) self->options_.refused(channel, *rbuf, checked);
  }

  lcm::LCM& lcm_;
  MessageVerifier& verifier_;
  Handler handler_;
  Options options_;
  lcm::Subscription* subscription_ = nullptr;
};

// The accepted messages of a channel, decoded as Message.
template <class Message>
class Subscription {
 public:
  using Handler = std::function<void(const Message&, const Verdict&)>;
  // Told of each accepted message that does not decode (after it is counted here).
  using Undecodable = std::function<void(const Verdict&)>;

  Subscription(lcm::LCM& lcm, MessageVerifier& verifier, const std::string& channel, Handler handler,
               int queue_capacity = 0, Undecodable undecodable = nullptr)
      : handler_(std::move(handler)),
        on_undecodable_(std::move(undecodable)),
        raw_(lcm, verifier, channel,
             [this](const std::string&, const lcm::ReceiveBuffer& rbuf, const Verdict& checked) {
               if (!safeDecode(rbuf.data, checked.payload_bytes, &message_)) {
                 undecodable_.fetch_add(1, std::memory_order_relaxed);
                 if (on_undecodable_) on_undecodable_(checked);
                 return;
               }
               handler_(message_, checked);
             },
             RawOptions{queue_capacity, nullptr, nullptr}) {}

  bool good() const { return raw_.good(); }
  // Accepted messages that did not decode as Message (any thread may read it).
  int64_t undecodable() const { return undecodable_.load(std::memory_order_relaxed); }

 private:
  Handler handler_;
  Undecodable on_undecodable_;
  Message message_;  // decoded into (its arrays keep their capacity)
  std::atomic<int64_t> undecodable_{0};
  RawSubscription raw_;  // last: subscribed once the rest is there, unsubscribed before it goes
};

template <class Message>
std::unique_ptr<Subscription<Message>> subscribe(lcm::LCM& lcm, MessageVerifier& verifier, const std::string& channel,
                                                 typename Subscription<Message>::Handler handler,
                                                 int queue_capacity = 0,
                                                 typename Subscription<Message>::Undecodable undecodable = nullptr) {
  return std::make_unique<Subscription<Message>>(lcm, verifier, channel, std::move(handler), queue_capacity,
                                                 std::move(undecodable));
}

inline std::unique_ptr<RawSubscription> subscribeRaw(lcm::LCM& lcm, MessageVerifier& verifier,
                                                     const std::string& channel, RawHandler handler,
                                                     RawOptions options = {}) {
  return std::make_unique<RawSubscription>(lcm, verifier, channel, std::move(handler), std::move(options));
}

}  // namespace igms::bus
