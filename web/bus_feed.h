// The live bus into a BusView: a thread of its own that takes every message
// on the LCM URL (one raw subscription) and hands it over as bytes. It can
// also publish (the web device's commands).
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "web/bus_view.h"

namespace lcm {
class LCM;
}

namespace igms::web {

class BusFeed {
 public:
  // Throws std::runtime_error when the URL cannot be opened.
  BusFeed(const std::string& url, BusView& view);
  ~BusFeed();
  template <typename Message>
  void publish(const std::string& channel, const Message& m) {
    std::string bytes(static_cast<size_t>(m.getEncodedSize()), '\0');
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    publishBytes(channel, bytes);
  }
  void publishBytes(const std::string& channel, const std::string& bytes);

 private:
  std::unique_ptr<lcm::LCM> lcm_;
  BusView& view_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace igms::web
