#include "haptic_client/app/haptic_client.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include "bus/bus_key.h"
#include "core/realtime/clock.h"
#include "core/realtime/realtime_priority.h"
#include "core/realtime/udp_drops.h"
#include "core/scene/resolved_scene.h"
#include "haptic_client/device/device_registry.h"
#include "haptic_client/device/scripted_device.h"
#include "haptic_client/servo/client_bus.h"
#include "haptic_client/servo/client_interaction.h"
#include "haptic_client/servo/client_status_thread.h"
#include "haptic_client/servo/servo_loop.h"

namespace igms {
namespace {

constexpr int kStoppedWaiting = -1;

// Waits for the server's status (its session token and link order) and checks it runs this scene's model:
// 0, an exit code, or kStoppedWaiting.
int connect(ClientBus& bus, const Model& model, const ClientOptions& o, const std::atomic<bool>& stop) {
  const double t0 = monotonicSeconds();
  if (!o.quiet)  // after the stop signal's handler: from here Ctrl-C or SIGTERM ends the wait cleanly
    std::fprintf(stderr, "igms-haptic: waiting up to %.0f s for igms-server's status on %s\n", o.connect_timeout,
                 o.lcm_url.c_str());
  while (!bus.haveServer() && !stop) {
    if (monotonicSeconds() - t0 > o.connect_timeout) {
      const bus::VerifierCounts c = bus.verifier().counts();
      std::fprintf(stderr, "igms-haptic: no server status on the bus within %.0f s%s\n", o.connect_timeout,
                   c.refusedTotal() > 0 ? " that passed the message check (see above: a missing or wrong --key-file?)"
                                        : "");
      return 3;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!bus.haveServer()) {  // stopped (Ctrl-C, SIGTERM) while waiting: nothing to compare
    std::fprintf(stderr, "igms-haptic: stopped before any server appeared\n");
    return kStoppedWaiting;
  }
  const size_t server_links = bus.serverLinkNames().size();
  if (server_links != model.frames.size()) {
    std::fprintf(stderr, "igms-haptic: the server's model has %zu links, the scene's %zu: not the same scene?\n",
                 server_links, model.frames.size());
    return 2;
  }
  return 0;
}

void printSummary(const ServoStats& s, double wall) {
  const auto cycles = static_cast<long long>(s.cycles.load());
  std::fprintf(stderr,
               "igms-haptic: %lld cycles in %.2f s (%.1f Hz), %lld deadline misses (max %lld in a row), %lld "
               "fallbacks, %lld late replies, max force step %.3f N (%lld cycles cut to the bound)\n"
               "igms-haptic: state age p50 %s ms, p99 %s ms, max %.2f ms; lowest energy balance %.4f J, "
               "passivity controller acted in %lld cycles, took out %.4f J\n"
               "igms-haptic: %lld cycles started over a period late (caught up), %lld periods skipped\n"
               "igms-haptic: round trip p50 %s us, p99 %s us, p99.9 %s us, max %.0f us (%lld replies); "
               "cycle jitter p50 %s us, p99 %s us, max %.0f us\n",
               cycles, wall, static_cast<double>(cycles) / wall, static_cast<long long>(s.misses.load()),
               static_cast<long long>(s.max_consecutive.load()), static_cast<long long>(s.fallbacks.load()),
               static_cast<long long>(s.late.load()), s.max_force_step.load(),
               static_cast<long long>(s.slew_limited.load()), quantileText(s.age_all, 0.5, 1e-3, 2).c_str(),
               quantileText(s.age_all, 0.99, 1e-3, 2).c_str(), s.age_all.max() * 1e-3, s.passivity_min_energy.load(),
               static_cast<long long>(s.passivity_acted.load()), s.passivity_dissipated.load(),
               static_cast<long long>(s.late_cycles.load()), static_cast<long long>(s.skipped_periods.load()),
               quantileText(s.rtt_all, 0.5).c_str(), quantileText(s.rtt_all, 0.99).c_str(),
               quantileText(s.rtt_all, 0.999).c_str(), s.rtt_all.max(), static_cast<long long>(s.rtt_all.count()),
               quantileText(s.jitter_all, 0.5).c_str(), quantileText(s.jitter_all, 0.99).c_str(), s.jitter_all.max());
  if (s.proxy_substep_limited.load() > 0)
    std::fprintf(stderr, "igms-haptic: the tip's proxy ran out of its substep budget in %lld cycles (caught up the next)\n",
                 static_cast<long long>(s.proxy_substep_limited.load()));
  if (s.local_runs.load() > 0)
    std::fprintf(stderr,
                 "igms-haptic: local model: %lld cycles estimated by it (%lld carried on after a solve at its sweep "
                 "limit, %lld at its compute budget), deepest overlap in its estimate %.3f mm\n",
                 static_cast<long long>(s.local_runs.load()), static_cast<long long>(s.local_cut_short.load()),
                 static_cast<long long>(s.local_over_budget.load()), s.local_max_penetration.load() * 1e3);
  const int64_t over = s.rtt_all.overflow() + s.jitter_all.overflow() + s.age_all.overflow();
  if (over)
    std::fprintf(stderr,
                 "igms-haptic: beyond the histograms' range: %lld round trips over %.0f ms, %lld cycle jitters over "
                 "%.0f ms, %lld state ages over %.0f ms (counted, their maxima exact)\n",
                 static_cast<long long>(s.rtt_all.overflow()), s.rtt_all.limit() * 1e-3,
                 static_cast<long long>(s.jitter_all.overflow()), s.jitter_all.limit() * 1e-3,
                 static_cast<long long>(s.age_all.overflow()), s.age_all.limit() * 1e-3);
}

// What the client renders to: the device's limits (or igms's defaults for a device that gives none),
// and the share of the coupling's force the hand feels when the scene's springs, at the device,
// are stiffer than it renders stably.
void printLimits(const DeviceLimits& l, const Scene& scene, double rate_hz) {
  char stiffness[32] = "unlimited (a simulated device)";
  if (std::isfinite(l.max_stiffness)) std::snprintf(stiffness, sizeof stiffness, "%.0f N/m", l.max_stiffness);
  std::fprintf(stderr,
               "igms-haptic: device limits: force %.2f N, step %.2f N a cycle, stiffness %s, torque %.2f N m, "
               "workspace [%.3f %.3f %.3f] .. [%.3f %.3f %.3f] m\n",
               l.max_force, l.max_force_step, stiffness, l.max_torque, l.workspace_min.x(), l.workspace_min.y(),
               l.workspace_min.z(), l.workspace_max.x(), l.workspace_max.y(), l.workspace_max.z());
  const double coupling = couplingStiffness(scene), share = stiffnessScale(l.max_stiffness, coupling);
  if (share < 1.0)
    std::fprintf(stderr,
                 "igms-haptic: coupling: the scene's springs are %.0f N/m at the device (k x workspace scale %.3g), over "
                 "its stable %.0f N/m: the hand feels %.3g of the force, the robot all of it\n",
                 coupling, scene.workspace_scale, l.max_stiffness, share);
  if (scene.push.enabled) {
    const double s = scene.workspace_scale * share;  // device metres to scene metres, and the share felt
    std::fprintf(stderr,
                 "igms-haptic: virtual coupling: k %.0f N/m, b %.3g N s/m (on the device: %.0f N/m, %.3g N s/m); "
                 "passive at %.0f Hz: b >= k T / 2 = %.3g N s/m\n",
                 scene.push.k_p, scene.push.b, scene.push.k_p * s, scene.push.b * s, rate_hz,
                 couplingMinDamping(scene, rate_hz));
  }
}

// The device's own calls as the loop timed them, and what it reported failed.
void printDeviceSummary(const ServoStats& s, const HapticDevice& device) {
  std::fprintf(stderr,
               "igms-haptic: device read p50 %s us, p99 %s us, max %.0f us; write p50 %s us, p99 %s us, max %.0f us; "
               "%lld overruns (calls over %.0f us), %lld failed calls",
               quantileText(s.device_read.all, 0.5).c_str(), quantileText(s.device_read.all, 0.99).c_str(),
               s.device_read.all.max(), quantileText(s.device_write.all, 0.5).c_str(),
               quantileText(s.device_write.all, 0.99).c_str(), s.device_write.all.max(),
               static_cast<long long>(s.device_read.overruns + s.device_write.overruns), DeviceCallTimes::kOverrunUs,
               static_cast<long long>(device.failedCalls()));
  if (device.readingsRejected() > 0)
    std::fprintf(stderr, ", %lld readings rejected", static_cast<long long>(device.readingsRejected()));
  if (s.blocked_reads > 0)
    std::fprintf(stderr, ", %lld reads blocked over 5 ms (the force ramped out as for a lost device)",
                 static_cast<long long>(s.blocked_reads.load()));
  std::fprintf(stderr, "\n");
  if (const std::string more = device.report(); !more.empty()) std::fprintf(stderr, "igms-haptic: %s\n", more.c_str());
}

// The device the options name, its link lookups reading the estimate's newest link poses.
std::unique_ptr<HapticDevice> makeDevice(const ClientOptions& o, const ResolvedScene& resolved, const StateEstimate& estimate,
                                         const std::vector<SE3>& links, const std::optional<bus::BusKey>& key) {
  const Model& model = *resolved.model;
  DeviceContext context{{resolved.scene.workspace_scale, resolved.scene.workspace_offset},
                        [&](const std::string& name, SE3* X) {
                          const int f = model.frameIndex(name);
                          if (f < 0 || !estimate.any()) return false;
                          *X = links[static_cast<size_t>(f)];
                          return true;
                        },
                        [&model](const std::string& name) { return model.frameIndex(name); }, o.lcm_url, key,
                        o.accept_replay};
  return DeviceRegistry::make(o.device, context);
}

// What the run leaves behind: the cycles' record (--record) and a script's targets (--export-targets).
// \return the exit code.
int writeOutputs(const ClientOptions& o, const ServoRecord& record, const ScriptedDevice* scripted) {
  if (!o.record.empty()) {
    std::string error;
    if (!record.write(o.record, &error)) {
      std::fprintf(stderr, "igms-haptic: --record %s\n", error.c_str());
      return 2;
    }
    if (record.dropped() > 0)
      std::fprintf(stderr, "igms-haptic: --record kept the first %zu cycles; %lld more were not recorded\n",
                   record.rows().size(), static_cast<long long>(record.dropped()));
  }
  if (!o.export_targets.empty()) {
    FILE* f = std::fopen(o.export_targets.c_str(), "w");
    const std::string text = scripted->pluginTargets();
    if (!f || std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fclose(f) != 0) {
      std::fprintf(stderr, "igms-haptic: --export-targets %s: cannot write it\n", o.export_targets.c_str());
      return 2;
    }
  }
  return 0;
}

}  // namespace

int runClient(const ClientOptions& o, const std::atomic<bool>& stop) {
  ResolvedScene resolved;
  FallbackPolicy policy;
  std::optional<bus::BusKey> key;
  try {
    key = bus::busKeyFor("igms-haptic", o.key_file);
    resolved = resolveScene(loadScene(o.scene_path));
    if (!parseFallback(o.fallback, &policy))
      throw std::runtime_error("--fallback is predict, hold, extrapolate or interpolate");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-haptic: %s\n", e.what());
    return 2;
  }
  for (const std::string& w : resolved.warnings) std::fprintf(stderr, "igms-haptic: warning: %s\n", w.c_str());
  const Model& model = *resolved.model;
  const int nlinks = static_cast<int>(model.frames.size());
  // Before any thread starts, so that every thread inherits it: a servo loop on SCHED_FIFO whose
  // bus thread an ordinary load can hold back still renders against late states.
  if (o.rt_priority > 0) requestRealtimeAndSay("igms-haptic", "every thread", o.rt_priority);
  ClientBus bus(o.lcm_url, nlinks, model.nq, model.nv, o.servo.client_id, key, o.accept_replay);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-haptic: cannot open LCM at %s\n", o.lcm_url.c_str());
    return 2;
  }
  // The estimate, shared by the device (link lookups) and the loop.
  StateEstimate estimate(model, policy, o.max_prediction_ms * 1e-3);
  std::vector<SE3> links(static_cast<size_t>(nlinks), SE3::Identity());
  std::unique_ptr<HapticDevice> device;
  try {
    device = makeDevice(o, resolved, estimate, links, key);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-haptic: %s\n", e.what());
    return 2;
  }
  // The scene's load checked the coupling at its own rate; the servo loop may run slower.
  const double rate = o.servo.rate_hz;
  if (resolved.scene.push.enabled && resolved.scene.push.b < couplingMinDamping(resolved.scene, rate)) {
    std::fprintf(stderr,
                 "igms-haptic: %s: interaction.coupling.b %.3g N s/m is below k T / 2 = %.3g N s/m at --rate %.0f Hz: "
                 "the coupling would not be passive (raise the damper or the rate)\n",
                 o.scene_path.c_str(), resolved.scene.push.b, couplingMinDamping(resolved.scene, rate), rate);
    return 2;
  }
  const auto* scripted = dynamic_cast<const ScriptedDevice*>(device.get());
  if (!o.export_targets.empty() && !scripted) {
    std::fprintf(stderr, "igms-haptic: --export-targets needs a scripted device (--device scripted:FILE)\n");
    return 2;
  }
  static ServoStats stats;  // large (histograms): static storage, one client per process
  ClientStatusThread status(bus, stats, *device,
                            ClientIdentity{o.servo.client_id, device->name(), fallbackName(policy), o.servo.lost_ms});
  if (const int code = connect(bus, model, o, stop)) return code == kStoppedWaiting ? 0 : code;
  if (!o.quiet)
    std::fprintf(stderr, "igms-haptic: %s on %s, %.0f Hz, deadline %.0f us, fallback %s\n", device->name().c_str(),
                 o.scene_path.c_str(), rate, o.servo.deadline_us, fallbackName(policy));
  if (!o.quiet) printLimits(device->limits(), resolved.scene, rate);
  // The record's rows, allocated now: the run's cycles (a duration, or a script's end), else 10 minutes'.
  const double record_s = o.servo.duration > 0 ? o.servo.duration : scripted ? scripted->endTime() : 600.0;
  ServoRecord record(o.record.empty() ? 0 : static_cast<int64_t>(record_s * rate) + 2);
  ServoLoop loop(resolved, *device, bus, estimate, links, stats,
                 o.servo, &record);
  const double wall = loop.run(stop);
  stats.finished = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // one more status
  if (!o.quiet) {
    printSummary(stats, wall);
    printDeviceSummary(stats, *device);
  }
  if (!o.quiet || bus.verifier().keyed() || bus.verifier().counts().refusedTotal() > 0) {
    std::fprintf(stderr, "igms-haptic: bus: %s\n", bus.verifier().summary().c_str());
    // A late reply is a state that came after a newer one: on a signed bus, only a state this
    // client missed (lost on its socket) can come again, replayed, and be late; these say how many.
    std::fprintf(stderr, "igms-haptic: %lld states missed (gaps in their seq), %lld datagrams dropped on full sockets\n",
                 static_cast<long long>(bus.statesMissed()), static_cast<long long>(ownUdpDrops()));
  }
  if (bus.undecodable() > 0)
    std::fprintf(stderr, "igms-haptic: %lld messages could not be decoded and were ignored\n",
                 static_cast<long long>(bus.undecodable()));
  return writeOutputs(o, record, scripted);
}

}  // namespace igms
