// HttpServer: the page and the WebSocket only with the token; only the page's files, and every ES
// module the page imports (through index.html's import map, with the token); bounded requests;
// a WebSocket client gets hello, frames, and an error for a bad message. A client that stops
// reading holds a bounded queue and is dropped; idle connections are closed; out of file
// descriptors the server neither spins nor stops serving.
#include "server/http_server.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Json = nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// A small scene served on a free loopback port by a server on its own thread.
class Served {
 public:
  explicit Served(std::chrono::milliseconds write_timeout = 10s) {
    const std::filesystem::path file = dir_.write(
        "scene.json", R"({"camera": {"eye": [0, -300, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
      "image": {"width": 16, "height": 16},
      "objects": [{"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 40}}]})");
    SessionOptions session_options;
    session_options.log = false;
    session_ = std::make_unique<ViewerSession>(load_viewer_state(file), session_options);
    ServerOptions options;
    options.port = 0;
    options.web_dir = IMX_WEB_DIR;
    options.token = "0123456789abcdef0123456789abcdef";
    options.max_clients = 3;
    options.write_timeout = write_timeout;
    server_ = std::make_unique<HttpServer>(*session_, options);
    thread_ = std::thread([this] { server_->run(); });
  }
  ~Served() {
    server_->stop();
    thread_.join();
    session_->stop();
  }
  uint16_t port() const { return server_->port(); }
  static std::string token() { return "0123456789abcdef0123456789abcdef"; }
  ViewerSession& session() { return *session_; }
  HttpServer::Load load() const { return server_->load(); }
  // CPU seconds the server's network thread has used.
  double cpu_seconds() {
    clockid_t clock;
    timespec t{};
    if (pthread_getcpuclockid(thread_.native_handle(), &clock) != 0 ||
        clock_gettime(clock, &t) != 0)
      ADD_FAILURE() << "no CPU clock for the server thread";
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  // Waits (at most `timeout`) until `pred(load())`.
  bool wait_load(const std::function<bool(const HttpServer::Load&)>& pred,
                 std::chrono::milliseconds timeout = 5s) {
    for (const auto end = Clock::now() + timeout; Clock::now() < end;
         std::this_thread::sleep_for(10ms))
      if (pred(load())) return true;
    return pred(load());
  }

 private:
  test::TempDir dir_;
  std::unique_ptr<ViewerSession> session_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
};

http::response<http::string_body> get(
    uint16_t port, const std::string& target, size_t extra_header_bytes = 0,
    const std::vector<std::pair<http::field, std::string>>& headers = {
        {http::field::host, "127.0.0.1"}}) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> request(http::verb::get, target, 11);
  for (const auto& [field, value] : headers) request.set(field, value);
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
  EXPECT_EQ(get(s.port(), "/js/main.js" + t).result(), http::status::ok);
  EXPECT_EQ(get(s.port(), "/viewer.css" + t).result(), http::status::ok);
  EXPECT_EQ(get(s.port(), "/").result(), http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/js/main.js").result(), http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/?token=0123456789abcdef0123456789abcdee").result(),
            http::status::forbidden);
  EXPECT_EQ(get(s.port(), "/?token=").result(), http::status::forbidden);
  // Nothing but the page's files, whatever the path.
  EXPECT_EQ(get(s.port(), "/../CMakeLists.txt" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/etc/passwd" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/js/../index.html" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/js/no_such_module.js" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/js/" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/viewer.js" + t).result(), http::status::not_found);
  EXPECT_EQ(get(s.port(), "/" + t, 20000).result(), http::status::payload_too_large);
}

// A page from another site, or a name resolving to this machine (DNS rebinding), is refused
// before the token is looked at; the page's own origin, by IP or localhost, is answered.
TEST(HttpServer, OriginAndHostMustBeTheViewersOwn) {
  Served s;
  const std::string t = "?token=" + Served::token();
  const std::string own = fmt::format("127.0.0.1:{}", s.port());
  using Headers = std::vector<std::pair<http::field, std::string>>;
  auto status = [&](const Headers& h) { return get(s.port(), "/" + t, 0, h).result(); };
  EXPECT_EQ(status({{http::field::host, own}, {http::field::origin, "http://" + own}}),
            http::status::ok);
  EXPECT_EQ(status({{http::field::host, fmt::format("localhost:{}", s.port())}}), http::status::ok);
  const auto evil_origin =
      get(s.port(), "/" + t, 0,
          {{http::field::host, own}, {http::field::origin, "http://evil.example"}});
  EXPECT_EQ(evil_origin.result(), http::status::forbidden);
  EXPECT_NE(evil_origin.body().find("Origin 'http://evil.example'"), std::string::npos);
  EXPECT_EQ(status({{http::field::host, "evil.example"}}), http::status::forbidden);
  EXPECT_EQ(status({{http::field::host, fmt::format("evil.example:{}", s.port())}}),
            http::status::forbidden);
  EXPECT_EQ(status({{http::field::host, own}, {http::field::origin, "null"}}),
            http::status::forbidden);
  // Another local page (another port) is another origin.
  EXPECT_EQ(status({{http::field::host, own}, {http::field::origin, "http://127.0.0.1:1"}}),
            http::status::forbidden);
  // The WebSocket upgrade is held to the same rule.
  asio::io_context io;
  websocket::stream<beast::tcp_stream> ws(io);
  beast::get_lowest_layer(ws).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), s.port()));
  ws.set_option(websocket::stream_base::decorator(
      [](websocket::request_type& r) { r.set(http::field::origin, "http://evil.example"); }));
  beast::error_code ec;
  ws.handshake(own, "/ws" + t, ec);
  EXPECT_TRUE(ec) << "an upgrade from another site was accepted";
}

