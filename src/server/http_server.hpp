// HttpServer: the viewer's HTTP + WebSocket endpoint on Boost.Beast (docs/viewer.md). It serves
// the page's three files from web/ and one WebSocket per client at /ws, all behind the session
// token, and passes WebSocket text messages to a ViewerSession. One network thread; rendering
// runs on the session's own thread.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "server/viewer_session.hpp"

namespace imx::server {

struct ServerOptions {
  std::string bind = "127.0.0.1";  // loopback: remote use goes through an SSH tunnel
  uint16_t port = 8080;            // 0: any free port (port() says which)
  std::filesystem::path web_dir;   // index.html, viewer.js, viewer.css
  std::string token;               // every request must carry ?token=<this>
  int max_clients = 32;            // WebSocket clients at once; more are refused (503)
};

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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace imx::server
