#include "web/bus_feed.h"

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "bus/bus_status.h"
#include "channels.h"
#include "core/realtime/clock.h"

namespace igms::web {
BusFeed::BusFeed(const std::string& url, BusView& view, const std::optional<bus::BusKey>& key,
                 const std::string& program)
    : lcm_(std::make_unique<lcm::LCM>(url)), view_(view), verifier_(key, program), program_(program) {
  verifier_.acceptReplays();  // the page shows a replay (igms-replay play) as it shows a live session
  if (!lcm_->good()) throw std::runtime_error("cannot open LCM at " + url);
  out_ = std::make_unique<bus::SignedPublisher>(*lcm_, key, 16 * 1024);
  // Every message checked; the view decodes what was accepted, each by its channel's type (bus_view.h).
  in_ = bus::subscribeRaw(
      *lcm_, verifier_, ".*",
      [this](const std::string& channel, const lcm::ReceiveBuffer& m, const bus::Verdict& checked) {
        view_.handle(channel, m.data, checked.payload_bytes, monotonicSeconds());
      },
      {1000, nullptr, nullptr});
  thread_ = std::thread([this] {
    double next_status = monotonicSeconds() + 1.0;
    while (!stop_) {
      lcm_->handleTimeout(50);
      if (monotonicSeconds() < next_status) continue;
      next_status += 1.0;
      publish(channels::kBusStatus, bus::busStatus(program_, verifier_, wallMicros()));
    }
  });
}

BusFeed::~BusFeed() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void BusFeed::publishBytes(const std::string& channel, const std::string& bytes) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  out_->publish(channel, bytes.data(), bytes.size());
}

}  // namespace igms::web
