#include "server/app/state_publisher.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "channels.h"
#include "core/realtime/clock.h"

namespace igms {

robot_state_t sizedStateMessage(const Model& m) {
  robot_state_t msg{};
  msg.nq = m.nq;
  msg.nv = m.nv;
  msg.q.resize(static_cast<size_t>(m.nq));
  msg.v.resize(static_cast<size_t>(m.nv));
  msg.qdd.resize(static_cast<size_t>(m.nv));
  msg.tau.resize(static_cast<size_t>(m.nv));
  msg.nlinks = static_cast<int32_t>(m.frames.size());
  msg.link_poses.assign(m.frames.size(), std::vector<double>(7, 0.0));
  // The hand arrays keep kMaxHands rows; nhands says how many are sent (the
  // generated encoder reads the count, not the vectors' sizes): no allocation per state.
  msg.hand_client.assign(kMaxHands, -1);
  msg.hand_input_seq.assign(kMaxHands, -1);
  msg.hand_mode.assign(kMaxHands, 0);
  msg.hand_force.assign(kMaxHands, std::vector<double>(3, 0.0));
  msg.hand_torque.assign(kMaxHands, std::vector<double>(3, 0.0));
  msg.hand_point.assign(kMaxHands, std::vector<double>(3, 0.0));
  msg.nhands = kMaxHands;
  return msg;
}

std::string stateTooLarge(const Model& m, const std::string& scene) {
  robot_state_t msg = sizedStateMessage(m);
  const int size = msg.getEncodedSize();
  // The bus signature's trailer rides in the same datagram (keyed or not: a scene must not stop fitting when signed).
  if (size + static_cast<int>(bus::kTrailerBytes) <= kMaxDatagramBytes) return "";
  return scene + ": its state message would be " + std::to_string(size) + " bytes (nq " + std::to_string(m.nq) +
         ", nv " + std::to_string(m.nv) + ", " + std::to_string(m.frames.size()) +
         " links), more than one LCM datagram holds with the bus signature (" + std::to_string(kMaxDatagramBytes) +
         " bytes, " + std::to_string(bus::kTrailerBytes) + " of them the signature's): fewer bodies, or fewer links (fixed joints merge their links' bodies but keep their frames)";
}

StatePublisher::StatePublisher(bus::SignedPublisher& bus, const Model& m, const GeometryModel& geometry,
                               FaultInjection faults, bool quiet)
    : bus_(bus), world_(m, geometry), faults_(faults), quiet_(quiet), stats_(m), fault_epoch_(monotonicSeconds()) {
  msg_ = sizedStateMessage(m);
  buffer_.resize(static_cast<size_t>(msg_.getEncodedSize()) + 64 + bus::kTrailerBytes);  // signed in place
  stats_.step_times_us.reserve(4096);
}

void StatePublisher::fill(const Snapshot& s) {
  msg_.utime = s.utime;
  msg_.seq = s.seq;
  msg_.sim_time = s.sim_time;
  msg_.input_seq = s.outcome.input_seq;
  msg_.input_client = s.outcome.input_client;
  std::copy(s.q.begin(), s.q.end(), msg_.q.begin());
  std::copy(s.v.begin(), s.v.end(), msg_.v.begin());
  std::copy(s.qdd.begin(), s.qdd.end(), msg_.qdd.begin());
  std::copy(s.tau.begin(), s.tau.end(), msg_.tau.begin());
  msg_.mode = static_cast<int8_t>(s.outcome.mode);
  for (int k = 0; k < 3; ++k) {
    msg_.interaction_force[k] = s.outcome.force_on_robot[k];
    msg_.interaction_point[k] = s.outcome.force_point[k];
    msg_.interaction_torque[k] = s.outcome.torque_on_robot[k];
  }
  msg_.nhands = s.outcome.nhands;
  for (size_t h = 0; h < static_cast<size_t>(s.outcome.nhands); ++h) {
    const HandOutcome& o = s.outcome.hands[h];
    msg_.hand_client[h] = o.client;
    msg_.hand_input_seq[h] = o.input_seq;
    msg_.hand_mode[h] = static_cast<int8_t>(o.mode);
    for (size_t k = 0; k < 3; ++k) {
      msg_.hand_force[h][k] = o.applied.force[static_cast<int>(k)];
      msg_.hand_torque[h][k] = o.applied.torque[static_cast<int>(k)];
      msg_.hand_point[h][k] = o.applied.point[static_cast<int>(k)];
    }
  }
  for (size_t f = 0; f < s.link_poses.size(); ++f) {
    const SE3& X = s.link_poses[f];
    Eigen::Quaterniond quat(X.R);
    if (quat.w() < 0) quat.coeffs() *= -1.0;
    auto& row = msg_.link_poses[f];
    row[0] = X.p.x(); row[1] = X.p.y(); row[2] = X.p.z();
    row[3] = quat.w(); row[4] = quat.x(); row[5] = quat.y(); row[6] = quat.z();
  }
  msg_.step_us = s.step_us;
}

void StatePublisher::checkCollisions(const Snapshot& s) {
  if (world_.empty()) {
    msg_.min_obstacle_distance = 1e9;
    msg_.in_collision = false;
    msg_.closest_link = -1;
    return;
  }
  const CollisionReport c = world_.check(s.link_poses);
  msg_.min_obstacle_distance = c.min_distance;
  msg_.in_collision = c.in_collision;
  msg_.closest_link = c.closest_frame;
  stats_.min_distance = std::min(stats_.min_distance, c.min_distance);
  if (!c.in_collision) return;
  ++stats_.collisions;
  if (stats_.first_collision >= 0) return;
  stats_.first_collision = s.sim_time;
  if (!quiet_)
    std::fprintf(stderr, "igms-server: collision at t=%.3f s: %s hits %s\n", s.sim_time, c.closest_link.c_str(),
                 c.closest_obstacle.c_str());
}

void StatePublisher::publish(const Snapshot& s) {
  fill(s);
  checkCollisions(s);
  const int n = msg_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size() - bus::kTrailerBytes));
  if (n > 0 && faults_.any()) bus_.publishInPlace(truth_channel_, buffer_.data(), static_cast<size_t>(n));
  if (n > 0 && !faultDrops()) {
    if (faults_.delay_us > 0)
      std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int64_t>(faults_.delay_us)));
    bus_.publishInPlace(state_channel_, buffer_.data(), static_cast<size_t>(n));
  }
  stats_.last_sim_time = s.sim_time;
  stats_.step_times_us.push_back(s.step_us);
  stats_.solve = s.solve;
  stats_.candidates_dropped = s.candidates_dropped;
  stats_.proxy_substep_limited = s.proxy_substep_limited;
  if (s.solved) {
    stats_.solve_sweeps_max = std::max(stats_.solve_sweeps_max, s.solve.iterations);
    stats_.solve_residual_max = std::max(stats_.solve_residual_max, s.solve.residual);
    stats_.solve_slip_angle_max = std::max(stats_.solve_slip_angle_max, s.solve.slip_angle);
    stats_.solve_linearised_angle_max = std::max(stats_.solve_linearised_angle_max, s.solve.linearised_angle);
  }
  stats_.limits.observe(s.q);
}

bool StatePublisher::faultDrops() {
  if (faults_.drop > 0 && uniform_(rng_) < faults_.drop) return true;
  if (faults_.burst_ms > 0) {
    const double phase = std::fmod(monotonicSeconds() - fault_epoch_, 1.0);
    if (phase < faults_.burst_ms * 1e-3) return true;
  }
  return false;
}

}  // namespace igms
