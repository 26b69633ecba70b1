#include "haptic_client/servo/haptic_client.h"

#include <sched.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <thread>
#include <vector>

#include "channels.h"
#include "haptic_client/device/replay_device.h"
#include "haptic_client/device/scripted_device.h"
#include "haptic_client/servo/client_interaction.h"
#include "haptic_client/servo/state_estimate.h"
#include "igms/client_status_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "core/scene/resolved_scene.h"
#include "core/scene/scene.h"
#include "core/realtime/clock.h"
#include "core/realtime/triple_buffer.h"

namespace igms {
namespace {

struct Received {
  RobotSample sample;
  double received = 0.0;  // monotonic s
};

// Samples of one statistic, written by the servo loop, read by the status thread.
class SampleRing {
 public:
  void push(double x) {
    const uint64_t i = n_.load(std::memory_order_relaxed);
    v_[i % v_.size()].store(x, std::memory_order_relaxed);
    n_.store(i + 1, std::memory_order_release);
  }
  // p50, p99, max of the samples since the last call.
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

// Whole-run distribution of a time in microseconds: 1 us bins up to 20 ms,
// preallocated, filled by the servo loop, read at the end.
class Histogram {
 public:
  void add(double us) { ++bins_[static_cast<size_t>(std::clamp(us, 0.0, static_cast<double>(bins_.size() - 1)))]; ++n_; }
  double percentile(double p) const {
    const auto want = static_cast<int64_t>(p * static_cast<double>(n_));
    int64_t seen = 0;
    for (size_t b = 0; b < bins_.size(); ++b)
      if ((seen += bins_[b]) > want) return static_cast<double>(b);
    return static_cast<double>(bins_.size() - 1);
  }
  double max() const {
    for (size_t b = bins_.size(); b-- > 0;)
      if (bins_[b]) return static_cast<double>(b);
    return 0.0;
  }
  int64_t count() const { return n_; }

 private:
  std::array<int64_t, 20000> bins_{};
  int64_t n_ = 0;
};

struct Stats {
  std::atomic<int64_t> cycles{0}, misses{0}, max_consecutive{0}, fallbacks{0}, late{0};
  std::atomic<double> state_age_ms{0}, force_scale{1}, max_force_step{0};
  std::atomic<int> mode{0};
  std::atomic<double> force[3] = {0, 0, 0};
  std::atomic<bool> lost{false}, finished{false};
  SampleRing jitter, rtt;
  Histogram rtt_all, jitter_all;
};

class Bus {
 public:
  Bus(const std::string& url, Received initial) : lcm_(url), states_(initial) {}
  bool good() { return lcm_.good(); }
  lcm::LCM& lcm() { return lcm_; }

  void onState(const lcm::ReceiveBuffer*, const std::string&, const robot_state_t* m) {
    Received& r = states_.back();
    RobotSample& s = r.sample;
    if (static_cast<size_t>(m->nlinks) != s.links.size() || static_cast<size_t>(m->nq) != s.q.size()) return;
    s.seq = m->seq;
    s.input_seq = m->input_seq;
    s.sim_time = m->sim_time;
    for (size_t k = 0; k < s.links.size(); ++k) {
      const auto& p = m->link_poses[k];
      s.links[k].p = Vector3(p[0], p[1], p[2]);
      s.links[k].R = Eigen::Quaterniond(p[3], p[4], p[5], p[6]).normalized().toRotationMatrix();
    }
    std::copy(m->q.begin(), m->q.end(), s.q.begin());
    r.received = monotonicSeconds();
    states_.publish();
  }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const server_status_t* m) {
    token_ = m->session_token;
    have_token_ = true;
    link_names_ = m->link_names;
  }

  TripleBuffer<Received>& states() { return states_; }
  std::atomic<int64_t> token_{0};
  std::atomic<bool> have_token_{false};
  std::vector<std::string> link_names_;

 private:
  lcm::LCM lcm_;
  TripleBuffer<Received> states_;
};

}  // namespace

int runClient(const ClientOptions& o, const std::atomic<bool>& stop) {
  ResolvedScene resolved;
  FallbackPolicy policy;
  try {
    resolved = resolveScene(loadScene(o.scene_path));
    if (!parseFallback(o.fallback, &policy)) throw std::runtime_error("--fallback is hold, extrapolate or interpolate");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-haptic: %s\n", e.what());
    return 2;
  }
  const Scene& scene = resolved.scene;
  const Model* model = resolved.model.get();
  const int nlinks = static_cast<int>(model->frames.size());
  Received initial;
  initial.sample.links.assign(static_cast<size_t>(nlinks), SE3::Identity());
  initial.sample.q.assign(static_cast<size_t>(model->nq), 0.0);
  Bus bus(o.lcm_url.empty() ? channels::kDefaultUrl : o.lcm_url, initial);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-haptic: cannot open LCM at %s\n", o.lcm_url.c_str());
    return 2;
  }
  bus.lcm().subscribe(channels::kRobotState, &Bus::onState, &bus)->setQueueCapacity(100);
  bus.lcm().subscribe(channels::kServerStatus, &Bus::onStatus, &bus);

