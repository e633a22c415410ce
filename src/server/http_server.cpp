// HttpServer: Boost.Beast on one asio thread. Each TCP connection reads HTTP requests; a GET of
// the page answers from memory, an upgrade at /ws becomes a WebSocketClient that the session
// sends to. Every request needs the token; nothing else of the file system is reachable.
#include "server/http_server.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <deque>
#include <fstream>
#include <list>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"
#include "server/request_guard.hpp"

namespace imx::server {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

// Bounds on what one HTTP request may send: the page's requests are a few hundred bytes.
constexpr uint32_t kMaxHeaderBytes = 16 * 1024;
constexpr uint64_t kMaxBodyBytes = 1024;
// Out of file descriptors, the accept loop pauses this long instead of retrying at once.
constexpr auto kAcceptRetry = std::chrono::milliseconds(50);
// Pending connections one pause accepts and closes at most (the backlog is about as long).
constexpr int kMaxShedConnections = 4096;

// What every client together holds, for HttpServer::load().
struct Totals {
  std::atomic<int> clients{0};
  std::atomic<size_t> messages{0}, bytes{0};
};

struct PageFile {
  std::string body;
  std::string content_type;
};

// What a request must show to be answered, the same for every connection of a server.
struct Access {
  RequestGuard guard;
  std::string cookie;  // the name of the cookie that carries the token
};

// Compares in time that does not depend on where the strings differ.
bool same_token(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string_view header(const http::request<http::string_body>& request, http::field field) {
  const auto it = request.find(field);
  return it == request.end() ? std::string_view{}
                             : std::string_view(it->value().data(), it->value().size());
}

std::string_view path_of(std::string_view target) {
  return target.substr(0, target.find('?'));
}

// A page module's file name: letters, digits, '_' or '-', then ".js".
bool is_module_name(const std::string& name) {
  if (name.size() <= 3 || name.compare(name.size() - 3, 3, ".js") != 0) return false;
  return std::all_of(name.begin(), name.end() - 3, [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

// The page, read once: index.html (also at /), viewer.css, and each ES module web/js/NAME.js at
// /js/NAME.js (text/javascript, as module scripts need). Nothing else of `dir` is served.
std::map<std::string, PageFile> read_page(const std::filesystem::path& dir) {
  const auto unreadable = [](const std::filesystem::path& file) {
    return Error(fmt::format("{}: cannot read the viewer's page (give the web folder with --web)",
                             file.string()));
  };
  const auto read = [&](const std::filesystem::path& file) {
    std::ifstream in = try_open_input_stream(file);
    if (!in) throw unreadable(file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  };
  std::map<std::string, PageFile> page;
  page["/index.html"] = {read(dir / "index.html"), "text/html; charset=utf-8"};
  page["/viewer.css"] = {read(dir / "viewer.css"), "text/css; charset=utf-8"};
  const std::filesystem::path modules = dir / "js";
  std::error_code ec;
  for (std::filesystem::directory_iterator it(modules, ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_ec;
    if (is_module_name(name) && it->is_regular_file(type_ec))
      page["/js/" + name] = {read(it->path()), "text/javascript; charset=utf-8"};
  }
  if (ec) throw unreadable(modules);
  if (!page.count("/js/main.js")) throw unreadable(modules / "main.js");
  page["/"] = page["/index.html"];
  return page;
}

// A WebSocket client of the session: reads messages into it, writes what it sends in order.
// Its queue holds at most one unsent state and one unsent frame (the newest) and a bounded
// number of replies; a client whose socket takes no message for write_timeout is dropped.
class WebSocketClient : public ClientSink, public std::enable_shared_from_this<WebSocketClient> {
 public:
  WebSocketClient(tcp::socket socket, ViewerSession& session, Totals& totals,
                  std::chrono::milliseconds write_timeout)
      : ws_(std::move(socket)),
        stall_(ws_.get_executor()),
        session_(session),
        totals_(totals),
        write_timeout_(write_timeout) {
    ++totals_.clients;
  }
  ~WebSocketClient() override {
    forget(queue_.begin(), queue_.end());
    --totals_.clients;
  }

  void start(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxMessageBytes);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->session_.add_client(self);
      self->joined_ = true;
      self->read();
    });
  }

  void send_text(std::string text) override { enqueue({std::move(text), {}, false, Kind::reply}); }
  void send_state(std::string text) override { enqueue({std::move(text), {}, false, Kind::state}); }
  void send_frame(std::string text, std::string image, bool droppable) override {
    enqueue({std::move(text), std::move(image), true, droppable ? Kind::frame : Kind::reply});
  }

 private:
  // A reply is always sent (errors, saved, screenshots); an unsent state or frame gives way to
  // a newer one of its kind.
  enum class Kind { reply, state, frame };
  struct Outgoing {
    std::string text;
    std::string binary;  // sent after text when `has_binary`
    bool has_binary = false;
    Kind kind = Kind::reply;
    size_t bytes() const { return text.size() + binary.size(); }
  };
  using Queue = std::deque<Outgoing>;

  void enqueue(Outgoing message) {
    asio::post(ws_.get_executor(), [self = shared_from_this(), m = std::move(message)]() mutable {
      self->push(std::move(m));
    });
  }

  void push(Outgoing m) {
    if (closed_) return;
    const Queue::iterator unsent = queue_.begin() + (writing_ ? 1 : 0);
    if (m.kind != Kind::reply) {
      const auto old =
          std::find_if(unsent, queue_.end(), [&](const Outgoing& o) { return o.kind == m.kind; });
      if (old != queue_.end()) forget(old, old + 1);
    } else {
      size_t replies = 0, bytes = 0;
      for (const Outgoing& o : queue_)
        if (o.kind == Kind::reply) ++replies, bytes += o.bytes();
      // The first reply always fits: a screenshot may be larger than the bound.
      if (replies >= kMaxQueuedReplies || (replies > 0 && bytes + m.bytes() > kMaxQueuedReplyBytes))
        return drop();  // it does not read its own replies
    }
    ++totals_.messages;
    totals_.bytes += m.bytes();
    queue_.push_back(std::move(m));
    if (!writing_) write_next(false);
  }

  void forget(Queue::iterator first, Queue::iterator last) {
    for (auto it = first; it != last; ++it) {
      --totals_.messages;
      totals_.bytes -= it->bytes();
    }
    queue_.erase(first, last);
  }

  // Writes the front message's text, then (`binary_part`) its image.
  void write_next(bool binary_part) {
    if (queue_.empty() || closed_) {
      writing_ = false;
      stall_.cancel();
      return;
    }
    writing_ = true;
    if (!binary_part) watch();
    const Outgoing& m = queue_.front();
    ws_.text(!binary_part);
    const std::string& payload = binary_part ? m.binary : m.text;
    ws_.async_write(asio::buffer(payload),
                    [self = shared_from_this(), binary_part](beast::error_code ec, size_t) {
                      if (ec) return self->close();
                      if (!binary_part && self->queue_.front().has_binary)
                        return self->write_next(true);
                      self->forget(self->queue_.begin(), self->queue_.begin() + 1);
                      self->write_next(false);
                    });
  }

  // The message now being written must be taken within write_timeout_.
  void watch() {
    stall_.expires_after(write_timeout_);
    stall_.async_wait([self = shared_from_this(), write = ++writes_](beast::error_code ec) {
      if (!ec && write == self->writes_ && self->writing_) self->drop();
    });
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) return self->close();
      const std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      if (self->ws_.got_text())
        self->session_.on_message(self, text);
      else
        self->send_text(
            R"({"type":"error","message":"message: binary messages are not part of the protocol"})");
      self->read();
    });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    stall_.cancel();
    // A message being written stays until its write ends: the socket reads from it.
    forget(queue_.begin() + (writing_ ? 1 : 0), queue_.end());
    if (joined_) session_.remove_client(this);
  }

  // A client that stopped reading: its socket closes, its pending reads and writes end.
  void drop() {
    close();
    beast::get_lowest_layer(ws_).close();
  }

  websocket::stream<beast::tcp_stream> ws_;
  asio::steady_timer stall_;
  ViewerSession& session_;
  Totals& totals_;
  const std::chrono::milliseconds write_timeout_;
  beast::flat_buffer buffer_;
  Queue queue_;
  uint64_t writes_ = 0;  // messages whose write began; a stall timer is for the latest only
  bool writing_ = false;
  bool closed_ = false;
  bool joined_ = false;
};

class HttpConnection;

// The connections waiting for a request (half-open ones, idle keep-alives), oldest first: when
// the descriptors run out, the oldest is closed for the next connection (HttpServer::Impl).
// Only the server's one network thread touches it.
using WaitingConnections = std::list<std::weak_ptr<HttpConnection>>;

// One TCP connection's HTTP requests, until it upgrades to a WebSocket or closes.
class HttpConnection : public std::enable_shared_from_this<HttpConnection> {
 public:
  HttpConnection(tcp::socket socket, ViewerSession& session,
                 const std::map<std::string, PageFile>& page, const ServerOptions& options,
                 const Access& access, Totals& totals, WaitingConnections& waiting)
      : stream_(std::move(socket)),
        session_(session),
        page_(page),
        options_(options),
        access_(access),
        totals_(totals),
        waiting_(waiting) {}
  ~HttpConnection() { stop_waiting(); }