// The page runs under a Content-Security-Policy whose nonce its inline scripts carry, and sets
// the token's cookie, which then stands for the token in the address.
TEST(HttpServer, ThePageHasAPolicyAndATokenCookie) {
  Served s;
  const auto page = get(s.port(), "/?token=" + Served::token());
  ASSERT_EQ(page.result(), http::status::ok);
  const std::string policy(page["Content-Security-Policy"]);
  const size_t n = policy.find("'nonce-");
  ASSERT_NE(n, std::string::npos) << policy;
  const std::string nonce = policy.substr(n + 7, policy.find('\'', n + 7) - n - 7);
  EXPECT_EQ(nonce.size(), 32u);
  EXPECT_NE(policy.find("frame-ancestors 'none'"), std::string::npos);
  size_t scripts = 0;
  for (size_t at = page.body().find("<script"); at != std::string::npos;
       at = page.body().find("<script", at + 1), ++scripts)
    EXPECT_EQ(page.body().compare(at, 16 + nonce.size(), "<script nonce=\"" + nonce + "\""), 0);
  EXPECT_GE(scripts, 2u);
  EXPECT_NE(get(s.port(), "/?token=" + Served::token())["Content-Security-Policy"], policy)
      << "the nonce must change with every page";
  const std::string cookie(page[http::field::set_cookie]);
  const std::string pair = fmt::format("imx_token_{}={}", s.port(), Served::token());
  EXPECT_EQ(cookie.rfind(pair + ";", 0), 0u) << cookie;
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos);
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos);
  const auto with_cookie = [&](const std::string& value) {
    return get(s.port(), "/js/main.js", 0,
               {{http::field::host, "127.0.0.1"}, {http::field::cookie, "a=1; " + value}})
        .result();
  };
  EXPECT_EQ(with_cookie(pair), http::status::ok);
  EXPECT_EQ(with_cookie(fmt::format("imx_token_{}=0123", s.port())), http::status::forbidden);
  EXPECT_EQ(with_cookie(fmt::format("imx_token_1={}", Served::token())), http::status::forbidden);
}

