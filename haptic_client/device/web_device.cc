#include "haptic_client/device/web_device.h"

#include <openssl/rand.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <regex>

#include "core/realtime/clock.h"
#include "igms/command_t.hpp"
#include "channels.h"
#include "web/bus_feed.h"
#include "web/page_files.h"
#include "web/view_service.h"

namespace igms {
namespace {

using nlohmann::json;
using web::PageMessage;

// 128 bits from OpenSSL's generator (std::random_device need not be a cryptographic source).
std::string newToken() {
  unsigned char bytes[16];
  if (RAND_bytes(bytes, sizeof bytes) != 1) throw std::runtime_error("--device web: no random bytes (OpenSSL)");
  char buf[33];
  for (int i = 0; i < 16; ++i) std::snprintf(buf + 2 * i, 3, "%02x", bytes[i]);
  return buf;
}

bool vector3(const json& m, const char* key, double limit, Vector3* out) {
  if (!m.contains(key) || !m[key].is_array() || m[key].size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!m[key][static_cast<size_t>(i)].is_number()) return false;
    (*out)[i] = m[key][static_cast<size_t>(i)].get<double>();
  }
  return out->allFinite() && out->norm() <= limit;
}

bool flag(const json& m, const char* key, bool* out) {
  if (!m.contains(key)) return true;  // optional, false
  if (!m[key].is_boolean()) return false;
  *out = m[key].get<bool>();
  return true;
}

}  // namespace

// The page side: the view service, the bus feed, and the page's messages.
class WebDevice::Page {
 public:
  Page(WebDevice& device, const web::WebServerOptions& options, const DeviceContext& context)
      : device_(device), context_(context), view_(options, 60.0), feed_(context.lcm_url, view_.bus(), context.key, "igms-haptic (web)") {
    view_.onPageMessage([this](int, bool authorized, const json& m) { return handle(authorized, m); });
    view_.frameExtra([this] { return extra(); });
    view_.statusExtra([this] {
      return ",\"device_targets\":" + std::to_string(targets_.load()) +
             ",\"commands_sent\":" + std::to_string(commands_.load());
    });
    view_.start();
  }
  std::string url() const { return view_.url(true); }

 private:
  PageMessage handle(bool authorized, const json& m) {
    const std::string type = m["type"];
    if (type != "device" && type != "command") return PageMessage::Malformed;
    if (!authorized) return PageMessage::NeedsToken;
    return type == "device" ? target(m) : command(m);
  }

  // {"type":"device","seq":N,"tip":[x,y,z],"active":b,"pull":b,"jump":b,
  //  "attach_link":"name","attach_point":[x,y,z],"rotation":[rx,ry,rz]}   (rotation: optional, |r| <= pi)
  PageMessage target(const json& m) {
    Target t;
    if (!m.contains("seq") || !m["seq"].is_number_integer()) return PageMessage::Malformed;
    t.seq = m["seq"].get<int64_t>();
    if (t.seq <= last_seq_) return PageMessage::Malformed;  // stale or replayed
    if (!vector3(m, "tip", 50.0, &t.tip)) return PageMessage::Malformed;
    bool jump = false;
    if (!flag(m, "active", &t.active) || !flag(m, "pull", &t.pull) || !flag(m, "jump", &jump))
      return PageMessage::Malformed;
    if (t.pull) {
      if (!m.contains("attach_link") || !m["attach_link"].is_string()) return PageMessage::Malformed;
      const std::string link = m["attach_link"];
      if (link.size() > 200 || (t.attach_frame = context_.frame_index(link)) < 0) return PageMessage::Malformed;
      if (!vector3(m, "attach_point", 10.0, &t.attach_point)) return PageMessage::Malformed;
      if (m.contains("rotation") && !vector3(m, "rotation", M_PI + 1e-9, &t.rotation)) return PageMessage::Malformed;
    }
    last_seq_ = t.seq;
    if (jump) {
      drag_seq_ = t.seq;
      drag_start_ = t.tip;
    }
    t.drag_seq = drag_seq_;  // the servo loop reads only the newest target: each carries its drag's start
    t.drag_start = drag_start_;
    device_.target_.write(t);
    ++targets_;
    return PageMessage::Handled;
  }

  // {"type":"command","kind":"pause"|"resume"|"step"|"reset"|"save","file":"name.yaml"}
  PageMessage command(const json& m) {
    if (!m.contains("kind") || !m["kind"].is_string()) return PageMessage::Malformed;
    const std::string kind = m["kind"];
    command_t c{};
    c.utime = wallMicros();
    c.seq = ++command_seq_;
    c.nvalues = 0;
    c.trajectory = {};
    if (kind == "pause") c.kind = command_t::PAUSE;
    else if (kind == "resume") c.kind = command_t::START;
    else if (kind == "step") c.kind = command_t::STEP;
    else if (kind == "reset") c.kind = command_t::RESET;
    else if (kind == "save") {
      // A plain file name in the server's folder: no paths from a page.
      static const std::regex kName("[A-Za-z0-9_.-]{1,64}\\.yaml");
      const std::string file = m.contains("file") && m["file"].is_string() ? m["file"].get<std::string>()
                                                                             : "edited_trajectory.yaml";
      if (!std::regex_match(file, kName) || file.find("..") != std::string::npos) return PageMessage::Malformed;
      c.kind = command_t::SAVE_TRAJECTORY;
      c.text = file;
    } else {
      return PageMessage::Malformed;
    }
    // On a signed bus the signature is the proof (the key never goes out); else the session token.
    c.auth = std::to_string(view_.bus().serverToken());  // binds it to this session, signed or not
    feed_.publish(channels::kCommand, c);
    ++commands_;
    return PageMessage::Handled;
  }

