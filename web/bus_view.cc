#include "web/bus_view.h"

#include <cmath>
#include <cstdio>

#include "channels.h"
#include "safe_decode.h"

namespace igms::web {
namespace {

void append(std::string& s, const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, std::isfinite(v) ? v : 0.0);
  s += buf;
}

void appendArray(std::string& s, const double* v, int n, const char* fmt = "%.5g") {
  s += '[';
  for (int i = 0; i < n; ++i) {
    if (i) s += ',';
    append(s, fmt, v[i]);
  }
  s += ']';
}

// Text from the bus into a JSON string: printable ASCII only, quotes escaped.
void appendString(std::string& s, const std::string& text) {
  s += '"';
  for (char c : text.substr(0, 200)) {
    if (c == '"' || c == '\\') s += '\\';
    s += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  s += '"';
}

}  // namespace

// The newest message of a channel: decoded in place, or counted as undecodable.
template <typename Message>
bool BusView::take(const void* data, size_t size, double now, Message* out, double* time, bool* have) {
  if (!safeDecode(data, size, out)) {
    ++undecodable_;
    *have = false;
    return false;
  }
  *time = now;
  *have = true;
  return true;
}

void BusView::handle(const std::string& channel, const void* data, size_t size, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (channel == channels::kRobotState) {
    robot_state_t m;
    if (!safeDecode(data, size, &m) || m.nlinks < 0 || m.nlinks > 10000) {
      ++undecodable_;
      return;
    }
    state_ = std::move(m);
    state_time_ = now;
    have_state_ = true;
    ++states_;
  } else if (channel == channels::kServerStatus) {
    take(data, size, now, &server_, &server_time_, &have_server_);
  } else if (channel == channels::kClientStatus) {
    take(data, size, now, &client_, &client_time_, &have_client_);
  } else if (channel == channels::kHapticInput) {
    take(data, size, now, &input_, &input_time_, &have_input_);
  } else if (channel == channels::kContacts) {
    contacts_t m;
    if (!safeDecode(data, size, &m) || m.ncontacts < 0 || m.ncontacts > kMaxContacts) {
      ++undecodable_;
      return;
    }
    contacts_ = std::move(m);
    contacts_time_ = now;
    have_contacts_ = true;
  } else if (channel == channels::kSessionInfo) {
    session_info_t m;
    if (!safeDecode(data, size, &m)) {
      ++undecodable_;
      return;
    }
    const std::string key = m.scene_path + "|" + m.model_hash + "|" + std::to_string(m.session_token);
    if (key != session_key_) {
      session_key_ = key;
      session_ = std::move(m);
      new_session_ = true;
    }
  }
}

void BusView::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  have_state_ = have_server_ = have_client_ = have_input_ = have_contacts_ = false;
  state_time_ = server_time_ = client_time_ = input_time_ = contacts_time_ = -1e9;
}

bool BusView::takeSession(session_info_t* info) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!new_session_) return false;
  new_session_ = false;
  *info = session_;
  return true;
}

int64_t BusView::undecodable() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return undecodable_;
}

int64_t BusView::serverToken() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return have_server_ ? server_.session_token : 0;
}

int64_t BusView::states() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return states_;
}

std::string BusView::frameJson(double now, const std::string& extra) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string s;
  if (!have_state_ && !have_server_) return s;
  s.reserve(512 + 80 * static_cast<size_t>(state_.nlinks));
  s += "{\"type\":\"frame\"";
  const bool server_lost = now - std::max(state_time_, server_time_) > kLostAfter;
  if (have_state_) appendState(s);
  if (have_server_) appendServer(s);
  s += ",\"server_lost\":"; s += server_lost ? "true" : "false";
  if (have_client_) appendClient(s, now);
  if (have_input_ && now - input_time_ < kLostAfter) appendInput(s);
  if (have_contacts_ && now - contacts_time_ < kContactsFor) appendContacts(s);
  s += extra;
  s += '}';
  return s;
}

// The frame's parts, each from the newest message of its channel (mutex_ held).
void BusView::appendState(std::string& s) const {
  const robot_state_t& m = state_;
  s += ",\"t\":"; append(s, "%.6f", m.sim_time);
  s += ",\"seq\":" + std::to_string(m.seq);
  s += ",\"mode\":" + std::to_string(int{m.mode});
  s += ",\"force\":"; appendArray(s, m.interaction_force, 3);
  s += ",\"point\":"; appendArray(s, m.interaction_point, 3);
  s += ",\"torque\":"; appendArray(s, m.interaction_torque, 3);
  s += ",\"hands\":" + std::to_string(m.nhands);
  s += ",\"in_collision\":"; s += m.in_collision ? "true" : "false";
  s += ",\"closest_link\":" + std::to_string(m.closest_link);
  s += ",\"min_distance\":"; append(s, "%.5g", m.min_obstacle_distance);
  s += ",\"step_us\":" + std::to_string(m.step_us);
  s += ",\"poses\":[";
  for (int i = 0; i < m.nlinks; ++i) {
    if (i) s += ',';
    appendArray(s, m.link_poses[static_cast<size_t>(i)].data(), 7, "%.6g");
  }
  s += ']';
}

