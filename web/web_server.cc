#include "web/web_server.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace igms::web {
namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;
constexpr size_t kMaxMessageBytes = 16 * 1024;  // a page's messages are small; more is malformed

bool readFile(const std::string& path, std::string* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  *out = s.str();
  return true;
}

std::string mimeOf(const std::string& path) {
  const size_t dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  if (ext == "html") return "text/html; charset=utf-8";
  if (ext == "js") return "application/javascript";  // module scripts need a JavaScript type
  if (ext == "css") return "text/css";
  if (ext == "json") return "application/json";
  if (ext == "dae") return "model/vnd.collada+xml";
  if (ext == "png") return "image/png";
  if (ext == "jpg" || ext == "jpeg") return "image/jpeg";
  return "application/octet-stream";
}

// A path from a request may not climb out of its folder.
bool safeRelative(const std::string& p) {
  if (p.empty() || p[0] == '/' || p.find('\\') != std::string::npos || p.find('\0') != std::string::npos) return false;
  std::istringstream s(p);
  std::string part;
  while (std::getline(s, part, '/'))
    if (part == ".." || part == ".") return false;
  return true;
}

// {"type":"auth","token":"..."}: a page presenting the token (its first message).
bool authMessage(const std::string& text, std::string* token) {
  if (text.size() > 512 || text.find("\"auth\"") == std::string::npos) return false;
  const nlohmann::json m = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!m.is_object() || !m.contains("type") || m["type"] != "auth") return false;
  *token = m.contains("token") && m["token"].is_string() ? m["token"].get<std::string>() : std::string();
  return true;
}