  void read() {
    parser_.emplace();
    parser_->header_limit(kMaxHeaderBytes);
    parser_->body_limit(kMaxBodyBytes);
    stream_.expires_after(kRequestTimeout);  // the whole request, however slowly it comes
    if (!in_waiting_) in_waiting_ = waiting_.insert(waiting_.end(), weak_from_this());
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, size_t) {
                       self->stop_waiting();
                       if (ec) return self->fail(ec);
                       self->answer(self->parser_->release());
                     });
  }

  // Closes the connection, whose request has not come, to free its descriptor.
  void evict() {
    stop_waiting();
    beast::error_code ec;
    stream_.socket().close(ec);
  }

 private:
  void stop_waiting() {
    if (in_waiting_) waiting_.erase(*std::exchange(in_waiting_, std::nullopt));
  }

  void fail(beast::error_code ec) {
    // A request over the limits gets its answer; timeouts and closed connections just end.
    if (ec == http::error::header_limit || ec == http::error::body_limit)
      respond(http::status::payload_too_large, "request too large\n", "text/plain", 11, false);
    else
      stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
  }

  void answer(http::request<http::string_body> request) {
    const std::string_view target(request.target().data(), request.target().size());
    const bool keep_alive = request.keep_alive();
    const unsigned version = request.version();
    const std::string_view host = header(request, http::field::host);
    // Who asks before what they carry: a page from another site must not learn even that the
    // token is wrong.
    std::string refused = access_.guard.check_host(host);
    if (refused.empty())
      refused = access_.guard.check_origin(header(request, http::field::origin), host);
    if (!refused.empty())
      return respond(http::status::forbidden, "forbidden: " + refused + "\n", "text/plain", version,
                     false);
    csp_ = content_security_policy(host, "");
    const std::string_view token =
        request_token(target, header(request, http::field::cookie), access_.cookie);
    if (!same_token(token, options_.token))
      return respond(http::status::forbidden, "forbidden: this address needs the session token\n",
                     "text/plain", version, false);
    const std::string path(path_of(target));
    if (websocket::is_upgrade(request)) {
      if (path != "/ws")
        return respond(http::status::not_found, "not found\n", "text/plain", version, false);
      if (totals_.clients.load() >= options_.max_clients)
        return respond(http::status::service_unavailable,
                       fmt::format("this session already has {} clients\n", options_.max_clients),
                       "text/plain", version, false);
      stream_.expires_never();
      auto client = std::make_shared<WebSocketClient>(stream_.release_socket(), session_, totals_,
                                                      options_.write_timeout);
      client->start(std::move(request));
      return;
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head)
      return respond(http::status::method_not_allowed, "only GET\n", "text/plain", version, false);
    const auto file = page_.find(path);
    if (file == page_.end())
      return respond(http::status::not_found, "not found\n", "text/plain", version, keep_alive);
    std::string body = file->second.body;
    if (file->second.content_type.rfind("text/html", 0) == 0) {
      // The page's inline scripts run by this response's nonce; the token goes into a cookie, so
      // that the page may take it out of the address bar and still be reloaded.
      const std::string nonce = random_token();
      for (size_t at = body.find("<script"); at != std::string::npos;
           at = body.find("<script", at + 1))
        body.insert(at + 7, " nonce=\"" + nonce + "\"");
      csp_ = content_security_policy(host, nonce);
      set_cookie_ =
          fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict", access_.cookie, options_.token);
    }
    respond(http::status::ok, std::move(body), file->second.content_type, version, keep_alive,
            request.method() == http::verb::head);
  }

  void respond(http::status status, std::string body, const std::string& type, unsigned version,
               bool keep_alive, bool head = false) {
    auto response = std::make_shared<http::response<http::string_body>>(status, version);
    response->set(http::field::server, "intermix");
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-store");
    // The token is in the address: no page it links to may learn it.
    response->set("Referrer-Policy", "no-referrer");
    response->set("X-Content-Type-Options", "nosniff");
    response->set("X-Frame-Options", "DENY");
    if (!csp_.empty()) response->set("Content-Security-Policy", csp_);
    if (!set_cookie_.empty()) response->set(http::field::set_cookie, set_cookie_);
    csp_.clear();
    set_cookie_.clear();
    response->keep_alive(keep_alive);
    response->body() = std::move(body);
    response->prepare_payload();
    if (head) response->body().clear();
    stream_.expires_after(options_.write_timeout);
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code ec, size_t) {
                        if (ec || !response->keep_alive()) {
                          self->stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
                          return;
                        }
                        self->read();
                      });
  }

  beast::tcp_stream stream_;
  ViewerSession& session_;
  const std::map<std::string, PageFile>& page_;
  const ServerOptions& options_;
  const Access& access_;
  Totals& totals_;
  WaitingConnections& waiting_;
  std::optional<WaitingConnections::iterator> in_waiting_;  // while a request is awaited
  std::string csp_, set_cookie_;                            // of the response being made
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