  // The estimate, shared by the device script (link lookups) and the loop.
  StateEstimate estimate(nlinks, model->nq, policy);
  std::vector<SE3> links(static_cast<size_t>(nlinks), SE3::Identity());
  WorkspaceMap map{scene.workspace_scale, scene.workspace_offset};
  std::unique_ptr<HapticDevice> device;
  try {
    if (o.device.rfind("replay:", 0) == 0) {
      device = std::make_unique<ReplayDevice>(o.device.substr(7), map);
    } else if (o.device.rfind("scripted:", 0) != 0) {
      throw std::runtime_error("--device must be scripted:FILE or replay:LOG (no real device driver is built)");
    } else device = std::make_unique<ScriptedDevice>(o.device.substr(9), map, [&](const std::string& name, SE3* X) {
      const int f = model->frameIndex(name);
      if (f < 0 || !estimate.any()) return false;
      *X = links[static_cast<size_t>(f)];
      return true;
    });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-haptic: %s\n", e.what());
    return 2;
  }

  // Bus thread: states, status in; client status out at 10 Hz.
  static Stats stats;  // large (histograms): static storage, one client per process
  std::atomic<bool> bus_stop{false};
  std::thread bus_thread([&] {
    double next_status = monotonicSeconds() + 0.1;
    int64_t seq = 0, last_cycles = 0;
    bool was_lost = false;
    double last_t = monotonicSeconds();
    while (!bus_stop) {
      bus.lcm().handleTimeout(5);
      const double now = monotonicSeconds();
      if (stats.lost != was_lost) {  // said here, not in the servo loop (no I/O there)
        was_lost = stats.lost;
        if (was_lost) std::fprintf(stderr, "igms-haptic: server lost (no state for %.0f ms): forces ramping down\n", o.lost_ms);
        else std::fprintf(stderr, "igms-haptic: server back: forces ramping up\n");
      }
      if (now < next_status) continue;
      next_status += 0.1;
      client_status_t s;
      s.utime = wallMicros();
      s.seq = seq++;
      s.client_id = o.client_id;
      s.device = device->name();
      s.fallback = fallbackName(policy);
      s.state = stats.finished ? "finished" : stats.lost ? "server_lost" : "running";
      s.cycles = stats.cycles;
      s.rate_hz = static_cast<double>(s.cycles - last_cycles) / (now - last_t);
      last_cycles = s.cycles;
      last_t = now;
      const auto j = stats.jitter.drain(), r = stats.rtt.drain();
      s.jitter_us_p50 = j[0]; s.jitter_us_p99 = j[1]; s.jitter_us_max = j[2];
      s.rtt_us_p50 = r[0]; s.rtt_us_p99 = r[1]; s.rtt_us_max = r[2];
      s.deadline_misses = stats.misses;
      s.max_consecutive_misses = stats.max_consecutive;
      s.fallbacks = stats.fallbacks;
      s.late_replies = stats.late;
      s.state_age_ms = stats.state_age_ms;
      s.force_scale = stats.force_scale;
      s.max_force_step = stats.max_force_step;
      s.mode = static_cast<int8_t>(stats.mode.load());
      for (int k = 0; k < 3; ++k) s.rendered_force[k] = stats.force[k];
      bus.lcm().publish(channels::kClientStatus, &s);
    }
  });
  auto finish = [&](int code) {
    bus_stop = true;
    bus_thread.join();
    return code;
  };

