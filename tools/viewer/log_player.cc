#include "tools/viewer/log_player.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

namespace igms {

LogPlayer::LogPlayer(const std::string& path, web::BusView& view) : view_(view) {
  log::LogContents contents = log::readAll(path);
  if (contents.damaged)
    std::fprintf(stderr, "igms-viewer: %s: %s at byte %llu; playing the %zu events before it\n", path.c_str(),
                 contents.error.c_str(), static_cast<unsigned long long>(contents.error_offset),
                 contents.events.size());
  events_ = std::move(contents.events);
  if (events_.empty()) throw log::LogError(path + ": no events", 0);
  std::stable_sort(events_.begin(), events_.end(),
                   [](const log::Event& a, const log::Event& b) { return a.utime < b.utime; });
  t0_ = events_.front().utime;
  duration_ = static_cast<double>(events_.back().utime - t0_) * 1e-6;
  const size_t slash = path.rfind('/');
  name_ = slash == std::string::npos ? path : path.substr(slash + 1);
  thread_ = std::thread([this] { run(); });
}

LogPlayer::~LogPlayer() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void LogPlayer::play() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (playhead_ >= duration_) {  // at the end: from the start again
    view_.clear();
    next_ = 0;
    playhead_ = 0.0;
  }
  playing_ = true;
}

void LogPlayer::pause() {
  std::lock_guard<std::mutex> lock(mutex_);
  playing_ = false;
}

void LogPlayer::speed(double s) {
  std::lock_guard<std::mutex> lock(mutex_);
  speed_ = std::clamp(s, 0.05, 20.0);
}

double LogPlayer::time() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return playhead_;
}

void LogPlayer::seek(double t) {
  std::lock_guard<std::mutex> lock(mutex_);
  playhead_ = std::clamp(t, 0.0, duration_);
  const int64_t until = t0_ + static_cast<int64_t>(playhead_ * 1e6 + 0.5);
  next_ = static_cast<size_t>(std::upper_bound(events_.begin(), events_.end(), until,
                                               [](int64_t u, const log::Event& e) { return u < e.utime; }) -
                              events_.begin());
  // The newest message of each channel at or before the playhead, oldest first.
  std::map<std::string, size_t> newest;
  for (size_t i = 0; i < next_; ++i) newest[events_[i].channel] = i;
  std::vector<size_t> order;
  for (const auto& [channel, i] : newest) order.push_back(i);
  std::sort(order.begin(), order.end());
  view_.clear();
  for (size_t i : order) {
    const log::Event& e = events_[i];
    view_.handle(e.channel, e.data.data(), e.data.size(), static_cast<double>(e.utime - t0_) * 1e-6);
  }
}

void LogPlayer::feedUntil(double t) {
  const int64_t until = t0_ + static_cast<int64_t>(t * 1e6 + 0.5);
  while (next_ < events_.size() && events_[next_].utime <= until) {
    const log::Event& e = events_[next_++];
    view_.handle(e.channel, e.data.data(), e.data.size(), static_cast<double>(e.utime - t0_) * 1e-6);
  }
}

void LogPlayer::run() {
  auto last = std::chrono::steady_clock::now();
  while (!stop_) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const auto now = std::chrono::steady_clock::now();
    const double wall = std::chrono::duration<double>(now - last).count();
    last = now;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!playing_) continue;
    playhead_ = std::min(duration_, playhead_ + wall * speed_);
    feedUntil(playhead_);
    if (playhead_ >= duration_) playing_ = false;
  }
}

std::string LogPlayer::timelineJson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  char buf[256];
  std::snprintf(buf, sizeof buf, ",\"timeline\":{\"t\":%.4f,\"end\":%.4f,\"playing\":%s,\"speed\":%.3g,\"log\":\"",
                playhead_, duration_, playing_ ? "true" : "false", speed_);
  std::string s = buf;
  for (char c : name_) s += (c == '"' || c == '\\' || c < 0x20) ? '_' : c;
  return s + "\"}";
}

}  // namespace igms
