// The servo loop's figures, written by the loop (no lock, no allocation) and
// read by the status thread: counters, short windows of samples (p50, p99,
// max since the last status) and whole-run histograms.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace igms {

// Samples of one statistic, written by the servo loop, read by the status thread.
class SampleRing {
 public:
  void push(double x) {
    const uint64_t i = n_.load(std::memory_order_relaxed);
    v_[i % v_.size()].store(x, std::memory_order_relaxed);
    n_.store(i + 1, std::memory_order_release);
  }
  // p50, p99, max of the samples since the last call (the reader's side: allocates).
  std::array<double, 3> drain() {
    const uint64_t n = n_.load(std::memory_order_acquire);
    const uint64_t from = std::max(read_, n > v_.size() ? n - v_.size() : 0);
    std::vector<double> s;
    for (uint64_t i = from; i < n; ++i) s.push_back(v_[i % v_.size()].load(std::memory_order_relaxed));
    read_ = n;
    if (s.empty()) return {0, 0, 0};
    std::sort(s.begin(), s.end());
    return {s[s.size() / 2], s[std::min(s.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(s.size())))],
            s.back()};
  }

 private:
  std::array<std::atomic<double>, 4096> v_{};
  std::atomic<uint64_t> n_{0};
  uint64_t read_ = 0;
};

// Whole-run distribution of a time in microseconds: 20 000 bins of bin_us
// (1 us: up to 20 ms), preallocated, filled by the servo loop, read at the end.
// What lands beyond the last bin is counted as overflow, never as the last
// bin's value: a quantile there is +infinity, and the maximum is kept exactly.
class Histogram {
 public:
  explicit Histogram(double bin_us = 1.0) : bin_us_(bin_us) {}
  void add(double us) {
    max_ = std::max(max_, us);
    ++n_;
    if (!(us < limit())) {
      ++overflow_;
      return;
    }
    ++bins_[static_cast<size_t>(std::max(0.0, us / bin_us_))];
  }
  // The p-quantile (bin floor), +infinity when it lies in the overflow.
  double percentile(double p) const {
    const auto want = static_cast<int64_t>(p * static_cast<double>(n_));
    int64_t seen = 0;
    for (size_t b = 0; b < bins_.size(); ++b)
      if ((seen += bins_[b]) > want) return static_cast<double>(b) * bin_us_;
    return n_ ? std::numeric_limits<double>::infinity() : 0.0;
  }
  double max() const { return max_; }  // exact, also beyond the bins
  int64_t count() const { return n_; }
  int64_t overflow() const { return overflow_; }
  double limit() const { return static_cast<double>(bins_.size()) * bin_us_; }

 private:
  double bin_us_;
  std::array<int64_t, 20000> bins_{};
  int64_t n_ = 0, overflow_ = 0;
  double max_ = 0.0;
};

// "123" (scaled by `scale`, `decimals` places), or "> 20000" when the value
// is beyond the histogram's range.
inline std::string quantileText(const Histogram& h, double p, double scale = 1.0, int decimals = 0) {
  const double v = h.percentile(p);
  char out[48];
  if (std::isinf(v)) std::snprintf(out, sizeof out, "> %.*f", decimals, h.limit() * scale);
  else std::snprintf(out, sizeof out, "%.*f", decimals, v * scale);
  return out;
}

// One kind of device call (read or write), timed by the servo loop: the last status period's
// samples, the whole run's distribution, and its maximum where the status thread may read it.
struct DeviceCallTimes {
  static constexpr double kOverrunUs = 100.0;  // a call longer than this is an overrun
  SampleRing recent;
  Histogram all;
  std::atomic<double> max{0};
  std::atomic<int64_t> overruns{0};
  void add(double us) {
    recent.push(us);
    all.add(us);
    if (us > max.load(std::memory_order_relaxed)) max.store(us, std::memory_order_relaxed);
    if (us > kOverrunUs) overruns.fetch_add(1, std::memory_order_relaxed);
  }
};

struct ServoStats {
  std::atomic<int64_t> cycles{0}, misses{0}, max_consecutive{0}, fallbacks{0}, late{0}, slew_limited{0},
      passivity_acted{0}, late_cycles{0}, skipped_periods{0}, proxy_substep_limited{0};
  std::atomic<double> state_age_ms{0}, prediction_ms{0}, force_scale{1}, max_force_step{0}, passivity_dissipated{0},
      passivity_min_energy{0};
  std::atomic<int> mode{0};
  std::atomic<double> force[3] = {0, 0, 0};
  std::atomic<double> torque[3] = {0, 0, 0};  // N m rendered (a 6-dof device's 6-D pull)
  std::atomic<int64_t> phase_shifts{0};        // the loop's phase moved after another hand's (servo_loop.cc)
  std::atomic<int64_t> blocked_reads{0};       // device reads over ServoConfig::blocked_read_ms: the force ramped out
  // The local model (predict): the steps of its last run, and the deepest overlap its estimate put two things in, m.
  std::atomic<int> local_steps{0};
  std::atomic<int64_t> local_runs{0};
  std::atomic<double> local_max_penetration{0};
  std::atomic<int64_t> local_cut_short{0};  // runs stopped after a step whose solve hit its sweep limit
  std::atomic<int64_t> local_over_budget{0};  // runs stopped at the local model's compute budget
  std::atomic<bool> lost{false}, device_lost{false}, finished{false};
  SampleRing jitter, rtt, age_us;
  Histogram rtt_all{10.0};  // 10 us bins: round trips up to 200 ms
  Histogram jitter_all;
  Histogram age_all{10.0};  // 10 us bins: state ages up to 200 ms
  // The device's own calls, timed by the loop around read and write (a plugin's must not block).
  DeviceCallTimes device_read, device_write;
};

}  // namespace igms
