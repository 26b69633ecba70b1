// The client's side of the bus. In: robot states (decoded on the bus thread
// into a triple buffer the servo loop takes from without locks) and the
// server's status (its session token and link order), each checked first
// (bus::MessageVerifier: with a bus key, only what the key signed and is new
// gets through). Out: the servo loop's inputs as raw bytes from a
// preallocated buffer, signed in place with a key, and the status thread's
// messages through a publisher of their own.
#pragma once

#include <atomic>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <string>
#include <vector>

#include <memory>
#include <optional>

#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "bus/subscription.h"
#include "core/realtime/triple_buffer.h"
#include "haptic_client/servo/state_estimate.h"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"

namespace igms {

struct ReceivedState {
  RobotSample sample;
  double received = 0.0;  // monotonic s
};

class ClientBus {
 public:
  // nlinks, nq, nv: the scene's model; states of another shape are ignored.
  // client_id: this client's; each state names its hand among the others by it.
  // key: the bus key (none: unauthenticated).
  ClientBus(const std::string& url, int nlinks, int nq, int nv, int32_t client_id = 1,
            const std::optional<bus::BusKey>& key = std::nullopt, bool accept_replay = false);
  bool good() { return lcm_.good(); }
  lcm::LCM& lcm() { return lcm_; }
  // The status thread's publisher (client status, bus status).
  bus::SignedPublisher& statusOut() { return status_out_; }
  const bus::MessageVerifier& verifier() const { return verifier_; }

  TripleBuffer<ReceivedState>& states() { return states_; }
  bool haveServer() const { return have_token_; }
  int64_t sessionToken() const { return token_; }
  std::vector<std::string> serverLinkNames();
  // Encodes into the preallocated buffer and publishes (the servo loop's only I/O).
  void publishInput(const haptic_input_t& msg);

  // Messages that failed to decode (counted, never fatal).
  int64_t undecodable() const;
  // States that never arrived: gaps in their seq (a new session starts the count afresh).
  int64_t statesMissed() const { return states_missed_; }

 private:
  void onState(const robot_state_t& m);
  void onStatus(const server_status_t& m);

  const int32_t client_id_;
  lcm::LCM lcm_;
  bus::MessageVerifier verifier_;  // the bus thread's
  bus::SignedPublisher input_out_;  // the servo loop's: signs the input in buffer_, where it was encoded
  bus::SignedPublisher status_out_;
  const std::string input_channel_;
  TripleBuffer<ReceivedState> states_;
  std::atomic<int64_t> token_{0};
  std::atomic<bool> have_token_{false};
  std::mutex names_mutex_;
  std::vector<std::string> link_names_;
  std::vector<uint8_t> buffer_;
  std::atomic<int64_t> states_missed_{0};
  int64_t last_state_seq_ = -1;  // the bus thread's
  // Last: they call into the rest. Each decodes into a message it keeps (its vectors keep their capacity).
  std::unique_ptr<bus::Subscription<robot_state_t>> state_in_;
  std::unique_ptr<bus::Subscription<server_status_t>> status_in_;
};

}  // namespace igms
