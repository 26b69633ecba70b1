// A recorded session played into the browser view: a playhead over the log's
// time (seconds from its first event) that runs at a chosen speed, pauses and
// seeks. Seeking hands the view the newest message of each channel at or
// before the new time, so the drawn pose is the log's pose at that time.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tools/eventlog/event_log.h"
#include "web/bus_view.h"

namespace igms {

class LogPlayer {
 public:
  // Throws igms::log::LogError when the log cannot be read at all; a damaged
  // tail is reported on stderr and the events before it play.
  LogPlayer(const std::string& path, web::BusView& view);
  ~LogPlayer();

  void play();
  void pause();
  void seek(double t);   // clamped to [0, duration]
  void speed(double s);  // 0.05 .. 20
  double duration() const { return duration_; }
  double time() const;   // the playhead, s
  // ,"timeline":{...} for the frames.
  std::string timelineJson() const;

 private:
  void run();
  void feedUntil(double t);  // forward from the current index

  std::vector<log::Event> events_;
  std::string name_;
  web::BusView& view_;
  int64_t t0_ = 0;
  double duration_ = 0.0;
  mutable std::mutex mutex_;
  double playhead_ = 0.0, speed_ = 1.0;
  bool playing_ = true;
  size_t next_ = 0;  // the first event not yet fed
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace igms
