#include "haptic_client/servo/client_status_thread.h"

#include <cstdio>

#include "bus/bus_status.h"
#include "channels.h"
#include "core/realtime/clock.h"
#include "core/realtime/udp_drops.h"
#include "igms/client_status_t.hpp"
#include "igms/device_status_t.hpp"

namespace igms {

ClientStatusThread::ClientStatusThread(ClientBus& bus, ServoStats& stats, const HapticDevice& device,
                                       ClientIdentity who)
    : bus_(bus), stats_(stats), device_(device), limits_(device.limits()), who_(std::move(who)),
      last_t_(monotonicSeconds()) {
  thread_ = std::thread([this] { run(); });
}

ClientStatusThread::~ClientStatusThread() {
  stop_ = true;
  thread_.join();
}

void ClientStatusThread::run() {
  double next_status = monotonicSeconds() + 0.1;
  bool was_lost = false, device_was_lost = false;
  while (!stop_) {
    bus_.lcm().handleTimeout(5);
    const double now = monotonicSeconds();
    if (stats_.lost != was_lost) {
      was_lost = stats_.lost;
      if (was_lost)
        std::fprintf(stderr, "igms-haptic: server lost (no state for %.0f ms): forces ramping down\n", who_.lost_ms);
      else
        std::fprintf(stderr, "igms-haptic: server back: forces ramping up\n");
    }
    if (stats_.device_lost != device_was_lost) {  // a bus device's readings stopped, or came back
      device_was_lost = stats_.device_lost;
      std::fprintf(stderr, device_was_lost
                               ? "igms-haptic: device lost (its readings stopped, or a read blocked): forces ramping down\n"
                               : "igms-haptic: device back: forces ramping up\n");
    }
    if (now < next_status) continue;
    next_status += 0.1;
    publishStatus(now);
  }
}

void ClientStatusThread::publishStatus(double now) {
  client_status_t s;
  s.utime = wallMicros();
  s.seq = seq_++;
  s.client_id = who_.client_id;
  s.device = who_.device;
  s.fallback = who_.fallback;
  s.state = stats_.finished ? "finished" : stats_.lost ? "server_lost" : "running";
  s.cycles = stats_.cycles;
  s.rate_hz = static_cast<double>(s.cycles - last_cycles_) / (now - last_t_);
  last_cycles_ = s.cycles;
  last_t_ = now;
  const auto j = stats_.jitter.drain(), r = stats_.rtt.drain();
  s.jitter_us_p50 = j[0]; s.jitter_us_p99 = j[1]; s.jitter_us_max = j[2];
  s.rtt_us_p50 = r[0]; s.rtt_us_p99 = r[1]; s.rtt_us_max = r[2];
  s.deadline_misses = stats_.misses;
  s.max_consecutive_misses = stats_.max_consecutive;
  s.fallbacks = stats_.fallbacks;
  s.late_replies = stats_.late;
  s.state_age_ms = stats_.state_age_ms;
  s.force_scale = stats_.force_scale;
  s.max_force_step = stats_.max_force_step;
  s.mode = static_cast<int8_t>(stats_.mode.load());
  for (int k = 0; k < 3; ++k) s.rendered_force[k] = stats_.force[k];
  s.undecodable = bus_.undecodable();
  const auto a = stats_.age_us.drain();
  s.state_age_ms_p50 = a[0] * 1e-3; s.state_age_ms_p99 = a[1] * 1e-3; s.state_age_ms_max = a[2] * 1e-3;
  s.prediction_ms = stats_.prediction_ms;
  s.force_slew_limited = stats_.slew_limited;
  s.passivity_acted = stats_.passivity_acted;
  s.proxy_substep_limited = stats_.proxy_substep_limited;
  s.passivity_dissipated = stats_.passivity_dissipated;
  s.late_cycles = stats_.late_cycles;
  s.skipped_periods = stats_.skipped_periods;
  s.states_missed = bus_.statesMissed();
  s.socket_drops = ownUdpDrops();
  bus_.statusOut().publish(channels::kClientStatus, s);
  if (s.seq % 10 == 0) {
    bus_.statusOut().publish(channels::kBusStatus, bus::busStatus("igms-haptic", bus_.verifier(), s.utime));
    publishDeviceStatus(s.utime);
  }
}

void ClientStatusThread::publishDeviceStatus(int64_t utime) {
  device_status_t d{};
  d.utime = utime;
  d.client_id = who_.client_id;
  d.device = who_.device;
  const auto r = stats_.device_read.recent.drain(), w = stats_.device_write.recent.drain();
  d.read_us_p50 = r[0]; d.read_us_p99 = r[1]; d.read_us_max = r[2];
  d.write_us_p50 = w[0]; d.write_us_p99 = w[1]; d.write_us_max = w[2];
  d.read_us_max_all = stats_.device_read.max;
  d.write_us_max_all = stats_.device_write.max;
  d.overruns = stats_.device_read.overruns + stats_.device_write.overruns;
  d.failed_calls = device_.failedCalls();
  d.readings_rejected = device_.readingsRejected();
  d.reading_age_ms = device_.readingAgeMs();
  d.max_force = limits_.max_force;
  d.max_force_step = limits_.max_force_step;
  d.max_stiffness = limits_.max_stiffness;
  d.max_torque = limits_.max_torque;
  for (int k = 0; k < 3; ++k) {
    d.workspace_min[k] = limits_.workspace_min[k];
    d.workspace_max[k] = limits_.workspace_max[k];
  }
  bus_.statusOut().publish(channels::kDeviceStatus, d);
}

}  // namespace igms
