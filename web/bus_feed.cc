#include "web/bus_feed.h"

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "core/realtime/clock.h"

namespace igms::web {
namespace {

void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel, BusView* view) {
  view->handle(channel, rbuf->data, rbuf->data_size, monotonicSeconds());
}

}  // namespace

BusFeed::BusFeed(const std::string& url, BusView& view) : lcm_(std::make_unique<lcm::LCM>(url)), view_(view) {
  if (!lcm_->good()) throw std::runtime_error("cannot open LCM at " + url);
  lcm::Subscription* sub = lcm_->subscribeFunction<BusView*>(".*", &onMessage, &view_);
  sub->setQueueCapacity(1000);
  thread_ = std::thread([this] {
    while (!stop_) lcm_->handleTimeout(50);
  });
}

BusFeed::~BusFeed() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void BusFeed::publishBytes(const std::string& channel, const std::string& bytes) {
  lcm_->publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size()));
}

}  // namespace igms::web