// Constant-time comparison: the token is a secret.
bool sameToken(const std::string& a, const std::string& b) {
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char d = 0;
  for (size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

}  // namespace

struct WebServer::Impl {
  Server server;
  std::thread thread;
  struct Connection {
    int id;
    bool authorized;
    bool first = true;  // no message yet: the one that may carry the token
  };
  std::map<Handle, Connection, std::owner_less<Handle>> connections;  // server thread only
  std::map<int, Handle> by_id;                                         // server thread only
  int next_id = 1;
  MessageHandler on_message;
  OpenHandler on_open;
  AuthorizedHandler on_authorized;
  std::function<std::string()> status_extra;
  std::mutex files_mutex;
  std::map<std::string, std::string> files;  // url path -> file
  int next_file = 1;

  void serveHttp(WebServer& w, Handle h);
  bool validateSocket(WebServer& w, Handle h);
  void openSocket(WebServer& w, Handle h);
  void closeSocket(WebServer& w, Handle h);
  void takeMessage(WebServer& w, Handle h, Server::message_ptr m);
  void listen(WebServer& w);
};

WebServer::WebServer(const WebServerOptions& options) : impl_(std::make_unique<Impl>()), options_(options) {}

WebServer::~WebServer() {
  if (!impl_->thread.joinable()) return;
  websocketpp::lib::error_code ec;
  impl_->server.stop_listening(ec);
  impl_->server.stop();
  impl_->thread.join();
}

void WebServer::onMessage(MessageHandler h) { impl_->on_message = std::move(h); }
void WebServer::onOpen(OpenHandler h) { impl_->on_open = std::move(h); }
void WebServer::onAuthorized(AuthorizedHandler h) { impl_->on_authorized = std::move(h); }
void WebServer::onStatus(std::function<std::string()> extra) { impl_->status_extra = std::move(extra); }

bool sameOrigin(const std::string& origin, const std::string& host, const std::string& bind, int port,
                bool allow_no_origin) {
  if (origin.empty()) return allow_no_origin;  // not a browser (a browser always sends Origin on a WebSocket)
  if (origin != "http://" + host && origin != "https://" + host) return false;  // another site's page
  // Bound to this machine only: the page must have come from a loopback name, so a site whose DNS name
  // resolves to 127.0.0.1 (DNS rebinding) is still another origin.
  const bool loopback = bind == "127.0.0.1" || bind == "::1" || bind == "localhost";
  if (!loopback) return true;
  const std::string p = ":" + std::to_string(port);
  return host == "127.0.0.1" + p || host == "localhost" + p || host == "[::1]" + p;
}

bool hostAllowed(const std::string& host, const std::string& bind, int port) {
  if (host.empty()) return false;
  if (bind == "0.0.0.0" || bind == "::") return true;
  std::string name = host, rest;
  if (host[0] == '[') {
    const size_t close = host.find(']');
    if (close == std::string::npos) return false;
    name = host.substr(0, close + 1);
    rest = host.substr(close + 1);
  } else if (const size_t colon = host.rfind(':'); colon != std::string::npos) {
    name = host.substr(0, colon);
    rest = host.substr(colon);
  }
  if (!rest.empty() && rest != ":" + std::to_string(port)) return false;
  const bool loopback = bind == "127.0.0.1" || bind == "::1" || bind == "localhost";
  if (loopback) return name == "127.0.0.1" || name == "localhost" || name == "[::1]";
  return name == bind || name == "[" + bind + "]";
}

std::string WebServer::url(bool with_token) const {
  std::string u = "http://" + options_.bind + ":" + std::to_string(port_) + "/";
  // In the fragment: a browser never sends it, so no server, proxy or Referer header sees the token.
  if (with_token && !options_.token.empty()) u += "#token=" + options_.token;
  return u;
}

std::string WebServer::addFile(const std::string& file) {
  std::lock_guard<std::mutex> lock(impl_->files_mutex);
  for (const auto& [url, path] : impl_->files)
    if (path == file) return url;
  const size_t slash = file.rfind('/');
  const std::string url =
      "/mesh/" + std::to_string(impl_->next_file++) + "/" + (slash == std::string::npos ? file : file.substr(slash + 1));
  impl_->files[url] = file;
  return url;
}

void WebServer::send(int client, std::string text) {
  Impl* impl = impl_.get();
  auto shared = std::make_shared<std::string>(std::move(text));
  impl->server.get_io_service().post([this, impl, client, shared] {
    const auto it = impl->by_id.find(client);
    if (it == impl->by_id.end()) return;
    websocketpp::lib::error_code ec;
    impl->server.send(it->second, *shared, websocketpp::frame::opcode::text, ec);
    if (!ec) counters_.bytes_sent += static_cast<int64_t>(shared->size());
  });
}

void WebServer::sendAll(std::string text) {
  Impl* impl = impl_.get();
  auto shared = std::make_shared<std::string>(std::move(text));
  impl->server.get_io_service().post([this, impl, shared] {
    for (const auto& [handle, c] : impl->connections) {
      websocketpp::lib::error_code ec;
      impl->server.send(handle, *shared, websocketpp::frame::opcode::text, ec);
      if (!ec) counters_.bytes_sent += static_cast<int64_t>(shared->size());
    }
  });
}

void WebServer::broadcastFrame(std::string text) {
  Impl* impl = impl_.get();
  auto shared = std::make_shared<std::string>(std::move(text));
  impl->server.get_io_service().post([this, impl, shared] {
    for (const auto& [handle, c] : impl->connections) {
      websocketpp::lib::error_code ec;
      Server::connection_ptr con = impl->server.get_con_from_hdl(handle, ec);
      if (ec) continue;
      if (con->get_buffered_amount() > shared->size()) {  // the last frame is still on its way
        ++counters_.frames_skipped;
        continue;
      }
      impl->server.send(handle, *shared, websocketpp::frame::opcode::text, ec);
      if (ec) continue;
      ++counters_.frames_sent;
      counters_.bytes_sent += static_cast<int64_t>(shared->size());
    }
  });
}

void WebServer::start() {
  Impl* impl = impl_.get();
  Server& s = impl->server;
  s.clear_access_channels(websocketpp::log::alevel::all);
  s.clear_error_channels(websocketpp::log::elevel::all);
  s.init_asio();
  s.set_reuse_addr(true);
  s.set_max_message_size(kMaxMessageBytes);
  s.set_http_handler([this, impl](Handle h) { impl->serveHttp(*this, h); });
  s.set_validate_handler([this, impl](Handle h) { return impl->validateSocket(*this, h); });
  s.set_open_handler([this, impl](Handle h) { impl->openSocket(*this, h); });
  s.set_close_handler([this, impl](Handle h) { impl->closeSocket(*this, h); });
  s.set_message_handler([this, impl](Handle h, Server::message_ptr m) { impl->takeMessage(*this, h, m); });
  impl->listen(*this);
}

// The server thread's handlers (Impl is WebServer's: they count in its counters).
void WebServer::Impl::serveHttp(WebServer& w, Handle h) {
  Server::connection_ptr con = server.get_con_from_hdl(h);
  ++w.counters_.http_requests;
  if (!hostAllowed(con->get_request_header("Host"), w.options_.bind, w.port_)) {
    ++w.counters_.rejected_host;
    con->set_status(websocketpp::http::status_code::forbidden);
    con->replace_header("Content-Type", "text/plain");
    con->set_body("this server answers to the names it is bound to, not to " + con->get_request_header("Host") + "\n");
    return;
  }
  std::string resource = con->get_resource();
  const size_t q = resource.find('?');
  if (q != std::string::npos) resource.resize(q);
  std::string file, body;
  if (resource == "/" || resource == "/index.html") {
    file = w.options_.page_dir + "/index.html";
  } else if (resource == "/status.json") {
    const WebCounters& c = w.counters_;
    std::ostringstream o;
    o << "{\"connections\":" << c.connections << ",\"messages\":" << c.messages
      << ",\"rejected_malformed\":" << c.rejected_malformed << ",\"rejected_token\":" << c.rejected_token
      << ",\"rejected_origin\":" << c.rejected_origin << ",\"rejected_host\":" << c.rejected_host
      << ",\"frames_sent\":" << c.frames_sent << ",\"frames_skipped\":" << c.frames_skipped
      << ",\"bytes_sent\":" << c.bytes_sent << ",\"http_requests\":" << c.http_requests
      << ",\"http_not_found\":" << c.http_not_found;
    if (status_extra) o << status_extra();
    o << "}";
    con->set_status(websocketpp::http::status_code::ok);
    con->replace_header("Content-Type", "application/json");
    con->replace_header("Cache-Control", "no-store");
    con->set_body(o.str());
    return;
  } else if (resource.rfind("/igms/", 0) == 0 && safeRelative(resource.substr(6))) {
    file = w.options_.page_dir + "/" + resource.substr(6);
  } else if (resource.rfind("/three/", 0) == 0 && safeRelative(resource.substr(7))) {
    file = w.options_.three_dir + "/" + resource.substr(7);
  } else if (resource.rfind("/mesh/", 0) == 0) {
    std::lock_guard<std::mutex> lock(files_mutex);
    const auto it = files.find(resource);
    if (it != files.end()) file = it->second;
  }
  if (file.empty() || !readFile(file, &body)) {
    ++w.counters_.http_not_found;
    con->set_status(websocketpp::http::status_code::not_found);
    con->replace_header("Content-Type", "text/plain");
    con->set_body("not found: " + resource + "\n");
    return;
  }
  con->set_status(websocketpp::http::status_code::ok);
  con->replace_header("Content-Type", mimeOf(file));
  con->replace_header("Cache-Control", "no-cache");
  con->set_body(std::move(body));
}

// Only a socket on /ws, from a page this server served (its Host and Origin), opens.
bool WebServer::Impl::validateSocket(WebServer& w, Handle h) {
  Server::connection_ptr con = server.get_con_from_hdl(h);
  const std::string r = con->get_resource();
  if (r != "/ws" && r.rfind("/ws?", 0) != 0) return false;
  if (!hostAllowed(con->get_request_header("Host"), w.options_.bind, w.port_)) {
    ++w.counters_.rejected_host;
    return false;
  }
  if (sameOrigin(con->get_request_header("Origin"), con->get_request_header("Host"), w.options_.bind, w.port_,
                 w.options_.allow_no_origin))
    return true;
  ++w.counters_.rejected_origin;
  return false;
}

void WebServer::Impl::openSocket(WebServer& w, Handle h) {
  const int id = next_id++;
  connections[h] = Impl::Connection{id, false};
  by_id[id] = h;
  ++w.counters_.connections;
  if (on_open) on_open(id, false);
}

void WebServer::Impl::closeSocket(WebServer& w, Handle h) {
  // A message over the size limit ends its connection (close code 1009): a rejection too.
  Server::connection_ptr con = server.get_con_from_hdl(h);
  if (con->get_local_close_code() == websocketpp::close::status::message_too_big) ++w.counters_.rejected_malformed;
  const auto it = connections.find(h);
  if (it == connections.end()) return;
  by_id.erase(it->second.id);
  connections.erase(it);
  --w.counters_.connections;
}

void WebServer::Impl::takeMessage(WebServer& w, Handle h, Server::message_ptr m) {
  ++w.counters_.messages;
  const auto it = connections.find(h);
  if (it == connections.end()) return;
  if (m->get_opcode() != websocketpp::frame::opcode::text) {
    ++w.counters_.rejected_malformed;
    return;
  }
  Impl::Connection& c = it->second;
  const bool first = c.first;
  c.first = false;
  std::string token;
  if (authMessage(m->get_payload(), &token)) {
    // One try, and only as the first message: a page cannot guess on and on over one socket.
    if (first && sameToken(token, w.options_.token)) {
      c.authorized = true;
      if (on_authorized) on_authorized(c.id);
    } else {
      ++w.counters_.rejected_token;
    }
    return;
  }
  if (on_message) on_message(c.id, c.authorized, m->get_payload());
}

// Listens on the bound address (a page that may act: this machine only) and runs the server's thread.
void WebServer::Impl::listen(WebServer& w) {
  Server& s = server;
  websocketpp::lib::error_code ec;
  boost::system::error_code address_error;
  const auto address = boost::asio::ip::make_address(w.options_.bind, address_error);
  if (address_error) throw std::runtime_error("--bind " + w.options_.bind + ": not an IP address");
  if (!w.options_.token.empty() && !address.is_loopback())
    throw std::runtime_error("--bind " + w.options_.bind +
                             ": a page that may act binds to this machine only (127.0.0.1): there is no TLS here, so "
                             "its token would cross the network in the clear; from another machine, use an SSH "
                             "tunnel (ssh -L PORT:127.0.0.1:PORT this-host)");
  s.listen(boost::asio::ip::tcp::endpoint(address, static_cast<unsigned short>(w.options_.port)), ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + w.options_.bind + ":" + std::to_string(w.options_.port) + ": " +
                             ec.message());
  boost::system::error_code endpoint_error;
  w.port_ = s.get_local_endpoint(endpoint_error).port();
  s.start_accept(ec);
  if (ec) throw std::runtime_error("cannot accept connections: " + ec.message());
  thread = std::thread([this] {
    try {
      server.run();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "igms web server: %s\n", e.what());
    }
  });
}

}  // namespace igms::web
