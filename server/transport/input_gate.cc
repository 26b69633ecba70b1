#include "server/transport/input_gate.h"

#include <cmath>

namespace igms {
namespace {

constexpr double kMaxPosition = 100.0;  // m from the scene origin
constexpr double kMaxSpeed = 100.0;     // m/s
constexpr double kMaxTipRadius = 0.5;   // m

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
  last_seq_.clear();
}

bool toInteractionInput(const haptic_input_t& m, const Model& model, InteractionInput* out, RejectReason* why) {
  if (!finite3(m.tip_position) || !finite3(m.tip_velocity) || !finite3(m.attach_point) ||
      !std::isfinite(m.tip_radius)) {
    *why = RejectReason::NonFinite;
    return false;
  }
  if (m.mode < haptic_input_t::MODE_NONE || m.mode > haptic_input_t::MODE_PULL ||
      norm3(m.tip_position) > kMaxPosition || norm3(m.tip_velocity) > kMaxSpeed || m.tip_radius < 0.0 ||
      m.tip_radius > kMaxTipRadius || norm3(m.attach_point) > 10.0) {
    *why = RejectReason::Range;
    return false;
  }
  int contact = -1, attach = -1;
  if ((!m.contact_link.empty() && (contact = model.frameIndex(m.contact_link)) < 0) ||
      (!m.attach_link.empty() && (attach = model.frameIndex(m.attach_link)) < 0)) {
    *why = RejectReason::UnknownLink;
    return false;
  }
  out->mode = static_cast<InteractionMode>(m.mode);
  out->tip_position = Vector3(m.tip_position[0], m.tip_position[1], m.tip_position[2]);
  out->tip_velocity = Vector3(m.tip_velocity[0], m.tip_velocity[1], m.tip_velocity[2]);
  out->tip_radius = m.tip_radius > 0.0 ? m.tip_radius : 0.01;
  out->contact_frame = contact;
  out->attach_frame = attach;
  out->attach_point = Vector3(m.attach_point[0], m.attach_point[1], m.attach_point[2]);
  out->seq = m.seq;
  out->client = m.client_id;
  return true;
}

bool InputGate::admit(const haptic_input_t& m, InteractionInput* out, RejectReason* why) {
  ++received_;
  if (m.session_token != token_) return reject(RejectReason::Token, why);
  InteractionInput converted;
  if (!toInteractionInput(m, model_, &converted, why)) return reject(*why, why);
  // Newer than the last input admitted from this client (clients are few: a short list).
  auto it = last_seq_.begin();
  while (it != last_seq_.end() && it->first != m.client_id) ++it;
  if (it != last_seq_.end() && m.seq <= it->second) return reject(RejectReason::Stale, why);
  if (it == last_seq_.end()) {
    last_seq_.emplace_back(m.client_id, m.seq);
  } else {
    missed_ += m.seq - it->second - 1;  // inputs of this client that never came (lost, or a full socket)
    it->second = m.seq;
  }
  *out = converted;
  return true;
}

}  // namespace igms
