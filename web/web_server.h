// The HTTP and WebSocket side of the browser view (websocketpp on Boost.Asio,
// one thread of its own). It serves the page, three.js from Debian's
// libjs-three, and the mesh files a model names (only those: a table of
// registered files, never a path from the request), and it talks to pages
// over WebSockets at /ws.
//
// Everything a page sends is untrusted. A page is a viewer unless the first
// message on its WebSocket is {"type":"auth","token":"..."} with the
// session's token (never in a URL, where logs, history and other local users'
// process lists would see it); one try per socket, a wrong or late one
// counted. What a page may do beyond watching is the owner's decision (the
// message handler gets the flag). A WebSocket must come from the page's own
// origin: another site's, or none (not a browser), is refused unless
// allow_no_origin. A server whose pages may act (a token) binds only to a
// loopback address: without TLS here the token would cross the network in
// the clear (reach it from elsewhere through an SSH tunnel). Frames go out
// newest-wins: a page whose socket still holds more than a frame's worth of
// unsent bytes skips frames instead of queueing them.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>

namespace igms::web {

struct WebServerOptions {
  std::string bind = "127.0.0.1";
  int port = 0;            // 0: any free port (see port())
  std::string token;       // empty: no page may act, all watch
  std::string page_dir;    // the page's files (index.html, *.js, *.css)
  std::string three_dir;   // Debian's libjs-three (/usr/share/javascript/three)
  bool allow_no_origin = false;  // take WebSockets without an Origin (not a browser: a script of one's own)
};


// Counters a test or the HUD reads (GET /status.json also returns them).
struct WebCounters {
  std::atomic<int64_t> connections{0};        // open WebSockets now
  std::atomic<int64_t> messages{0};           // received from pages
  std::atomic<int64_t> rejected_malformed{0}; // not JSON, unknown type, bad fields, too long
  std::atomic<int64_t> rejected_token{0};     // an action from a page without the token, or a wrong or late auth
  std::atomic<int64_t> rejected_origin{0};    // a WebSocket from another site's page (its Origin), refused
  std::atomic<int64_t> rejected_host{0};      // a request whose Host is not a name this server is bound to
  std::atomic<int64_t> frames_sent{0};
  std::atomic<int64_t> frames_skipped{0};     // newest-wins: the page had not taken the last one
  std::atomic<int64_t> bytes_sent{0};
  std::atomic<int64_t> http_requests{0};
  std::atomic<int64_t> http_not_found{0};
};

// A WebSocket's Origin against the page's own (the Host it was served from):
// the same site; with a loopback bind the host must be a loopback name too.
// No Origin (not a browser) only when `allow_no_origin`.
bool sameOrigin(const std::string& origin, const std::string& host, const std::string& bind, int port,
                bool allow_no_origin = false);

// A request's Host header against the names the server is bound to: for a loopback bind 127.0.0.1,
// localhost or [::1]; for one address, that address; for every address (0.0.0.0, ::) any name. With
// or without the port (then ours). A page of another site whose DNS name now resolves to 127.0.0.1
// (DNS rebinding) sends its own name: refused, so it reads neither /status.json nor the meshes.
bool hostAllowed(const std::string& host, const std::string& bind, int port);

class WebServer {
 public:
  // client: a connection id; authorized: it presented the token.
  using MessageHandler = std::function<void(int client, bool authorized, const std::string& text)>;
  using OpenHandler = std::function<void(int client, bool authorized)>;  // at open: never authorized yet
  using AuthorizedHandler = std::function<void(int client)>;              // its first message held the token

  explicit WebServer(const WebServerOptions& options);
  ~WebServer();  // stops the thread, closes every connection
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Handlers run on the server's thread; set them before start().
  void onMessage(MessageHandler handler);
  void onOpen(OpenHandler handler);
  void onAuthorized(AuthorizedHandler handler);
  // Extra JSON fields for GET /status.json (called on the server's thread).
  void onStatus(std::function<std::string()> extra_json);

  // Binds and starts the thread. Throws std::runtime_error naming the
  // address when it cannot bind, or when pages may act (a token) and the
  // address is not a loopback one.
  void start();
  int port() const { return port_; }
  // http://BIND:PORT/ (with ?token=... when `with_token`).
  std::string url(bool with_token) const;

  // Serve `file` at /mesh/<id>/<basename>; returns that URL path. Thread-safe.
  std::string addFile(const std::string& file);
  // To one page / to every page (newest-wins for frames). Thread-safe.
  void send(int client, std::string text);
  void sendAll(std::string text);  // reliable (not newest-wins): session descriptions
  void broadcastFrame(std::string text);

  WebCounters& counters() { return counters_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  WebServerOptions options_;
  int port_ = 0;
  WebCounters counters_;
};

}  // namespace igms::web
