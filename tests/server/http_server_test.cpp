// HttpServer: the page and the WebSocket only with the token; only the page's files; bounded
// requests; a WebSocket client gets hello, frames, and an error for a bad message.
#include "server/http_server.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"

namespace imx::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Json = nlohmann::json;

// A small scene served on a free loopback port by a server on its own thread.
class Served {
 public:
  Served() {
    file_ = std::filesystem::temp_directory_path() /
            ("imx_http_server_test_" + std::to_string(::getpid()) + ".json");
    std::ofstream(file_)
        << R"({"camera": {"eye": [0, -300, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
      "image": {"width": 16, "height": 16},
      "objects": [{"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 40}}]})";
    SessionOptions session_options;
    session_options.log = false;
    session_ = std::make_unique<ViewerSession>(load_viewer_state(file_), session_options);
    ServerOptions options;
    options.port = 0;
    options.web_dir = IMX_WEB_DIR;
    options.token = "0123456789abcdef0123456789abcdef";
    options.max_clients = 2;
    server_ = std::make_unique<HttpServer>(*session_, options);
    thread_ = std::thread([this] { server_->run(); });
  }
  ~Served() {
    server_->stop();
    thread_.join();
    session_->stop();
    std::filesystem::remove(file_);
  }
  uint16_t port() const { return server_->port(); }
  static std::string token() { return "0123456789abcdef0123456789abcdef"; }

 private:
  std::filesystem::path file_;
  std::unique_ptr<ViewerSession> session_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
};

http::response<http::string_body> get(uint16_t port, const std::string& target,
                                      size_t extra_header_bytes = 0) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> request(http::verb::get, target, 11);
  request.set(http::field::host, "127.0.0.1");
  if (extra_header_bytes) request.set("X-Padding", std::string(extra_header_bytes, 'x'));
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  beast::error_code ec;
  http::read(stream, buffer, response, ec);
  return response;
}

TEST(HttpServer, ServesThePageOnlyWithTheToken) {
  Served s;
  const std::string t = "?token=" + Served::token();
  auto page = get(s.port(), "/" + t);
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_NE(page.body().find("<canvas id=\"view\""), std::string::npos);
  EXPECT_EQ(page[http::field::content_type], "text/html; charset=utf-8");
  EXPECT_EQ(get(s.port(), "/viewer.js" + t).result(), http::status::ok);
  EXPECT_EQ(get(s.port(), "/viewer.css" + t).result(), http::status::ok);
  EXPECT_EQ(get(s.port(), "/").result(), http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/viewer.js").result(), http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/?token=0123456789abcdef0123456789abcdee").result(),
            http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/?token=").result(), http::status::forbidden);
  // Nothing but the page's three files, whatever the path.
  EXPECT_EQ(get(s.port(), "/../CMakeLists.txt" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/etc/passwd" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/" + t, 20000).result(), http::status::payload_too_large);
}

TEST(HttpServer, WebSocketNeedsTheTokenAndAnswersBadMessages) {
  Served s;
  asio::io_context io;
  {
    websocket::stream<beast::tcp_stream> ws(io);
    beast::get_lowest_layer(ws).connect(
        tcp::endpoint(asio::ip::make_address("127.0.0.1"), s.port()));
    beast::error_code ec;
    ws.handshake("127.0.0.1", "/ws", ec);
    EXPECT_TRUE(ec) << "an upgrade without the token was accepted";
  }
  websocket::stream<beast::tcp_stream> ws(io);
  beast::get_lowest_layer(ws).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), s.port()));
  ws.handshake("127.0.0.1", "/ws?token=" + Served::token());
  beast::flat_buffer buffer;
  ws.read(buffer);
  const Json hello = Json::parse(beast::buffers_to_string(buffer.data()));
  EXPECT_EQ(hello["type"], "hello");
  EXPECT_EQ(hello["objects"][0]["name"], "ball");
  // The first frame: its JSON, then the PNG.
  for (;;) {
    buffer.consume(buffer.size());
    ws.read(buffer);
    if (!ws.got_text()) continue;
    const Json m = Json::parse(beast::buffers_to_string(buffer.data()));
    if (m["type"] != "frame") continue;
    buffer.consume(buffer.size());
    ws.read(buffer);
    EXPECT_FALSE(ws.got_text());
    EXPECT_EQ(beast::buffers_to_string(buffer.data()).substr(1, 3), "PNG");
    break;
  }
  ws.text(true);
  ws.write(asio::buffer(std::string(R"({"type": "edit", "object": "../../etc/passwd"})")));
  for (;;) {
    buffer.consume(buffer.size());
    ws.read(buffer);
    if (!ws.got_text()) continue;
    const Json m = Json::parse(beast::buffers_to_string(buffer.data()));
    if (m["type"] != "error") continue;
    EXPECT_NE(m["message"].get<std::string>().find("is not an object of the scene"),
              std::string::npos);
    break;
  }
  // A message over the bound closes the connection instead of being buffered.
  ws.write(asio::buffer(std::string(kMaxMessageBytes + 10, ' ')));
  beast::error_code ec;
  for (int i = 0; i < 100 && !ec; ++i) {
    buffer.consume(buffer.size());
    ws.read(buffer, ec);
  }
  EXPECT_TRUE(ec);
}

}  // namespace
}  // namespace imx::server