std::string random_token() {
  std::random_device device;
  std::string token;
  for (int i = 0; i < 4; ++i) token += fmt::format("{:08x}", static_cast<uint32_t>(device()));
  return token;
}

struct HttpServer::Impl {
  Impl(ViewerSession& s, ServerOptions o)
      : session(s),
        options(std::move(o)),
        acceptor(io),
        retry(io),
        signals(io),
        reserve(::open("/dev/null", O_RDONLY | O_CLOEXEC)) {}
  ~Impl() {
    if (reserve >= 0) ::close(reserve);
  }

  void accept() {
    acceptor.async_accept(asio::make_strand(io), [this](beast::error_code ec, tcp::socket socket) {
      if (ec == asio::error::operation_aborted) return;
      if (ec) {
        // Out of file descriptors: the connection that has waited longest for its request is
        // closed, and the pending one accepted in its place (issue 48: 1,100 half-open
        // connections otherwise shut out every client).
        if ((ec == asio::error::no_descriptors || ec.value() == ENFILE) && evict_oldest())
          return accept();
        // None waiting (or out of memory): the connection stays pending and accepting again at
        // once would spin. Shed the backlog, then pause.
        shed();
        retry.expires_after(kAcceptRetry);
        retry.async_wait([this](beast::error_code e) {
          if (!e) accept();
        });
        return;
      }
      // A frame is a text then a binary message: without this, Nagle's algorithm held the second
      // write for the client's delayed ACK (40 ms on Linux), most of a 2-D view's latency.
      beast::error_code no_delay;
      socket.set_option(tcp::no_delay(true), no_delay);
      std::make_shared<HttpConnection>(std::move(socket), session, page, options, access, totals,
                                       waiting)
          ->read();
      accept();
    });
  }

