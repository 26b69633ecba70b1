// The live bus into a BusView: a thread of its own that takes every message
// on the LCM URL (one raw subscription), checks it (bus::MessageVerifier:
// with a bus key, only what the key signed and is new) and hands the message
// over as bytes. It can also publish (the web device's and the viewer's
// commands), signed with the key.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "bus/subscription.h"
#include "web/bus_view.h"

namespace igms::web {

class BusFeed {
 public:
  // Throws std::runtime_error when the URL cannot be opened. program: names the feed's refusal lines.
  BusFeed(const std::string& url, BusView& view, const std::optional<bus::BusKey>& key = std::nullopt,
          const std::string& program = "igms-viewer");
  ~BusFeed();
  template <typename Message>
  void publish(const std::string& channel, const Message& m) {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    out_->publish(channel, m);
  }
  void publishBytes(const std::string& channel, const std::string& bytes);
  const bus::MessageVerifier& verifier() const { return verifier_; }
  bool keyed() const { return verifier_.keyed(); }

 private:
  std::unique_ptr<lcm::LCM> lcm_;
  BusView& view_;
  bus::MessageVerifier verifier_;  // the feed thread's
  std::mutex publish_mutex_;
  std::unique_ptr<bus::SignedPublisher> out_;
  std::unique_ptr<bus::RawSubscription> in_;
  std::string program_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace igms::web
