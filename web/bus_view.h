// The session as the page sees it: the newest robot state, server status,
// client status, haptic input, contacts and session info, from the bus or from a log,
// turned into one frame (JSON) at display rate. Messages are untrusted: each
// is decoded with safeDecode, and one that does not decode (or whose sizes
// disagree) is counted and dropped.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include "igms/client_status_t.hpp"
#include "igms/contacts_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "igms/session_info_t.hpp"

namespace igms::web {

class BusView {
 public:
  // A server or client is "lost" when nothing came from it for this long.
  static constexpr double kLostAfter = 1.0;  // s
  // Contacts older than this are not drawn (the server sends them at --contact-rate).
  static constexpr double kContactsFor = 0.25;  // s
  // A contacts message holding more is refused (the server sends at most 512).
  static constexpr int kMaxContacts = 4096;

  // `now`: the feed's clock (wall time live, log time in a replay), s.
  void handle(const std::string& channel, const void* data, size_t size, double now);
  // Forget everything (a replay seeks backwards).
  void clear();
  // A session info not yet taken (true once per new session).
  bool takeSession(session_info_t* info);
  // The frame at `now` ({"type":"frame",...}); `extra` is appended inside the
  // object (",\"key\":value..."). Empty before the first state.
  std::string frameJson(double now, const std::string& extra);
  int64_t undecodable() const;
  // The session token of the newest server status (0 before one): commands carry it.
  int64_t serverToken() const;
  int64_t states() const;

 private:
  // frameJson's parts (mutex_ held).
  void appendState(std::string& s) const;
  void appendServer(std::string& s) const;
  void appendClient(std::string& s, double now) const;
  void appendInput(std::string& s) const;
  void appendContacts(std::string& s) const;

  template <typename Message>
  bool take(const void* data, size_t size, double now, Message* out, double* time, bool* have);

  mutable std::mutex mutex_;
  robot_state_t state_{};
  server_status_t server_{};
  client_status_t client_{};
  haptic_input_t input_{};
  session_info_t session_{};
  contacts_t contacts_{};
  bool have_state_ = false, have_server_ = false, have_client_ = false, have_input_ = false, have_contacts_ = false;
  bool new_session_ = false;
  std::string session_key_;
  double state_time_ = -1e9, server_time_ = -1e9, client_time_ = -1e9, input_time_ = -1e9, contacts_time_ = -1e9;
  int64_t undecodable_ = 0, states_ = 0;
};

}  // namespace igms::web