  // Closes the connection that has waited longest for a request; false when none waits.
  bool evict_oldest() {
    while (!waiting.empty()) {
      const std::shared_ptr<HttpConnection> oldest = waiting.front().lock();
      if (!oldest) {
        waiting.pop_front();
        continue;
      }
      oldest->evict();  // leaves the list
      return true;
    }
    return false;
  }

  // Accepts and closes the pending connections in the descriptor the reserve frees, so that the
  // backlog drains (its clients see the connection close) while the held ones time out.
  void shed() {
    if (reserve >= 0) ::close(reserve);
    for (int i = 0; i < kMaxShedConnections; ++i) {
      const int fd = ::accept4(acceptor.native_handle(), nullptr, nullptr, SOCK_CLOEXEC);
      if (fd < 0) break;  // none pending (the acceptor does not block), or the slot is gone
      ::close(fd);
    }
    reserve = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  }

  ViewerSession& session;
  ServerOptions options;
  std::map<std::string, PageFile> page;
  Access access;
  Totals totals;               // before io: the handlers io destroys last still count down
  WaitingConnections waiting;  // before io: connections leave it as io destroys them
  asio::io_context io{1};
  tcp::acceptor acceptor;
  asio::steady_timer retry;  // the accept loop's pause
  asio::signal_set signals;
  int reserve = -1;  // a descriptor kept open to be freed when there are none
};

