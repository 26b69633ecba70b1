#include "server/transport/input_gate.h"

#include <cmath>

namespace igms {
namespace {

constexpr double kMaxPosition = 100.0;  // m from the scene origin
constexpr double kMaxSpeed = 100.0;     // m/s
constexpr double kMaxTipRadius = 0.5;   // m
constexpr double kMaxAngularSpeed = 100.0;  // rad/s

bool finite3(const double* x) { return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]); }
double norm3(const double* x) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); }

}  // namespace

const char* rejectReasonName(RejectReason r) {
  switch (r) {
    case RejectReason::NonFinite: return "non_finite";
    case RejectReason::Range: return "out_of_range";
    case RejectReason::UnknownLink: return "unknown_link";
    case RejectReason::Token: return "wrong_session_token";
    case RejectReason::Stale: return "stale_seq";
    case RejectReason::Undecodable: return "undecodable";
    case RejectReason::HandsFull: return "hands_full";
  }
  return "?";
}

int64_t InputGate::rejectedTotal() const {
  int64_t s = 0;
  for (auto r : rejected_) s += r;
  return s;
}

void InputGate::newSession(int64_t token) {
  token_ = token;
  clients_.clear();
}

bool toInteractionInput(const haptic_input_t& m, const FrameNames& frames, InteractionInput* out, RejectReason* why) {
  const bool orientation_finite = !m.has_orientation ||
                                  (finite3(m.tip_angular_velocity) && std::isfinite(m.tip_orientation[0]) &&
                                   finite3(m.tip_orientation + 1) && std::isfinite(m.attach_orientation[0]) &&
                                   finite3(m.attach_orientation + 1));
  if (!finite3(m.tip_position) || !finite3(m.tip_velocity) || !finite3(m.attach_point) ||
      !std::isfinite(m.tip_radius) || !orientation_finite) {
    *why = RejectReason::NonFinite;
    return false;
  }
  if (m.mode < haptic_input_t::MODE_NONE || m.mode > haptic_input_t::MODE_PULL ||
      norm3(m.tip_position) > kMaxPosition || norm3(m.tip_velocity) > kMaxSpeed || m.tip_radius < 0.0 ||
      m.tip_radius > kMaxTipRadius || norm3(m.attach_point) > 10.0) {
    *why = RejectReason::Range;
    return false;
  }
  Eigen::Quaterniond tip_q = Eigen::Quaterniond::Identity(), attach_q = Eigen::Quaterniond::Identity();
  if (m.has_orientation) {
    // Unit quaternions (within a rounding tolerance; normalised here), and a device turning slower than 100 rad/s.
    tip_q = Eigen::Quaterniond(m.tip_orientation[0], m.tip_orientation[1], m.tip_orientation[2], m.tip_orientation[3]);
    attach_q = Eigen::Quaterniond(m.attach_orientation[0], m.attach_orientation[1], m.attach_orientation[2],
                                  m.attach_orientation[3]);
    if (std::abs(tip_q.norm() - 1.0) > 1e-3 || std::abs(attach_q.norm() - 1.0) > 1e-3 ||
        norm3(m.tip_angular_velocity) > kMaxAngularSpeed) {
      *why = RejectReason::Range;
      return false;
    }
    tip_q.normalize();
    attach_q.normalize();
  }
  int contact = -1, attach = -1;
  if ((!m.contact_link.empty() && (contact = frames.find(m.contact_link)) < 0) ||
      (!m.attach_link.empty() && (attach = frames.find(m.attach_link)) < 0)) {
    *why = RejectReason::UnknownLink;
    return false;
  }
  out->mode = static_cast<InteractionMode>(m.mode);
  out->tip_position = Vector3(m.tip_position[0], m.tip_position[1], m.tip_position[2]);
  out->tip_velocity = Vector3(m.tip_velocity[0], m.tip_velocity[1], m.tip_velocity[2]);
  out->tip_radius = m.tip_radius > 0.0 ? m.tip_radius : 0.01;
  out->attach_frame = attach;
  out->attach_point = Vector3(m.attach_point[0], m.attach_point[1], m.attach_point[2]);
  out->has_orientation = m.has_orientation;
  out->tip_orientation = tip_q;
  out->tip_angular_velocity = m.has_orientation ? Vector3(m.tip_angular_velocity[0], m.tip_angular_velocity[1],
                                                          m.tip_angular_velocity[2])
                                                : Vector3::Zero();
  out->attach_orientation = attach_q;
  out->seq = m.seq;
  out->client = m.client_id;
  return true;
}

ClientRecord* InputGate::record(int32_t client) {
  for (ClientRecord& c : clients_)
    if (c.id == client) return &c;
  if (clients_.size() >= kMaxClientRecords) return nullptr;
  clients_.push_back(ClientRecord{});
  clients_.back().id = client;
  return &clients_.back();
}

void InputGate::rejectHandsFull(int32_t client) {
  ++rejected_[static_cast<int>(RejectReason::HandsFull)];
  if (ClientRecord* c = record(client)) {
    ++c->rejected;
    --c->admitted;  // admit() had counted it
  }
}

bool InputGate::admit(const haptic_input_t& m, InteractionInput* out, RejectReason* why, double now) {
  ++received_;
  // A foreign token is counted against a client this session already lists, and lists none (a stranger
  // flooding ids does not crowd out this session's clients).
  ClientRecord* c = nullptr;
  for (ClientRecord& r : clients_)
    if (r.id == m.client_id) c = &r;
  auto refuse = [&](RejectReason r) {
    if (c) ++c->rejected;
    return reject(r, why);
  };
  if (m.session_token != token_) return refuse(RejectReason::Token);
  if (!c) c = record(m.client_id);
  InteractionInput converted;
  if (!toInteractionInput(m, frames_, &converted, why)) return refuse(*why);
  // Newer than the last input admitted from this client.
  if (c && c->last_seq >= 0 && m.seq <= c->last_seq) return refuse(RejectReason::Stale);
  if (c) {
    if (c->last_seq >= 0) missed_ += m.seq - c->last_seq - 1;  // inputs of this client that never came
    c->last_seq = m.seq;
    ++c->admitted;
    c->mode = m.mode;
    c->arrived = now;
  }
  *out = converted;
  return true;
}

}  // namespace igms