  // Wait for the server (its session token and link order).
  const double t_connect = monotonicSeconds();
  while (!bus.have_token_ && !stop) {
    if (monotonicSeconds() - t_connect > o.connect_timeout) {
      std::fprintf(stderr, "igms-haptic: no server status on the bus within %.0f s\n", o.connect_timeout);
      return finish(3);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (bus.link_names_.size() != model->frames.size()) {
    std::fprintf(stderr, "igms-haptic: the server's model has %zu links, the scene's %zu: not the same scene?\n",
                 bus.link_names_.size(), model->frames.size());
    return finish(2);
  }
  if (!o.quiet)
    std::fprintf(stderr, "igms-haptic: %s on %s, %.0f Hz, deadline %.0f us, fallback %s\n", device->name().c_str(),
                 o.scene_path.c_str(), o.rate_hz, o.deadline_us, fallbackName(policy));

  const double period = 1.0 / o.rate_hz;
  const double sim_dt = scene.dt;
  lcm::LCM& lcm = bus.lcm();
  haptic_input_t msg{};
  msg.client_id = o.client_id;
  msg.tip_radius = scene.push.tip_radius;
  ClientInteraction interaction(resolved);
  int64_t consecutive = 0;
  double expected_time = 0.0;
  const DeviceLimits limits = device->limits();
  std::vector<uint8_t> buffer(static_cast<size_t>(msg.getEncodedSize()) + 256);

  const double start = monotonicSeconds();
  timespec next;
  clock_gettime(CLOCK_MONOTONIC, &next);
  for (int64_t k = 1; !stop; ++k) {
    const double t = static_cast<double>(k - 1) * period;
    if ((o.duration > 0 && t >= o.duration) || (o.duration <= 0 && device->finished(t))) break;
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
    const double cycle_start = monotonicSeconds();
    stats.jitter.push(std::abs(cycle_start - (start + t)) * 1e6);
    stats.jitter_all.add(std::abs(cycle_start - (start + t)) * 1e6);

    // 1. The device, mapped into the scene.
    const DeviceReading reading = device->read(t);
    const Vector3 tip = map.toScene(reading.position);
    const Vector3 tip_velocity = map.scale * reading.velocity;

    // 2. The input: pull while the button is held, push when the tip touches a link.
    interaction.fillInput(tip, tip_velocity, reading.buttons, links, msg);
    msg.utime = wallMicros();
    msg.seq = k;
    msg.session_token = bus.token_;
    const int8_t mode = msg.mode;
    msg.last_state_seq = estimate.any() ? estimate.newest().seq : -1;
    const int n = msg.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
    const double sent = monotonicSeconds();
    if (n > 0) lcm.publish(channels::kHapticInput, buffer.data(), static_cast<unsigned>(n));

    // 3. This cycle's state, until the deadline.
    bool on_time = false;
    const double deadline = cycle_start + o.deadline_us * 1e-6;
    for (;;) {
      Received* r = nullptr;
      if (bus.states().take(&r)) {
        if (!estimate.offer(r->sample)) ++stats.late;
        if (r->sample.input_seq >= k) {
          on_time = true;
          stats.rtt.push((r->received - sent) * 1e6);
          stats.rtt_all.add((r->received - sent) * 1e6);
        }
      }
      if (on_time || monotonicSeconds() >= deadline) break;
      // Within the deadline window: yield rather than sleep (a sleep's wake-up
      // costs tens of microseconds on a VM), so the bus thread runs at once.
      sched_yield();
    }
    if (estimate.any()) {
      // The reply to input k is the state one simulation step after the reply to k-1.
      expected_time = on_time ? estimate.newest().sim_time : expected_time + sim_dt;
      bool fallback = false;
      estimate.estimate(expected_time, links, &fallback);
      if (fallback) ++stats.fallbacks;
    }
    const bool resynced = on_time && consecutive >= 3;
    if (on_time) {
      consecutive = 0;
    } else {
      ++stats.misses;
      stats.max_consecutive = std::max<int64_t>(stats.max_consecutive, ++consecutive);
    }

    // 4. The force against the estimate; render its reaction.
    const Vector3 on_user =
        estimate.any() ? interaction.userForce(links, expected_time, tip, tip_velocity) : Vector3::Zero();
    // Lost: no state for lost_ms; the force ramps down, and back up when states return.
    const bool lost = estimate.any() && static_cast<double>(consecutive) * period * 1e3 > o.lost_ms;
    stats.lost = lost;
    const Vector3 rendered = interaction.render(on_user, lost, resynced, period, limits.max_force);
    device->write(rendered);  // scene axes = device axes (the mapping scales positions only)
    stats.max_force_step = interaction.maxForceStep();
    stats.force_scale = interaction.forceScale();
    stats.mode = mode;
    for (int i = 0; i < 3; ++i) stats.force[i] = rendered[i];
    stats.state_age_ms = static_cast<double>(consecutive) * period * 1e3;
    ++stats.cycles;

    next.tv_nsec += static_cast<long>(period * 1e9);
    while (next.tv_nsec >= 1000000000L) {
      next.tv_nsec -= 1000000000L;
      ++next.tv_sec;
    }
  }
  const double wall = monotonicSeconds() - start;
  stats.finished = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // one more status
  if (!o.quiet)
    std::fprintf(stderr,
                 "igms-haptic: %lld cycles in %.2f s (%.1f Hz), %lld deadline misses (max %lld in a row), %lld "
                 "fallbacks, %lld late replies, max force step %.3f N\n"
                 "igms-haptic: round trip p50 %.0f us, p99 %.0f us, p99.9 %.0f us, max %.0f us (%lld replies); "
                 "cycle jitter p50 %.0f us, p99 %.0f us, max %.0f us\n",
                 static_cast<long long>(stats.cycles.load()), wall, static_cast<double>(stats.cycles.load()) / wall,
                 static_cast<long long>(stats.misses.load()), static_cast<long long>(stats.max_consecutive.load()),
                 static_cast<long long>(stats.fallbacks.load()), static_cast<long long>(stats.late.load()),
                 stats.max_force_step.load(), stats.rtt_all.percentile(0.5), stats.rtt_all.percentile(0.99),
                 stats.rtt_all.percentile(0.999), stats.rtt_all.max(), static_cast<long long>(stats.rtt_all.count()),
                 stats.jitter_all.percentile(0.5), stats.jitter_all.percentile(0.99), stats.jitter_all.max());
  return finish(0);
}

}  // namespace igms
