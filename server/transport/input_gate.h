// Validation of haptic inputs from the bus: a NaN, an out-of-range value, an
// unknown link, a foreign session token or a stale seq is rejected and
// counted by reason; the simulation never sees it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "igms/haptic_input_t.hpp"
#include "core/model/frame_names.h"
#include "core/model/model.h"
#include "core/simulation/hand_input.h"

namespace igms {

enum class RejectReason : int {
  NonFinite = 0, Range = 1, UnknownLink = 2, Token = 3, Stale = 4, Undecodable = 5, HandsFull = 6
};
constexpr int kRejectReasons = 7;
const char* rejectReasonName(RejectReason r);

// The checks that do not depend on the session (finite, in range, known
// links) and the conversion into the step's input: the same for the live
// server and for re-simulation of a log.
bool toInteractionInput(const haptic_input_t& msg, const FrameNames& frames, InteractionInput* out, RejectReason* why);

// One client as the gate has seen it this session.
struct ClientRecord {
  int32_t id = -1;
  int64_t last_seq = -1;   // newest admitted (-1: none yet)
  int64_t admitted = 0, rejected = 0;
  int8_t mode = 0;         // of the newest admitted input
  double arrived = 0.0;    // monotonic s, the newest admitted input
};

class InputGate {
 public:
  InputGate(const Model& model, int64_t session_token) : frames_(model), token_(session_token) {}

  // true: *out holds the validated input. false: *why says which check failed.
  // `now`: the arrival time (monotonic s) recorded for the client.
  bool admit(const haptic_input_t& msg, InteractionInput* out, RejectReason* why, double now = 0.0);
  void countUndecodable() { ++rejected_[static_cast<int>(RejectReason::Undecodable)]; }
  // A valid input the receiver could not seat (every hand taken): counted against its client.
  void rejectHandsFull(int32_t client);
  // A new session (reset): forget the clients' sequence numbers.
  void newSession(int64_t token);

  int64_t received() const { return received_; }
  // Gaps in the admitted clients' seq: inputs that never arrived.
  int64_t missed() const { return missed_; }
  const std::array<int64_t, kRejectReasons>& rejected() const { return rejected_; }
  int64_t rejectedTotal() const;
  int64_t token() const { return token_; }
  // The clients heard this session, in order of first appearance (at most kMaxClientRecords).
  const std::vector<ClientRecord>& clients() const { return clients_; }
  static constexpr size_t kMaxClientRecords = 32;  // a flood of ids is counted, not listed

 private:
  bool reject(RejectReason r, RejectReason* why) {
    ++rejected_[static_cast<int>(r)];
    *why = r;
    return false;
  }
  FrameNames frames_;  // the model's link names, resolved once per session
  int64_t token_;
  int64_t received_ = 0, missed_ = 0;
  std::array<int64_t, kRejectReasons> rejected_{};
  ClientRecord* record(int32_t client);  // null once kMaxClientRecords are listed
  std::vector<ClientRecord> clients_;
};

}  // namespace igms
