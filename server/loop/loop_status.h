// What the loop tells the status reporter: counters (atomics, written by the
// loop only) and the state words (a mutex the step itself never takes: they
// change between steps).
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace igms {

class LoopStatus {
 public:
  std::atomic<int64_t> steps{0}, overruns{0}, forces_clamped{0}, consumed_inputs{0}, ring_drops{0};
  std::atomic<int64_t> commands_rejected{0};
  std::atomic<int64_t> resume_ramps{0};

  // "running", "lockstep", "paused", "diverged", "stopped"; message: the last error or report.
  void setState(const std::string& state) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = state;
    message_.clear();
  }
  void setState(const std::string& state, const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = state;
    message_ = message;
  }
  void setMessage(const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    message_ = message;
  }
  void read(std::string* state, std::string* message) {
    std::lock_guard<std::mutex> lock(mutex_);
    *state = state_;
    *message = message_;
  }

 private:
  std::mutex mutex_;
  std::string state_ = "running", message_;
};

}  // namespace igms
