#include "web/view_service.h"

#include <chrono>
#include <cstdio>

#include "core/realtime/clock.h"

namespace igms::web {

ViewService::ViewService(const WebServerOptions& options, double frame_hz)
    : server_(options), frame_hz_(frame_hz), now_([] { return monotonicSeconds(); }) {}

ViewService::~ViewService() { stop(); }

void ViewService::start() {
  server_.onOpen([this](int client, bool authorized) { welcome(client, authorized); });
  // The page's first message held the token: it is the device now (its hello it already has).
  server_.onAuthorized([this](int client) { server_.send(client, "{\"type\":\"welcome\",\"role\":\"device\"}"); });
  server_.onMessage([this](int client, bool authorized, const std::string& text) { message(client, authorized, text); });
  server_.onStatus([this] {
    std::string s = ",\"bus_undecodable\":" + std::to_string(bus_.undecodable()) +
                    ",\"states\":" + std::to_string(bus_.states());
    if (status_extra_) s += status_extra_();
    return s;
  });
  server_.start();
  pump_ = std::thread([this] { pump(); });
}

void ViewService::stop() {
  stop_ = true;
  if (pump_.joinable()) pump_.join();
}

std::string ViewService::sceneError() const {
  std::lock_guard<std::mutex> lock(scene_mutex_);
  return scene_ ? scene_->error : "";
}

void ViewService::welcome(int client, bool authorized) {
  server_.send(client, std::string("{\"type\":\"welcome\",\"role\":\"") + (authorized ? "device" : "viewer") + "\"}");
  std::lock_guard<std::mutex> lock(scene_mutex_);
  if (scene_) server_.send(client, scene_->hello_json);
}

void ViewService::message(int client, bool authorized, const std::string& text) {
  nlohmann::json m = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  const bool shaped = m.is_object() && m.contains("type") && m["type"].is_string();
  const PageMessage r = shaped && handler_ ? handler_(client, authorized, m) : PageMessage::Malformed;
  if (r == PageMessage::Malformed) ++server_.counters().rejected_malformed;
  if (r == PageMessage::NeedsToken) ++server_.counters().rejected_token;
}

void ViewService::pump() {
  const auto period = std::chrono::duration<double>(1.0 / frame_hz_);
  auto next = std::chrono::steady_clock::now();
  while (!stop_) {
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
    session_info_t info;
    if (bus_.takeSession(&info)) {
      auto scene = std::make_shared<const SessionScene>(
          describeSession(info, [this](const std::string& file) { return server_.addFile(file); }));
      if (!scene->error.empty()) std::fprintf(stderr, "igms web view: %s\n", scene->error.c_str());
      {
        std::lock_guard<std::mutex> lock(scene_mutex_);
        scene_ = scene;
      }
      server_.sendAll(scene->hello_json);
    }
    std::string frame = bus_.frameJson(now_(), extra_ ? extra_() : std::string());
    if (!frame.empty()) server_.broadcastFrame(std::move(frame));
  }
}

}  // namespace igms::web
