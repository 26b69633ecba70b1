// Validation of haptic inputs from the bus: a NaN, an out-of-range value, an
// unknown link, a foreign session token or a stale seq is rejected and
// counted by reason; the simulation never sees it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "igms/haptic_input_t.hpp"
#include "core/simulation/simulation.h"

namespace igms {

enum class RejectReason : int { NonFinite = 0, Range = 1, UnknownLink = 2, Token = 3, Stale = 4, Undecodable = 5 };
constexpr int kRejectReasons = 6;
const char* rejectReasonName(RejectReason r);

// The checks that do not depend on the session (finite, in range, known
// links) and the conversion into the step's input: the same for the live
// server and for re-simulation of a log.
bool toInteractionInput(const haptic_input_t& msg, const Model& model, InteractionInput* out, RejectReason* why);

class InputGate {
 public:
  InputGate(const Model& model, int64_t session_token) : model_(model), token_(session_token) {}

  // true: *out holds the validated input. false: *why says which check failed.
  bool admit(const haptic_input_t& msg, InteractionInput* out, RejectReason* why);
  void countUndecodable() { ++rejected_[static_cast<int>(RejectReason::Undecodable)]; }
  // A new session (reset): forget the clients' sequence numbers.
  void newSession(int64_t token);

  int64_t received() const { return received_; }
  // Gaps in the admitted clients' seq: inputs that never arrived.
  int64_t missed() const { return missed_; }
  const std::array<int64_t, kRejectReasons>& rejected() const { return rejected_; }
  int64_t rejectedTotal() const;
  int64_t token() const { return token_; }

 private:
  bool reject(RejectReason r, RejectReason* why) {
    ++rejected_[static_cast<int>(r)];
    *why = r;
    return false;
  }
  const Model& model_;
  int64_t token_;
  int64_t received_ = 0, missed_ = 0;
  std::array<int64_t, kRejectReasons> rejected_{};
  std::vector<std::pair<int32_t, int64_t>> last_seq_;  // per client
};

}  // namespace igms
