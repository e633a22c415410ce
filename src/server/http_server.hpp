// HttpServer: the viewer's HTTP + WebSocket endpoint on Boost.Beast (docs/viewer.md). It serves
// the page from web/ (index.html, viewer.css, the ES modules js/*.js) and one WebSocket per
// client at /ws, all behind the session token, and passes WebSocket text messages to a
// ViewerSession. One network thread; rendering runs on the session's own thread.
#pragma once
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "server/viewer_session.hpp"

namespace imx::server {

struct ServerOptions {
  std::string bind = "127.0.0.1";  // loopback: remote use goes through an SSH tunnel
  uint16_t port = 8080;            // 0: any free port (port() says which)
  std::filesystem::path web_dir;   // index.html, viewer.css, js/*.js
  std::string token;               // every request must carry ?token=<this> (or its cookie)
  // Origins a page may come from besides the viewer's own address (request_guard.hpp).
  std::vector<std::string> allowed_origins;
  int max_clients = 32;  // WebSocket clients at once; more are refused (503)
  // A client whose socket has not taken one whole message (or a page response) within this
  // long has stopped reading: it is dropped instead of holding its queue (docs/viewer.md).
  std::chrono::milliseconds write_timeout{10000};
  // SIGINT and SIGTERM stop run(): a program's own server. A server inside another program (the
  // Python package's notebook views) leaves the signals to it.
  bool stop_on_signals = true;
};

// A connection that has not sent a complete HTTP request within this long is closed: idle and
// half-open connections must not hold the server's file descriptors.
inline constexpr std::chrono::milliseconds kRequestTimeout{2000};
// Replies (errors, saved, screenshots) a client may leave unread, and their bytes beyond the
// first; a client past either is dropped. States and frames do not count: a newer one replaces
// the unsent one.
inline constexpr size_t kMaxQueuedReplies = 64;
inline constexpr size_t kMaxQueuedReplyBytes = size_t{64} << 20;

// 32 hex digits from the system's random device.
std::string random_token();

class HttpServer {
 public:
  // Reads the page and binds; throws imx::Error naming the folder, file or address at fault.
  HttpServer(ViewerSession& session, ServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  uint16_t port() const;
  // http://ADDR:PORT/?token=TOKEN
  std::string url() const;
  // Serves until stop() (from any thread) or SIGINT / SIGTERM.
  void run();
  void stop();

  // What the server holds now (for tests): WebSocket clients, and the messages and bytes queued
  // for them. Each client queues at most one state, one frame and kMaxQueuedReplies replies.
  struct Load {
    int clients = 0;
    size_t queued_messages = 0;
    size_t queued_bytes = 0;
  };
  Load load() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace imx::server