// The module paths of index.html's import map: its list `const modules = ['main', ...]` gives
// each module ./js/NAME.js (resolved against the page, /js/NAME.js) with the token.
std::set<std::string> import_map_paths(const std::string& html) {
  std::smatch list;
  if (!std::regex_search(html, list, std::regex(R"(const modules = \[([^\]]*)\])"))) return {};
  std::set<std::string> paths;
  const std::string names = list[1];
  const std::regex name(R"('([A-Za-z0-9_-]+)')");
  for (auto it = std::sregex_iterator(names.begin(), names.end(), name);
       it != std::sregex_iterator(); ++it)
    paths.insert("/js/" + (*it)[1].str() + ".js");
  return paths;
}

// The specifiers a script imports: import '...', import ... from '...', export ... from '...',
// import('...').
std::vector<std::string> imports_of(const std::string& js) {
  const std::regex spec(
      R"(\b(?:import|export)\s*(?:[\w*{}\s,$]+\s*from\s*|\(\s*)?['"]([^'"]+)['"])");
  std::vector<std::string> specs;
  for (auto it = std::sregex_iterator(js.begin(), js.end(), spec); it != std::sregex_iterator();
       ++it)
    specs.push_back((*it)[1].str());
  return specs;
}

// Every module the page imports, followed from index.html's inline module through each module's
// imports, is in the import map (else the browser fetches it without the token, which is
// refused) and is served with the token (200, JavaScript), not without; and every module of the
// import map is imported by some module. A module file missing from web/js/ fails here.
TEST(HttpServer, ServesEveryModuleThePageImports) {
  Served s;
  const std::string t = "?token=" + Served::token();
  const std::string html = get(s.port(), "/" + t).body();
  const std::set<std::string> mapped = import_map_paths(html);
  ASSERT_FALSE(mapped.empty()) << "no `const modules = [...]` list in index.html";
  std::vector<std::pair<std::string, std::string>> pending;  // (path, the file that imports it)
  const auto add_imports = [&](const std::string& importer, const std::string& text) {
    const std::string dir = importer.substr(0, importer.rfind('/') + 1);
    for (const std::string& spec : imports_of(text)) {
      EXPECT_EQ(spec.rfind("./", 0), 0u)
          << importer << " imports '" << spec << "': page modules import './NAME.js'";
      pending.emplace_back(dir + spec.substr(spec.rfind("./", 0) == 0 ? 2 : 0), importer);
    }
  };
  add_imports("/index.html", html);
  ASSERT_FALSE(pending.empty()) << "index.html imports no module";
  std::set<std::string> seen;
  while (!pending.empty()) {
    const auto [path, importer] = pending.back();
    pending.pop_back();
    if (!seen.insert(path).second) continue;
    EXPECT_TRUE(mapped.count(path))
        << path << " (imported by " << importer
        << ") is not in index.html's import map: the browser would fetch it without the token";
    const auto module = get(s.port(), path + t);
    EXPECT_EQ(module.result(), http::status::ok) << path << ", imported by " << importer;
    EXPECT_EQ(module[http::field::content_type], "text/javascript; charset=utf-8") << path;
    EXPECT_EQ(get(s.port(), path).result(), http::status::forbidden) << path;
    if (module.result() == http::status::ok) add_imports(path, module.body());
  }
  for (const std::string& path : mapped)
    EXPECT_TRUE(seen.count(path)) << path << " is in the import map but no module imports it";
  EXPECT_GE(seen.size(), 5u);
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

// A session client that takes everything: it drives edits as a second browser would.
struct NullSink : ClientSink {
  void send_text(std::string) override {}
  void send_frame(std::string, std::string, bool) override {}
};

std::string move_message(int i) {
  return Json{{"type", "camera"},
              {"seq", i},
              {"moving", true},
              {"eye", {i % 100, -300.0, 10.0}},
              {"target", {0.0, 0.0, 0.0}}}
      .dump();
}

// A WebSocket client that reads nothing after its handshake, through a small receive buffer.
class Stalled {
 public:
  explicit Stalled(uint16_t port) : ws_(io_) {
    tcp::socket& socket = beast::get_lowest_layer(ws_).socket();
    socket.open(tcp::v4());
    socket.set_option(asio::socket_base::receive_buffer_size(4096));
    socket.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    ws_.handshake("127.0.0.1", "/ws?token=" + Served::token());
  }
  void send(const std::string& text) { ws_.write(asio::buffer(text)); }

 private:
  asio::io_context io_;
  websocket::stream<beast::tcp_stream> ws_;
};

// Moves the camera (as another browser would, through `mover`) until a client's socket is full:
// messages stay queued while the movements pause (or the client was dropped for it). False if
// that never happens.
bool move_until_stalled(Served& s, const std::shared_ptr<NullSink>& mover, int& sent) {
  const int clients = s.load().clients;
  while (sent < 500000) {
    for (int k = 0; k < 5000; ++k) s.session().on_message(mover, move_message(++sent));
    std::this_thread::sleep_for(50ms);  // a client that reads takes all in far less
    const HttpServer::Load l = s.load();
    if (l.queued_messages > 0 || l.clients < clients) return true;
  }
  return false;
}

// A browser tab that stopped reading while another client moves the camera 20,000 times: its
// queue keeps the newest state and frame only (it used to keep every state: +495 MB).
TEST(HttpServer, AClientThatDoesNotReadHoldsABoundedQueue) {
  Served s(10min);  // the 20,000 moves take 20 s in a sanitizer build: outlast them
  Stalled stalled(s.port());
  ASSERT_TRUE(s.wait_load([](const HttpServer::Load& l) { return l.clients == 1; }));
  auto mover = std::make_shared<NullSink>();
  s.session().add_client(mover);
  int sent = 0;
  ASSERT_TRUE(move_until_stalled(s, mover, sent)) << "the client's socket never filled";
  HttpServer::Load most;
  for (int i = 1; i <= 20000; ++i) {
    s.session().on_message(mover, move_message(++sent));
    if (i % 500 == 0) {
      const HttpServer::Load l = s.load();
      most.queued_messages = std::max(most.queued_messages, l.queued_messages);
      most.queued_bytes = std::max(most.queued_bytes, l.queued_bytes);
    }
  }
  std::this_thread::sleep_for(200ms);  // the network thread takes what is posted to it
  const HttpServer::Load now = s.load();
  // The message being written, one state and one frame.
  EXPECT_GE(now.queued_messages, 1u);
  EXPECT_LE(std::max(most.queued_messages, now.queued_messages), 3u);
  EXPECT_LT(std::max(most.queued_bytes, now.queued_bytes), 64u * 1024);
  EXPECT_EQ(now.clients, 1);  // within write_timeout: still a client
}

// A client whose socket takes no message within write_timeout is dropped; one that reads stays.
TEST(HttpServer, AStalledClientIsDropped) {
  // 2 s: long enough that the draining reader, starved of a core on a loaded machine (ctest -j2
  // beside builds), is not taken for stalled too; short enough for the test's time.
  Served s(2s);
  Stalled stalled(s.port());
  asio::io_context io;
  websocket::stream<beast::tcp_stream> reader(io);
  beast::get_lowest_layer(reader).connect(
      tcp::endpoint(asio::ip::make_address("127.0.0.1"), s.port()));
  reader.handshake("127.0.0.1", "/ws?token=" + Served::token());
  std::atomic<bool> reading{true};
  std::thread drain([&] {
    beast::flat_buffer buffer;
    beast::error_code ec;
    while (reading && !ec) {
      reader.read(buffer, ec);
      buffer.consume(buffer.size());
    }
  });
  ASSERT_TRUE(s.wait_load([](const HttpServer::Load& l) { return l.clients == 2; }));
  auto mover = std::make_shared<NullSink>();
  s.session().add_client(mover);
  int sent = 0;
  ASSERT_TRUE(move_until_stalled(s, mover, sent));
  EXPECT_TRUE(s.wait_load([](const HttpServer::Load& l) { return l.clients == 1; }, 10s))
      << s.load().clients << " clients";
  std::this_thread::sleep_for(2200ms);
  EXPECT_EQ(s.load().clients, 1);  // the reader
  reading = false;
  s.session().on_message(mover, move_message(++sent));  // wakes the reader
  drain.join();
}

// Replies are never replaced, so a client that sends but does not read its replies is dropped
// once kMaxQueuedReplies of them wait, long before write_timeout.
TEST(HttpServer, AClientThatDoesNotReadItsRepliesIsDropped) {
  Served s;
  Stalled stalled(s.port());
  ASSERT_TRUE(s.wait_load([](const HttpServer::Load& l) { return l.clients == 1; }));
  auto mover = std::make_shared<NullSink>();
  s.session().add_client(mover);
  int sent = 0;
  ASSERT_TRUE(move_until_stalled(s, mover, sent));
  for (size_t i = 0; i < kMaxQueuedReplies - 1; ++i) stalled.send("not json");
  // The server answers each in its own time (seconds on a loaded machine): wait for the replies.
  EXPECT_TRUE(s.wait_load(
      [](const HttpServer::Load& l) { return l.queued_messages >= kMaxQueuedReplies - 1; }, 10s))
      << s.load().queued_messages << " queued";
  EXPECT_EQ(s.load().clients, 1);
  for (int i = 0; i < 2; ++i) stalled.send("not json");
  EXPECT_TRUE(s.wait_load([](const HttpServer::Load& l) { return l.clients == 0; }, 2s));
  EXPECT_EQ(s.load().queued_messages, 0u);
}

// The loopback address of the server's port.
sockaddr_in loopback(uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

// Why the descriptor-exhaustion tests do not run under ASan/UBSan (their checks are real there;
// the sanitizers' own reports break once no descriptor is left).
constexpr const char* kSanitizersNeedDescriptors =
    "the sanitizers check memory through a pipe, which fails with no descriptor left: every "
    "vptr check of the render thread then reports a false error";

// `n` unconnected TCP sockets, made before a lowered limit so that only the server's accepts
// run out.
std::vector<int> sockets(int n) {
  std::vector<int> out(static_cast<size_t>(n));
  for (int& fd : out) fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  return out;
}

// The descriptor the next open would get: a limit above it by N leaves N to open.
int lowest_free_descriptor() {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  EXPECT_GE(fd, 0);
  ::close(fd);
  return fd;
}

// An idle connection, or one that sends its request slowly, is closed after kRequestTimeout
// (it used to be held 30 s, each holding a file descriptor).
TEST(HttpServer, ConnectionsWithoutACompleteRequestAreClosed) {
  Served s;
  auto connect = [&] {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const sockaddr_in address = loopback(s.port());
    EXPECT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    const timeval wait{5, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
    return fd;
  };
  const auto t0 = Clock::now();
  const int idle = connect(), slow = connect();
  const std::string part = "GET /?token=" + Served::token();  // never ends its request
  ASSERT_EQ(::send(slow, part.data(), part.size(), MSG_NOSIGNAL),
            static_cast<ssize_t>(part.size()));
  for (const int fd : {idle, slow}) {
    char byte;
    const ssize_t got = ::recv(fd, &byte, 1, 0);
    const int error = errno;
    EXPECT_LE(got, 0) << "the connection was not closed";
    if (got < 0) {
      EXPECT_NE(error, EAGAIN) << "still open after 5 s";
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_GT(seconds, 0.8 * std::chrono::duration<double>(kRequestTimeout).count());
  EXPECT_LT(seconds, std::chrono::duration<double>(kRequestTimeout).count() + 1.0);
  ::close(idle);
  ::close(slow);
}

// The soft RLIMIT_NOFILE for one scope.
class FileLimit {
 public:
  explicit FileLimit(rlim_t soft) {
    ::getrlimit(RLIMIT_NOFILE, &saved_);
    rlimit lowered = saved_;
    lowered.rlim_cur = soft;
    EXPECT_EQ(::setrlimit(RLIMIT_NOFILE, &lowered), 0);
  }
  ~FileLimit() { ::setrlimit(RLIMIT_NOFILE, &saved_); }

 private:
  rlimit saved_{};
};

// Idle connections that take every file descriptor: the accept loop used to retry EMFILE at
// once (a CPU at 100 %) and serve nobody. Now it closes the connection that has waited longest
// for a request (or, with none, sheds the backlog through a reserve descriptor and pauses), and
// serves the next client as soon as descriptors are free.
TEST(HttpServer, OutOfFileDescriptorsTheServerNeitherSpinsNorStops) {
#ifdef IMX_SANITIZED
  GTEST_SKIP() << kSanitizersNeedDescriptors;
#endif
  Served s;
  ASSERT_EQ(get(s.port(), "/?token=" + Served::token()).result(), http::status::ok);
  const std::vector<int> flood = sockets(40);
  const int lowest_free = lowest_free_descriptor();
  {
    FileLimit limit(static_cast<rlim_t>(lowest_free) + 8);  // the server may accept 8 at most
    const sockaddr_in address = loopback(s.port());
    for (const int fd : flood)
      ASSERT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    std::this_thread::sleep_for(200ms);
    // The server ran into the limit: at most the descriptor of the last connection it closed
    // for a pending one is left (connections waiting for a request make room for new ones).
    std::vector<int> left;
    for (int fd; (fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC)) >= 0;) left.push_back(fd);
    EXPECT_EQ(errno, EMFILE);
    EXPECT_LE(left.size(), 1u) << "descriptors left: the server did not run out";
    for (const int fd : left) ::close(fd);
    // Within kRequestTimeout: the server still holds its idle connections and has none left.
    const double cpu0 = s.cpu_seconds();
    std::this_thread::sleep_for(1s);
    EXPECT_LT(s.cpu_seconds() - cpu0, 0.1) << "the accept loop spins";
    for (const int fd : flood) ::close(fd);
    const auto t0 = Clock::now();
    EXPECT_EQ(get(s.port(), "/?token=" + Served::token()).result(), http::status::ok);
    EXPECT_LT(Clock::now() - t0, 1s);
  }
}

// Half-open connections that hold every descriptor the server may have, and stay open: the
// server closes the one that has waited longest for its request and accepts the next, so a
// client that sends its request is served within a second while the flood is still held
// (issue 48: 11 of 30 requests were served with 1,100 such connections).
TEST(HttpServer, AClientIsServedWhileHalfOpenConnectionsHoldEveryDescriptor) {
#ifdef IMX_SANITIZED
  GTEST_SKIP() << kSanitizersNeedDescriptors;
#endif
  Served s;
  ASSERT_EQ(get(s.port(), "/?token=" + Served::token()).result(), http::status::ok);
  const std::vector<int> flood = sockets(40);
  const int client = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int lowest_free = lowest_free_descriptor();
  const sockaddr_in address = loopback(s.port());
  std::string reply;
  {
    FileLimit limit(static_cast<rlim_t>(lowest_free) + 8);  // the server may accept 8 at most
    for (const int fd : flood)
      ASSERT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    std::this_thread::sleep_for(300ms);
    const auto t0 = Clock::now();
    ASSERT_EQ(::connect(client, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    const std::string request =
        "GET /?token=" + Served::token() + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    ASSERT_EQ(::send(client, request.data(), request.size(), 0),
              static_cast<ssize_t>(request.size()));
    timeval wait{2, 0};
    ::setsockopt(client, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
    char buffer[64] = {};
    const ssize_t n = ::recv(client, buffer, sizeof buffer - 1, 0);
    if (n > 0) reply.assign(buffer, static_cast<size_t>(n));
    EXPECT_LT(Clock::now() - t0, 1s);
  }
  EXPECT_EQ(reply.rfind("HTTP/1.1 200", 0), 0u) << "reply: '" << reply << "'";
  ::close(client);
  for (const int fd : flood) ::close(fd);
}

}  // namespace
}  // namespace imx::server