  std::string extra() {
    Vector3 tip, force, torque;
    device_.tip_shown_.read(&tip);
    device_.force_shown_.read(&force);
    device_.torque_shown_.read(&torque);
    Target t;
    device_.target_.read(&t);
    char buf[448];
    std::snprintf(buf, sizeof buf,
                  ",\"device\":{\"tip\":[%.5f,%.5f,%.5f],\"force\":[%.4f,%.4f,%.4f],\"torque\":[%.4f,%.4f,%.4f],"
                  "\"rotation\":[%.4f,%.4f,%.4f],\"active\":%s,\"pull\":%s,\"limit\":%.3g}",
                  tip.x(), tip.y(), tip.z(), force.x(), force.y(), force.z(), torque.x(), torque.y(), torque.z(),
                  t.rotation.x(), t.rotation.y(), t.rotation.z(), t.active ? "true" : "false",
                  t.pull ? "true" : "false", device_.limits_.max_force);
    return buf;
  }

  WebDevice& device_;
  DeviceContext context_;
  web::ViewService view_;
  web::BusFeed feed_;
  int64_t last_seq_ = 0;  // the web server's thread only
  int64_t drag_seq_ = 0;
  Vector3 drag_start_ = Vector3::Zero();
  int64_t command_seq_ = 0;
  std::atomic<int64_t> targets_{0}, commands_{0};
};

WebDevice::WebDevice(const std::string& args, const DeviceContext& context)
    : map_(context.map), follower_(map_.toScene(Vector3::Zero()) + Vector3(0.0, 0.0, 1.5)) {
  web::WebServerOptions options;
  options.port = kDefaultPort;
  options.page_dir = web::defaultPageDir();
  options.three_dir = web::kDebianThreeDir;
  options.token = newToken();
  static const std::regex kArgs("(?:([0-9.]+):)?([0-9]{1,5})");
  std::smatch match;
  if (!args.empty()) {
    if (!std::regex_match(args, match, kArgs) || std::stoi(match[2]) > 65535)
      throw std::runtime_error("--device web:" + args + ": expected web, web:PORT or web:ADDR:PORT");
    if (match[1].matched) options.bind = match[1];
    options.port = std::stoi(match[2]);
  }
  // Parked above the scene until the first drag, and after each.
  target_.write(Target{});
  tip_shown_.write(follower_.position());
  force_shown_.write(Vector3::Zero());
  torque_shown_.write(Vector3::Zero());
  limits_.max_torque = 1.0;  // N m: a 6-dof device's (the page shows it)
  page_ = std::make_unique<Page>(*this, options, context);
  name_ = "web:" + options.bind + ":" + std::to_string(options.port);
  std::printf("%s\n", page_->url().c_str());
  std::fflush(stdout);
}

WebDevice::~WebDevice() = default;

DeviceReading WebDevice::read(double t) {
  target_.read(&current_);
  const double dt = last_t_ < 0 ? 0.0 : std::clamp(t - last_t_, 0.0, 0.01);
  last_t_ = t;
  const Vector3& x = follower_.update(current_, dt, last_force_);
  tip_shown_.write(x);
  DeviceReading r;
  r.position = map_.toDevice(x);
  r.velocity = follower_.velocity() / map_.scale;
  r.buttons = current_.pull ? 1 : 0;
  r.attach_frame = current_.pull ? current_.attach_frame : -1;
  r.attach_point = current_.attach_point;
  // The orientation turns toward the page's (identity outside a pull) at most kMaxTurnRate.
  const double angle = current_.pull ? current_.rotation.norm() : 0.0;
  const Eigen::Quaterniond goal(angle > 0.0 ? Eigen::AngleAxisd(angle, current_.rotation / angle)
                                            : Eigen::AngleAxisd::Identity());
  const double gap = orientation_.angularDistance(goal);
  const double step = std::min(1.0, dt > 0.0 && gap > 0.0 ? kMaxTurnRate * dt / gap : (dt > 0.0 ? 1.0 : 0.0));
  const Eigen::Quaterniond next = orientation_.slerp(step, goal).normalized();
  const Eigen::AngleAxisd turn(next * orientation_.inverse());
  r.has_orientation = true;
  r.orientation = next;
  r.angular_velocity = dt > 0.0 ? Vector3(turn.angle() * turn.axis() / dt) : Vector3::Zero();
  orientation_ = next;
  return r;
}

void WebDevice::write(const Vector3& force) {
  last_force_ = force;
  force_shown_.write(force);
}

void WebDevice::writeTorque(const Vector3& torque) { torque_shown_.write(torque); }

IGMS_REGISTER_DEVICE((DeviceEntry{
    "web", "web[:[ADDR:]PORT]   the browser page and its mouse (default 127.0.0.1:8081; the URL with the token is printed)",
    [](const std::string& args, const DeviceContext& c) -> std::unique_ptr<HapticDevice> {
      return std::make_unique<WebDevice>(args, c);
    }}));

}  // namespace igms
