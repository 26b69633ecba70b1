// The browser view as one service: the web server, the session as seen on
// the bus (BusView), and a frame pump that sends the newest frame to every
// page at display rate (default 60 Hz), decimated from the 1 kHz stream.
// igms-viewer (live or from a log) and the web device (igms-haptic --device
// web) are this service plus what they add: replay controls, or the mouse.
//
// Messages from pages are parsed here (JSON objects with a string "type",
// at most 16 kB); the owner's handler decides what a type means. Anything
// else is rejected and counted, and the session runs on.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "web/bus_view.h"
#include "web/session_scene.h"
#include "web/web_server.h"

namespace igms::web {

enum class PageMessage { Handled, Malformed, NeedsToken };

class ViewService {
 public:
  using Handler = std::function<PageMessage(int client, bool authorized, const nlohmann::json& message)>;

  ViewService(const WebServerOptions& options, double frame_hz);
  ~ViewService();

  // Before start(): the owner's message handler, extra frame fields
  // (",\"key\":value", called at frame rate), extra /status.json fields, the
  // clock frames are stamped with (default: wall seconds).
  void onPageMessage(Handler handler) { handler_ = std::move(handler); }
  void frameExtra(std::function<std::string()> extra) { extra_ = std::move(extra); }
  void statusExtra(std::function<std::string()> extra) { status_extra_ = std::move(extra); }
  void clock(std::function<double()> now) { now_ = std::move(now); }

  // Starts the web server and the pump. Throws std::runtime_error when the
  // address cannot be bound.
  void start();
  void stop();

  BusView& bus() { return bus_; }
  WebServer& server() { return server_; }
  std::string url(bool with_token) const { return server_.url(with_token); }
  // The newest scene description (empty before the first session info).
  std::string sceneError() const;

 private:
  void pump();
  void welcome(int client, bool authorized);
  void message(int client, bool authorized, const std::string& text);

  WebServer server_;
  BusView bus_;
  const double frame_hz_;
  Handler handler_;
  std::function<std::string()> extra_, status_extra_;
  std::function<double()> now_;
  std::thread pump_;
  std::atomic<bool> stop_{false};
  mutable std::mutex scene_mutex_;
  std::shared_ptr<const SessionScene> scene_;
};

}  // namespace igms::web