void BusView::appendServer(std::string& s) const {
  const server_status_t& st = server_;
  s += ",\"server\":{\"state\":"; appendString(s, st.state);
  s += ",\"message\":"; appendString(s, st.message);
  s += ",\"rate\":"; append(s, "%.1f", st.rate_hz);
  s += ",\"step_p50\":"; append(s, "%.2f", st.step_us_p50);
  s += ",\"step_p99\":"; append(s, "%.2f", st.step_us_p99);
  s += ",\"step_max\":"; append(s, "%.2f", st.step_us_max);
  s += ",\"overruns\":" + std::to_string(st.overruns);
  s += ",\"inputs_rejected\":" + std::to_string(st.inputs_rejected);
  s += ",\"commands_rejected\":" + std::to_string(st.commands_rejected);
  // The contact solve over the run (all 0 in a scene without contact).
  s += ",\"contact\":{\"solves\":" + std::to_string(st.contact_solves);
  s += ",\"unconverged\":" + std::to_string(st.contact_unconverged);
  s += ",\"slips_unturned\":" + std::to_string(st.contact_slips_unturned) + "}";
  s += ",\"token\":\"" + std::to_string(st.session_token) + "\"}";
}

void BusView::appendClient(std::string& s, double now) const {
  const client_status_t& c = client_;
  s += ",\"client\":{\"state\":"; appendString(s, c.state);
  s += ",\"device\":"; appendString(s, c.device);
  s += ",\"fallback\":"; appendString(s, c.fallback);
  s += ",\"rate\":"; append(s, "%.1f", c.rate_hz);
  s += ",\"misses\":" + std::to_string(c.deadline_misses);
  s += ",\"fallbacks\":" + std::to_string(c.fallbacks);
  s += ",\"rtt_p50\":"; append(s, "%.0f", c.rtt_us_p50);
  s += ",\"rtt_p99\":"; append(s, "%.0f", c.rtt_us_p99);
  s += ",\"force_scale\":"; append(s, "%.3f", c.force_scale);
  s += ",\"max_force_step\":"; append(s, "%.4f", c.max_force_step);
  s += ",\"rendered_force\":"; appendArray(s, c.rendered_force, 3);
  s += "}";
  const bool finished = c.state == "finished";
  s += ",\"client_lost\":"; s += (!finished && now - client_time_ > kLostAfter) ? "true" : "false";
}

void BusView::appendInput(std::string& s) const {
  const haptic_input_t& in = input_;
  s += ",\"input\":{\"tip\":"; appendArray(s, in.tip_position, 3);
  s += ",\"radius\":"; append(s, "%.4g", in.tip_radius);
  s += ",\"mode\":" + std::to_string(int{in.mode});
  s += ",\"attach_link\":"; appendString(s, in.attach_link);
  s += ",\"attach_point\":"; appendArray(s, in.attach_point, 3);
  s += "}";
}

  // The contacts: points and forces as flat [x y z ...] arrays. The force drawn is the one on the
  // moving side (on b, as sent, unless b is the world: then on a), so an arrow shows what the
  // ground or a table does to the body.
void BusView::appendContacts(std::string& s) const {
  const contacts_t& c = contacts_;
  s += ",\"contacts\":{\"seq\":" + std::to_string(c.seq) + ",\"total\":" + std::to_string(c.total) + ",\"p\":[";
  for (int k = 0; k < c.ncontacts; ++k) {
    for (int i = 0; i < 3; ++i) {
      if (k || i) s += ',';
      append(s, "%.4f", c.point[static_cast<size_t>(k)][static_cast<size_t>(i)]);
    }
  }
  s += "],\"f\":[";
  for (int k = 0; k < c.ncontacts; ++k) {
    const auto n = static_cast<size_t>(k);
    const double sign = c.link_b[n] < 0 && c.link_a[n] >= 0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) {
      if (k || i) s += ',';
      append(s, "%.4g", sign * c.force[n][static_cast<size_t>(i)]);
    }
  }
  s += "]}";
}

}  // namespace igms::web
