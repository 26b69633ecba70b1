#include "server/app/status_reporter.h"

#include <algorithm>
#include <cstdio>

#include "bus/bus_status.h"
#include "channels.h"
#include "core/realtime/clock.h"
#include "core/realtime/udp_drops.h"
#include "igms/haptic_input_t.hpp"
#include "igms/server_status_t.hpp"
#include "igms_build_info.h"
#include "server/app/session_description.h"

namespace igms {

StatusReporter::StatusReporter(bus::SignedPublisher& bus, const Simulation& sim, const std::string& clock, BusReceiver& receiver,
                               LoopStatus& loop, bool quiet, double hold_s)
    : bus_(bus), receiver_(receiver), loop_(loop), quiet_(quiet), hold_s_(hold_s), scene_(sim.scene().source) {
  info_ = describeSession(sim, clock);
  files_ = describeSessionFiles(sim);
  for (const auto& f : sim.model().frames) link_names_.push_back(f.name);
  components_ = sim.activeComponents();
  window_start_ = monotonicSeconds();
  next_status_ = window_start_ + 0.1;
}

void StatusReporter::requestSessionInfo(int64_t token) {
  token_ = token;
  info_due_ = true;
}

void StatusReporter::pumpSessionInfo() {
  if (!info_due_.exchange(false)) return;
  info_.utime = wallMicros();
  info_.session_token = token_;
  bus_.publish(channels::kSessionInfo, info_);
  files_.utime = info_.utime;
  files_.session_token = token_;
  bus_.publish(channels::kSessionFiles, files_);
}

void StatusReporter::pumpStatus(PublishStats& published) {
  if (monotonicSeconds() >= next_status_) {
    publishStatus(published);
    next_status_ += 0.1;
  }
}

void StatusReporter::publishStatus(PublishStats& p) {
  server_status_t s;
  s.utime = wallMicros();
  s.seq = seq_++;
  s.session_token = token_;
  const BusCounters bus = receiver_.counters();
  s.inputs_received = bus.inputs_received;
  s.inputs_rejected = bus.inputs_rejected;
  for (int k = 0; k < kRejectReasons; ++k) s.rejected_by_reason[k] = bus.rejected_by_reason[static_cast<size_t>(k)];
  s.inputs_dropped = std::max<int64_t>(0, bus.inputs_accepted - loop_.consumed_inputs.load());
  s.commands_received = bus.commands_received;
  s.commands_rejected = bus.commands_refused + loop_.commands_rejected.load();
  s.scene = scene_;
  loop_.read(&s.state, &s.message);
  s.sim_time = p.last_sim_time;
  s.steps = loop_.steps.load();
  const double now = monotonicSeconds();
  const int64_t window_steps = static_cast<int64_t>(p.step_times_us.size());
  s.rate_hz = now > window_start_ ? static_cast<double>(window_steps) / (now - window_start_) : 0.0;
  std::vector<double>& t = p.step_times_us;
  std::sort(t.begin(), t.end());
  auto pct = [&](double q) { return t.empty() ? 0.0 : t[std::min(t.size() - 1, static_cast<size_t>(q * t.size()))]; };
  s.step_us_p50 = pct(0.5);
  s.step_us_p99 = pct(0.99);
  s.step_us_max = t.empty() ? 0.0 : t.back();
  s.overruns = loop_.overruns.load();
  s.forces_clamped = loop_.forces_clamped.load();
  s.collisions = p.collisions;
  s.first_collision_time = p.first_collision;
  s.min_obstacle_distance = p.min_distance;
  s.ncomponents = static_cast<int32_t>(components_.size());
  s.components = components_;
  s.nlinks = static_cast<int32_t>(link_names_.size());
  s.link_names = link_names_;
  s.inputs_missed = bus.inputs_missed;
  s.socket_drops = ownUdpDrops();
  s.resume_ramps = loop_.resume_ramps.load();
  s.limited_joints.clear();
  s.limit_steps.clear();
  s.limit_excess.clear();
  for (const JointLimitReport::Entry& e : p.limits.hits()) {
    s.limited_joints.push_back(e.joint);
    s.limit_steps.push_back(e.steps);
    s.limit_excess.push_back(e.excess);
  }
  s.nlimited = static_cast<int32_t>(s.limited_joints.size());
  for (const ClientRecord& c : receiver_.clients()) {
    if (c.last_seq < 0) continue;  // never admitted: counted in rejected_by_reason only
    const double age = now - c.arrived;
    s.client_ids.push_back(c.id);
    s.client_modes.push_back(c.mode);
    s.client_input_age_s.push_back(age);
    s.client_active.push_back(c.mode != haptic_input_t::MODE_NONE && age <= hold_s_);
    s.client_inputs.push_back(c.admitted);
    s.client_rejected.push_back(c.rejected);
  }
  s.nclients = static_cast<int32_t>(s.client_ids.size());
  s.contact_solves = p.solve.solves;
  s.contact_unconverged = p.solve.unconverged;
  s.contact_position_unconverged = p.solve.position_unconverged;
  s.contact_warm_dropped = p.solve.warm_dropped;
  s.contact_sweeps_max = p.solve_sweeps_max;
  s.contact_residual_max = p.solve_residual_max;
  s.contact_candidates_dropped = p.candidates_dropped;
  s.contact_slips_unturned = p.solve.slips_unturned;
  s.contact_slip_angle_max = p.solve_slip_angle_max;
  s.contact_linearised = p.solve.linearised;
  s.contact_linearised_angle_max = p.solve_linearised_angle_max;
  s.proxy_substep_limited = p.proxy_substep_limited;
  p.solve_sweeps_max = 0;
  p.solve_residual_max = 0.0;
  p.solve_slip_angle_max = 0.0;
  p.solve_linearised_angle_max = 0.0;
  bus_.publish(channels::kServerStatus, s);
  if (seq_ % 10 == 1) {
    requestSessionInfo(s.session_token);
    bus_.publish(channels::kBusStatus,
                 bus::busStatus("igms-server", receiver_.verifier(), s.utime));
  }
  window_start_ = now;
  t.clear();
  if (!quiet_) print(s, p);
}

void StatusReporter::print(const server_status_t& s, const PublishStats& p) const {
  std::fprintf(stderr,
               "igms-server: t=%.2f s  steps=%lld  rate=%.0f Hz  step p50/p99/max=%.1f/%.1f/%.1f us  overruns=%lld"
               "  inputs=%lld rejected=%lld  commands=%lld rejected=%lld  collisions=%lld  min_dist=%.3f m  %s%s%s\n",
               s.sim_time, static_cast<long long>(s.steps), s.rate_hz, s.step_us_p50, s.step_us_p99, s.step_us_max,
               static_cast<long long>(s.overruns), static_cast<long long>(s.inputs_received),
               static_cast<long long>(s.inputs_rejected), static_cast<long long>(s.commands_received),
               static_cast<long long>(s.commands_rejected), static_cast<long long>(p.collisions), p.min_distance,
               s.state.c_str(), s.message.empty() ? "" : ": ", s.message.c_str());
  if (s.contact_solves > 0)
    std::fprintf(stderr,
                 "igms-server:   contact: %lld solves, %lld unconverged (positions %lld), %lld warm starts dropped, "
                 "%lld candidate pairs dropped, %lld slips unturned, %lld islands on the linearised cone; this period at "
                 "most %d sweeps, residual %.2g m/s, slip angle %.2g rad\n",
                 static_cast<long long>(s.contact_solves), static_cast<long long>(s.contact_unconverged),
                 static_cast<long long>(s.contact_position_unconverged), static_cast<long long>(s.contact_warm_dropped),
                 static_cast<long long>(s.contact_candidates_dropped), static_cast<long long>(s.contact_slips_unturned),
                 static_cast<long long>(s.contact_linearised), s.contact_sweeps_max, s.contact_residual_max, s.contact_slip_angle_max);
  if (s.proxy_substep_limited > 0)
    std::fprintf(stderr, "igms-server:   hands' proxies: %lld cycles cut short by the substep budget\n",
                 static_cast<long long>(s.proxy_substep_limited));
  for (int k = 0; k < s.nclients && s.seq % 10 == 0; ++k) {  // the clients, once a second
    static const char* const kModes[] = {"none", "push", "pull"};
    const int8_t m = s.client_modes[static_cast<size_t>(k)];
    std::fprintf(stderr, "igms-server:   client %d: %s, %s, last input %.3f s ago, %lld inputs, %lld rejected\n",
                 s.client_ids[static_cast<size_t>(k)], m >= 0 && m <= 2 ? kModes[m] : "?",
                 s.client_active[static_cast<size_t>(k)] ? "active" : "released",
                 s.client_input_age_s[static_cast<size_t>(k)], static_cast<long long>(s.client_inputs[static_cast<size_t>(k)]),
                 static_cast<long long>(s.client_rejected[static_cast<size_t>(k)]));
  }
  for (int k = 0; k < s.nlimited; ++k)
    std::fprintf(stderr, "igms-server:   %s beyond its position limit in %lld states, by %.4f at most\n",
                 s.limited_joints[static_cast<size_t>(k)].c_str(), static_cast<long long>(s.limit_steps[static_cast<size_t>(k)]),
                 s.limit_excess[static_cast<size_t>(k)]);
}

}  // namespace igms
