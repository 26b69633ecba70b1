#include "haptic_client/servo/client_bus.h"

#include <algorithm>

#include "channels.h"
#include "core/realtime/clock.h"

namespace igms {

namespace {
ReceivedState initialState(int nlinks, int nq, int nv) {
  ReceivedState r;
  r.sample.links.assign(static_cast<size_t>(nlinks), SE3::Identity());
  r.sample.q.assign(static_cast<size_t>(nq), 0.0);
  r.sample.v.assign(static_cast<size_t>(nv), 0.0);
  r.sample.qdd.assign(static_cast<size_t>(nv), 0.0);
  return r;
}
}  // namespace

ClientBus::ClientBus(const std::string& url, int nlinks, int nq, int nv, int32_t client_id,
                     const std::optional<bus::BusKey>& key, bool accept_replay)
    : client_id_(client_id),
      lcm_(url.empty() ? channels::kDefaultUrl : url),
      verifier_(key, "igms-haptic"),
      input_out_(lcm_, key, 0),
      status_out_(lcm_, key, 16 * 1024),
      input_channel_(channels::kHapticInput),
      states_(initialState(nlinks, nq, nv)) {
  haptic_input_t probe{};
  buffer_.resize(static_cast<size_t>(probe.getEncodedSize()) + 256 + bus::kTrailerBytes);
  // The server whose status or state is taken first is the session's: no second signer speaks for it.
  verifier_.pinSender({channels::kRobotState, channels::kServerStatus});
  if (accept_replay) verifier_.acceptReplays();
  if (!lcm_.good()) return;
  state_in_ = bus::subscribe<robot_state_t>(
      lcm_, verifier_, channels::kRobotState, [this](const robot_state_t& m, const bus::Verdict&) { onState(m); },
      100);
  status_in_ = bus::subscribe<server_status_t>(
      lcm_, verifier_, channels::kServerStatus, [this](const server_status_t& m, const bus::Verdict&) { onStatus(m); });
}

int64_t ClientBus::undecodable() const {
  return (state_in_ ? state_in_->undecodable() : 0) + (status_in_ ? status_in_->undecodable() : 0);
}

void ClientBus::onState(const robot_state_t& state) {
  const robot_state_t* m = &state;
  if (last_state_seq_ >= 0 && m->seq > last_state_seq_ + 1) states_missed_ += m->seq - last_state_seq_ - 1;
  if (m->seq > last_state_seq_ || m->seq < last_state_seq_ - 1000) last_state_seq_ = m->seq;  // or a reset
  ReceivedState& r = states_.back();
  RobotSample& s = r.sample;
  if (static_cast<size_t>(m->nlinks) != s.links.size() || static_cast<size_t>(m->nq) != s.q.size() ||
      static_cast<size_t>(m->nv) != s.v.size())
    return;
  s.seq = m->seq;
  // This client's hand among the step's hands (none: the step did not consume an input of ours).
  s.input_seq = -1;
  s.input_client = -1;
  s.mode = m->mode;
  s.own_mode = 0;
  s.own_force.setZero();
  s.own_torque.setZero();
  s.nhands = 0;
  s.nconsumed = std::max(0, m->nhands);
  const size_t nhands = static_cast<size_t>(std::max(0, m->nhands));
  for (size_t h = 0; h < nhands; ++h) {
    if (m->hand_mode[h] != 0) ++s.nhands;
    if (m->hand_client[h] != client_id_) continue;
    s.input_seq = m->hand_input_seq[h];
    s.input_client = client_id_;
    s.own_mode = m->hand_mode[h];
    s.own_force = Vector3(m->hand_force[h][0], m->hand_force[h][1], m->hand_force[h][2]);
    s.own_torque = Vector3(m->hand_torque[h][0], m->hand_torque[h][1], m->hand_torque[h][2]);
  }
  s.sim_time = m->sim_time;
  for (size_t k = 0; k < s.links.size(); ++k) {
    const auto& p = m->link_poses[k];
    s.links[k].p = Vector3(p[0], p[1], p[2]);
    s.links[k].R = Eigen::Quaterniond(p[3], p[4], p[5], p[6]).normalized().toRotationMatrix();
  }
  std::copy(m->q.begin(), m->q.end(), s.q.begin());
  std::copy(m->v.begin(), m->v.end(), s.v.begin());
  std::copy(m->qdd.begin(), m->qdd.end(), s.qdd.begin());
  r.received = monotonicSeconds();
  states_.publish();
}

void ClientBus::onStatus(const server_status_t& status) {
  const server_status_t* m = &status;
  {
    std::lock_guard<std::mutex> lock(names_mutex_);
    link_names_ = m->link_names;
  }
  token_ = m->session_token;
  have_token_ = true;
}

std::vector<std::string> ClientBus::serverLinkNames() {
  std::lock_guard<std::mutex> lock(names_mutex_);
  return link_names_;
}

void ClientBus::publishInput(const haptic_input_t& msg) {
  const int n = msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size() - bus::kTrailerBytes));
  if (n > 0) input_out_.publishInPlace(input_channel_, buffer_.data(), static_cast<size_t>(n));
}

}  // namespace igms