HttpServer::HttpServer(ViewerSession& session, ServerOptions options)
    : impl_(std::make_unique<Impl>(session, std::move(options))) {
  Impl& s = *impl_;
  if (s.options.token.empty()) s.options.token = random_token();
  s.page = read_page(s.options.web_dir);
  beast::error_code ec;
  const auto address = asio::ip::make_address(s.options.bind, ec);
  if (ec) throw Error(fmt::format("--bind: '{}' is not an IP address", s.options.bind));
  const tcp::endpoint endpoint(address, s.options.port);
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (!ec) s.acceptor.non_blocking(true, ec);  // shed() must not wait for a connection
  if (ec)
    throw Error(
        fmt::format("cannot listen on {}:{}: {}", s.options.bind, s.options.port, ec.message()));
  s.access.guard.allowed_origins = s.options.allowed_origins;
  s.access.cookie = token_cookie_name(port());
}

HttpServer::~HttpServer() = default;

uint16_t HttpServer::port() const {
  return impl_->acceptor.local_endpoint().port();
}

std::string HttpServer::url() const {
  const std::string host = impl_->options.bind.find(':') != std::string::npos
                               ? "[" + impl_->options.bind + "]"
                               : impl_->options.bind;
  return fmt::format("http://{}:{}/?token={}", host, port(), impl_->options.token);
}

HttpServer::Load HttpServer::load() const {
  const Totals& t = impl_->totals;
  return {t.clients.load(), t.messages.load(), t.bytes.load()};
}

void HttpServer::run() {
  Impl& s = *impl_;
  if (s.options.stop_on_signals) {
    s.signals.add(SIGINT);
    s.signals.add(SIGTERM);
    s.signals.async_wait([&s](beast::error_code ec, int) {
      if (!ec) s.io.stop();
    });
  }
  s.accept();
  s.io.run();
}

void HttpServer::stop() {
  impl_->io.stop();
}

}  // namespace imx::server
