// ViewerSession: the shared state of one viewer session and the render thread behind it.
#include "server/viewer_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "io/streams/atomic_file.hpp"
#include "scene/json_reader.hpp"
#include "scene/strict_json.hpp"
#include "server/annotation_messages.hpp"
#include "server/jpeg_encoder.hpp"
#include "tubes/tube_cache.hpp"

namespace imx::server {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;
using scene_json::JsonReader;
using scene_json::Range;

namespace {

constexpr int kDefaultViewerSpp = 4;
constexpr int kMaxViewerSpp = 64;
constexpr size_t kMaxLatenciesPerReport = 1024;
constexpr size_t kMaxLatenciesKept = 100000;
// Numbered saves of one scene (NAME.viewer-N.json) before save asks the user to tidy up.
constexpr int kMaxSaves = 9999;
// zlib level of still frames: level 1 encodes several times faster than the default and the
// frames are sent once each.
constexpr int kStillPngLevel = 1;

// A page's `viewport` [width, height] (its canvas's device pixels), scaled down to at most
// `max_side` a side keeping its aspect: the size still frames are rendered at.
std::pair<int, int> fitted_viewport(const JsonReader& v, int max_side) {
  const std::vector<double> size = v.numbers(2, Range::closed(16.0, 16384.0));
  const double shrink = std::min(1.0, max_side / std::max(size[0], size[1]));
  return {std::max(16, static_cast<int>(std::lround(size[0] * shrink))),
          std::max(16, static_cast<int>(std::lround(size[1] * shrink)))};
}

// JSON text for a client. Error messages quote what a client sent, shortened, possibly inside a
// UTF-8 sequence: such bytes become U+FFFD instead of making dump() throw.
std::string text_of(const Json& message, int indent = -1) {
  return message.dump(indent, ' ', false, Json::error_handler_t::replace);
}

// Where nlohmann's parser stopped: the path of the value it was reading ("eye[1]", "opacity")
// and that value's text, so that an error names the field (a number out of a double's range
// fails while it is read, before the strict parser's callback sees it).
class ParseStop final : public nlohmann::json_sax<Json> {
 public:
  std::string path, token;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(size_t) override { return open(false); }
  bool key(string_t& key) override {
    open_.back().key = key;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(size_t, const std::string& last_token,
                   const nlohmann::detail::exception&) override {
    for (const Open& o : open_) {
      // The innermost array's failing element is the one after the last it read.
      const long index = o.index + (&o == &open_.back() ? 1 : 0);
      path += o.array ? fmt::format("[{}]", index) : (path.empty() ? "" : ".") + o.key;
    }
    token = last_token;
    return false;
  }

 private:
  struct Open {
    bool array = false;
    long index = -1;  // arrays: the element read last
    std::string key;  // objects: the key read last
  };
  bool value() {
    if (!open_.empty() && open_.back().array) ++open_.back().index;
    return true;
  }
  bool open(bool array) {
    value();
    open_.push_back({array, -1, {}});
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }
  std::vector<Open> open_;
};

// nlohmann's text without its "[json.exception.parse_error.101] " prefix.
std::string readable(const Json::exception& e) {
  const std::string what = e.what();
  const size_t at = what.find("] ");
  return at == std::string::npos ? what : what.substr(at + 2);
}

// A message as JSON, strictly; throws imx::Error for any text nlohmann refuses.
Json parse_message(std::string_view text) {
  try {
    return scene_json::parse_strict_json(std::string(text), "message");
  } catch (const Json::parse_error& e) {
    throw Error("message: not JSON: " + readable(e));  // it names the line and column
  } catch (const Json::exception& e) {  // a number beyond a double's range (out_of_range.406)
    ParseStop stop;
    Json::sax_parse(text, &stop);
    if (stop.token.empty()) throw Error("message: " + readable(e));
    throw Error(fmt::format("message: {}{} is beyond the range of a number (about 1.8e308)",
                            stop.path.empty() ? "" : stop.path + ": ", stop.token));
  }
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool perfect_square(int n) {
  const int r = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  return r * r == n;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t at = static_cast<size_t>(std::ceil(p * static_cast<double>(values.size()))) - 1;
  return values[std::min(at, values.size() - 1)];
}

}  // namespace

int viewer_spp(const Scene& scene, int requested) {
  const int spp = requested > 0          ? requested
                  : scene.render.spp > 0 ? scene.render.spp
                                         : kDefaultViewerSpp;
  if (spp > kMaxViewerSpp || !perfect_square(spp))
    throw Error(fmt::format("spp: {} is not a perfect square from 1 to {} (the viewer's range)",
                            spp, kMaxViewerSpp));
  return spp;
}

std::string viewer_method(const ViewerState& state, const std::string& requested) {
  std::string method = requested;
  if (method.empty()) {
    const Json& document = state.document.json();
    const auto render = document.find("render");
    if (render != document.end() && render->is_object() && render->contains("method") &&
        (*render)["method"].is_string())
      method = (*render)["method"].get<std::string>();
    else if (state.scene().csg || state.scene().render.mixing == "exclusive")
      method = "csg";  // the methods that render CSG and exclusive mixing: csg and reference
    else
      method = "zslab";
  }
  const std::vector<std::string> methods = available_methods();
  if (std::find(methods.begin(), methods.end(), method) == methods.end())
    throw Error(fmt::format("method: '{}' is not available; this build has: {}", method,
                            fmt::join(methods, ", ")));
  return method;
}

// What the render thread takes from the shared state for one frame.
struct ViewerSession::Snapshot {
  Scene scene;
  std::string method;
  int spp = 1;
  bool moving = false;
  uint64_t version = 0;
  std::vector<std::pair<const ClientSink*, long long>> seqs;  // each client's latest input
  std::vector<std::weak_ptr<ClientSink>> screenshot_to;
  bool full_resolution = false;  // the converged still frame's full-resolution successor
  Json document;                 // for it: the saved document
};

ViewerSession::ViewerSession(ViewerState state, SessionOptions options)
    : state_(std::move(state)), options_(std::move(options)) {
  method_ = last_good_method_ = viewer_method(state_, options_.method);
  spp_ = viewer_spp(state_.scene(), options_.spp);
  histograms_ = describe_histograms(state_.scene());
  tf_presets_ = describe_tf_presets();
  resolution_ = ResolutionControl(options_.moving_budget_ms);
  last_input_ = Clock::now();
  thread_ = std::thread([this] { render_loop(); });
}

ViewerSession::~ViewerSession() {
  stop();
}

void ViewerSession::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    cancel_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ViewerSession::reply_error(ClientSink& client, const std::string& message) {
  client.send_text(text_of(Json{{"type", "error"}, {"message", message}}));
}

Json ViewerSession::state_message() const {
  Json m = describe_state(state_);
  m["type"] = "state";
  m["method"] = method_;
  m["spp"] = spp_;
  return m;
}

void ViewerSession::broadcast_text(const std::string& text) {
  for (const Client& c : clients_)
    if (auto sink = c.sink.lock()) sink->send_text(text);
}

void ViewerSession::broadcast_state() {
  const std::string text = text_of(state_message());
  for (const Client& c : clients_)
    if (auto sink = c.sink.lock()) sink->send_state(text);
}

void ViewerSession::add_client(const std::shared_ptr<ClientSink>& client) {
  std::lock_guard lock(mutex_);
  Json hello = describe_state(state_);
  hello["type"] = "hello";
  hello["methods"] = available_methods();
  hello["method"] = method_;
  hello["spp"] = spp_;
  hello["image"] = {{"width", state_.scene().image.width}, {"height", state_.scene().image.height}};
  hello["histograms"] = histograms_;
  hello["tf_presets"] = tf_presets_;
  client->send_text(text_of(hello));
  if (!last_frame_text_.empty()) client->send_frame(last_frame_text_, last_frame_image_, true);
  clients_.push_back({client, client.get(), 0});
  if (options_.log)
    std::fprintf(stderr, "intermix serve: client joined (%zu now)\n", clients_.size());
}

void ViewerSession::remove_client(const ClientSink* client) {
  std::lock_guard lock(mutex_);
  std::erase_if(clients_, [&](const Client& c) { return c.id == client || c.sink.expired(); });
  if (options_.log)
    std::fprintf(stderr, "intermix serve: client left (%zu now)\n", clients_.size());
}

void ViewerSession::on_message(const std::shared_ptr<ClientSink>& client, std::string_view text) {
  try {
    if (text.size() > kMaxMessageBytes)
      throw Error(fmt::format("message: {} bytes, more than the {} a message may have", text.size(),
                              kMaxMessageBytes));
    handle(client, parse_message(text));
  } catch (const Json::exception& e) {  // a check missed: at least not nlohmann's own prefix
    reply_error(*client, "message: " + readable(e));
  } catch (const std::exception& e) {  // imx::Error, and whatever else a hostile message finds
    reply_error(*client, e.what());
  }
}

void ViewerSession::handle(const std::shared_ptr<ClientSink>& client, const Json& message) {
  if (!message.is_object())
    throw Error(fmt::format("message: expected a JSON object, got {}", message.type_name()));
  const JsonReader r(message, "message");
  const std::string type =
      r.get("type").choice({"camera", "edit", "settings", "save", "screenshot", "stats", "slice",
                            "probe", "annotations", "measure", "pick"});
  // seq and moving are checked before anything changes, so a refused message changes nothing.
  if (auto v = r.find("seq")) v->number(Range::closed(0.0, 9e15));
  if (auto v = r.find("moving")) v->boolean();

  if (type == "camera" || type == "edit") {
    std::lock_guard lock(mutex_);
    // An object edit that leaves the image (a volume's 2-D window) re-renders nothing.
    const bool image_changes = apply_edit(state_, message) || type == "camera";
    ++document_version_;
    if (image_changes)
      input_applied(client.get(), message);
    else
      input_acknowledged(client.get(), message);
  } else if (type == "annotations") {
    std::lock_guard lock(mutex_);
    if (apply_annotations(state_, message)) ++document_version_;
    input_acknowledged(client.get(), message);  // drawn by the page: the 3-D image stays
  } else if (type == "measure" || type == "pick") {
    Json answer;
    {
      std::lock_guard lock(mutex_);
      answer = type == "pick" ? answer_pick(state_, message) : answer_measure(state_, message);
    }
    client->send_text(text_of(answer));
  } else if (type == "slice") {
    // Rendered here, on the network thread: a 2-D view takes milliseconds, not a frame's time.
    SliceAnswer answer;
    {
      std::lock_guard lock(mutex_);
      answer = answer_slice(state_, message);
    }
    client->send_frame(std::move(answer.text), std::move(answer.png), false);
  } else if (type == "probe") {
    Json answer;
    {
      std::lock_guard lock(mutex_);
      answer = answer_probe(state_, message);
    }
    client->send_text(text_of(answer));
  } else if (type == "settings") {
    r.check_keys({"type", "seq", "moving", "method", "spp", "viewport"});
    std::lock_guard lock(mutex_);
    std::string method = method_;
    int spp = spp_;
    std::optional<std::pair<int, int>> viewport = viewport_;
    if (auto v = r.find("viewport")) viewport = fitted_viewport(*v, options_.max_image_side);
    if (auto v = r.find("method")) {
      method = v->string();
      const std::vector<std::string> methods = available_methods();
      if (std::find(methods.begin(), methods.end(), method) == methods.end())
        v->fail(fmt::format("'{}' is not a method of this build; it has: {}", method,
                            fmt::join(methods, ", ")));
    }
    if (auto v = r.find("spp")) {
      spp = v->integer(1, kMaxViewerSpp);
      if (!perfect_square(spp)) v->fail(fmt::format("{} is not a perfect square", spp));
    }
    method_ = method;
    spp_ = spp;
    viewport_ = viewport;
    input_applied(client.get(), message);
  } else if (type == "save") {
    r.check_keys({"type"});
    std::lock_guard lock(mutex_);
    const std::string name = save();
    client->send_text(text_of(
        Json{{"type", "saved"}, {"file", name}, {"text", text_of(saved_document(), 2) + "\n"}}));
  } else if (type == "screenshot") {
    r.check_keys({"type"});
    {
      std::lock_guard lock(mutex_);
      // Once per client until it is sent: its replies are not dropped, so they must not pile up.
      if (std::none_of(screenshot_requests_.begin(), screenshot_requests_.end(),
                       [&](const std::weak_ptr<ClientSink>& w) { return w.lock() == client; }))
        screenshot_requests_.push_back(client);
      idle_ = false;
    }
    wake_.notify_all();
  } else {  // stats
    r.check_keys({"type", "latency_ms"});
    const JsonReader list = r.get("latency_ms");
    list.expect_array();
    if (list.size() > kMaxLatenciesPerReport)
      list.fail(
          fmt::format("{} values; a report holds at most {}", list.size(), kMaxLatenciesPerReport));
    std::vector<double> values;
    for (const JsonReader& v : list.elements()) values.push_back(v.number(Range::closed(0.0, 1e7)));
    std::lock_guard lock(mutex_);
    for (double v : values)
      if (latencies_.size() < kMaxLatenciesKept) latencies_.push_back(v);
    if (options_.log && !latencies_.empty())
      std::fprintf(stderr,
                   "intermix serve: input-to-frame latency over %zu frames: median %.1f ms, "
                   "95th percentile %.1f ms\n",
                   latencies_.size(), percentile(latencies_, 0.5), percentile(latencies_, 0.95));
  }
}

std::pair<SceneDocument, uint64_t> ViewerSession::document() const {
  std::lock_guard lock(mutex_);
  return {state_.document, document_version_};
}

uint64_t ViewerSession::replace_document(SceneDocument document) {
  std::filesystem::path file;
  {
    std::lock_guard lock(mutex_);
    file = state_.file;
  }
  ViewerState next = viewer_state(std::move(document), file);  // parsed outside the lock
  std::lock_guard lock(mutex_);
  next.initial_camera = state_.initial_camera;
  state_ = std::move(next);
  ++document_version_;
  input_applied(nullptr, Json::object());
  return document_version_;
}

// After an input changed the state (caller holds the lock): remember the client's seq, restart
// the frames from this state, cancel a still frame in flight, and show every client the state.
void ViewerSession::input_applied(const ClientSink* client, const Json& message) {
  for (Client& c : clients_)
    if (c.id == client && message.contains("seq"))
      c.seq = std::max(c.seq, static_cast<long long>(message["seq"].get<double>()));
  ++version_;
  idle_ = false;
  moving_ = message.contains("moving") && message["moving"].get<bool>();
  last_input_ = Clock::now();
  cancel_ = true;  // only still frames poll it (render_and_send)
  broadcast_state();
  wake_.notify_all();
}

void ViewerSession::input_acknowledged(const ClientSink* client, const Json& message) {
  for (Client& c : clients_)
    if (c.id == client && message.contains("seq"))
      c.seq = std::max(c.seq, static_cast<long long>(message["seq"].get<double>()));
  acknowledge_ = true;
  broadcast_state();
  wake_.notify_all();
}

// The last frame again, each client's latest input in it: after inputs that changed no pixel.
void ViewerSession::resend_last_frame() {
  if (last_frame_text_.empty()) return;  // the first frame carries every seq
  Json frame = Json::parse(last_frame_text_);
  for (const Client& c : clients_)
    if (auto sink = c.sink.lock()) {
      frame["seq"] = c.seq;
      sink->send_frame(frame.dump(), last_frame_image_, true);
    }
}

// The session as a scene file: the edited document with the method and spp it converges with.
Json ViewerSession::saved_document() const {
  Json document = state_.document.json();
  document["render"]["method"] = method_;
  document["render"]["spp"] = spp_;
  return document;
}

// Writes the session beside its scene file as NAME.viewer-N.json, N the first number free, so
// that no save replaces an earlier one; returns the file's name (clients never see server paths).
std::string ViewerSession::save() {
  std::filesystem::path folder = state_.file.parent_path();
  if (folder.empty()) folder = ".";
  std::filesystem::path path;
  for (int n = 1;; ++n) {
    if (n > kMaxSaves)
      throw Error(fmt::format("save: {} saves of this scene already; move some away", kMaxSaves));
    path = folder / fmt::format("{}.viewer-{}.json", state_.file.stem().string(), n);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec) && !ec) break;
  }
  const std::string text = text_of(saved_document(), 2) + "\n";
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
  if (options_.log) std::fprintf(stderr, "intermix serve: saved %s\n", path.string().c_str());
  return path.filename().string();
}

bool ViewerSession::take_work(std::unique_lock<std::mutex>& lock, Snapshot& out) {
  const auto release_after = std::chrono::duration<double, std::milli>(options_.release_after_ms);
  for (;;) {
    if (stopping_) return false;
    if (moving_ && Clock::now() - last_input_ > release_after) moving_ = false;
    const bool shot = !screenshot_requests_.empty();
    const bool need_moving =
        moving_ && rendered_version_ != version_ && failed_version_ != version_;
    const bool need_still = !moving_ && failed_version_ != version_ &&
                            (accumulated_version_ != version_ || accumulator_.samples() < spp_);
    const bool need_full = options_.full_resolution && !moving_ && !need_still &&
                           failed_version_ != version_ && full_resolution_version_ != version_;
    if (shot || need_moving || need_still || need_full) {
      out.scene = state_.scene();  // shares voxels and meshes: the Renderer knows them by identity
      if (viewport_) std::tie(out.scene.image.width, out.scene.image.height) = *viewport_;
      out.method = method_;
      out.spp = spp_;
      out.moving = moving_;
      out.version = version_;
      for (const Client& c : clients_) out.seqs.emplace_back(c.id, c.seq);
      if (shot) out.screenshot_to = std::exchange(screenshot_requests_, {});
      out.full_resolution = !shot && need_full;
      if (out.full_resolution) out.document = saved_document();
      cancel_ = false;
      return true;
    }
    if (std::exchange(acknowledge_, false)) resend_last_frame();
    idle_ = !moving_;  // a drag not yet released still has its still frames to come
    idle_changed_.notify_all();
    if (moving_)
      wake_.wait_for(lock, release_after);
    else
      wake_.wait(lock);
  }
}

bool ViewerSession::wait_idle(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return idle_changed_.wait_for(lock, timeout, [&] { return idle_ || stopping_; });
}

void ViewerSession::render_loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    Snapshot snapshot;
    if (!take_work(lock, snapshot)) return;
    lock.unlock();
    if (!snapshot.screenshot_to.empty())
      screenshot(snapshot.screenshot_to, snapshot);
    else if (snapshot.full_resolution)
      render_full_resolution(snapshot);
    else
      render_and_send(snapshot);
    lock.lock();
  }
}

void ViewerSession::render_and_send(Snapshot& s) {
  Scene& scene = s.scene;
  const int full_w = scene.image.width, full_h = scene.image.height;
  RenderOptions o;
  o.method = s.method;
  o.threads = options_.threads;
  double scale = 1.0;
  int level = 0;  // the coarsest level of detail a moving frame drew
  if (s.moving) {
    // Moving frames are not cancelled: they are short, and one client's stream of them must not
    // starve another's.
    scale = resolution_.pick(static_cast<double>(full_w) * full_h, std::min(full_w, full_h));
    scene.image.width = std::max(1, static_cast<int>(std::lround(full_w * scale)));
    scene.image.height = std::max(1, static_cast<int>(std::lround(full_h * scale)));
    o.spp = 1;
    // A stride of each tractogram while moving (its own tube cache keeps both geometries).
    for (StreamlineObject& so : scene.streamlines) so.stride = preview_stride(so);
    // Tube silhouettes are covered once still: a moving frame's scale, the budget's pick, would
    // ask each time for tubes padded to its own pixels.
    scene.render.tube_coverage = "off";
    level = moving_levels_.apply(scene);
  } else {
    if (accumulated_version_ != s.version) {
      accumulator_.reset();
      accumulated_version_ = s.version;
    }
    o.spp = s.spp;
    o.sample_index = accumulator_.samples();
    o.cancel = &cancel_;
  }

  const auto t0 = Clock::now();
  Image image;
  try {
    image = renderer_.render(scene, o);
  } catch (const Cancelled&) {
    std::lock_guard lock(mutex_);
    ++counters_.frames_cancelled;
    return;
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    failed_version_ = s.version;
    std::string message = fmt::format("render with {}: {}", s.method, e.what());
    const bool fall_back = method_ == s.method && method_ != last_good_method_;
    if (fall_back) message += fmt::format("; back to {}", last_good_method_);
    broadcast_text(text_of(Json{{"type", "error"}, {"message", message}}));
    if (fall_back) {  // the error first, then the state that puts the method menus back
      method_ = last_good_method_;
      ++version_;
      broadcast_state();
    }
    return;
  }
  const double render_ms = ms_since(t0);
  const RendererStats stats = renderer_.last_stats();

  const auto t1 = Clock::now();
  std::string encoded;
  int samples = 1;
  if (s.moving) {
    encoded = encode_jpeg(image, options_.jpeg_quality);
  } else {
    accumulator_.add(image);
    samples = accumulator_.samples();
    encoded =
        encode_png(samples == 1 ? image : accumulator_.mean(), "frame", false, kStillPngLevel);
  }
  const double encode_ms = ms_since(t1);
  // A level's first moving frame builds its copy and its bricks' tables: no measure of the next.
  if (s.moving && level == moving_level_)
    resolution_.record(scale, static_cast<double>(full_w) * full_h, render_ms + encode_ms);
  if (s.moving) moving_level_ = level;

  Json frame = {{"type", "frame"},
                {"seq", 0},
                {"width", image.width()},
                {"height", image.height()},
                {"format", s.moving ? "jpeg" : "png"},
                {"samples", samples},
                {"spp", s.spp},
                {"final", !s.moving && samples >= s.spp},
                {"render_ms", render_ms},
                {"encode_ms", encode_ms},
                {"stages", stats.stages},
                {"stages_run", stats.stages_run},
                {"scale", scale}};
  if (options_.full_resolution) frame["full_resolution"] = false;  // coarse levels, refining
  if (level > 0) frame["level"] = level;  // a moving frame drawn from a coarser copy
  std::lock_guard lock(mutex_);
  // A still frame overtaken by input during its encoding is not worth sending.
  if (!s.moving && version_ != s.version) {
    ++counters_.frames_cancelled;
    return;
  }
  rendered_version_ = s.version;
  last_good_method_ = s.method;  // a later method that fails falls back to this one
  send_to_clients(std::move(frame), std::move(encoded), s);
  ++(s.moving ? counters_.moving_frames : counters_.still_frames);
}

void ViewerSession::render_full_resolution(const Snapshot& s) {
  const auto t0 = Clock::now();
  int step = 0;
  {
    std::lock_guard lock(mutex_);
    if (refined_version_ == s.version) step = refined_steps_;
  }
  SessionOptions::Refinement refined;
  try {
    refined = options_.full_resolution(s.document, s.scene.image.width, s.scene.image.height, step,
                                       cancel_);
  } catch (const Cancelled&) {
    std::lock_guard lock(mutex_);
    ++counters_.frames_cancelled;
    return;
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    full_resolution_version_ = s.version;  // the coarse frame stays; not tried again
    broadcast_text(text_of(
        Json{{"type", "error"}, {"message", fmt::format("full resolution: {}", e.what())}}));
    return;
  }
  const double render_ms = ms_since(t0);
  const auto t1 = Clock::now();
  std::string encoded = encode_png(refined.image, "frame", false, kStillPngLevel);
  Json frame = {{"type", "frame"},
                {"seq", 0},
                {"width", refined.image.width()},
                {"height", refined.image.height()},
                {"format", "png"},
                {"samples", s.spp},
                {"spp", s.spp},
                {"final", true},
                {"full_resolution", refined.last},
                {"refinement", step},
                {"render_ms", render_ms},
                {"encode_ms", ms_since(t1)},
                {"stages", 0},
                {"stages_run", 0},
                {"scale", 1.0}};
  if (options_.log)
    std::fprintf(stderr, "intermix serve: %s in %.1f s\n",
                 refined.last ? "full resolution" : "refined", render_ms / 1000.0);
  std::lock_guard lock(mutex_);
  if (version_ != s.version) {
    ++counters_.frames_cancelled;
    return;
  }
  refined_version_ = s.version;
  refined_steps_ = step + 1;
  if (refined.last) full_resolution_version_ = s.version;
  full_resolution_image_ = std::move(refined.image);
  send_to_clients(std::move(frame), std::move(encoded), s);
  ++counters_.full_resolution_frames;
}

void ViewerSession::send_to_clients(Json frame, std::string encoded, const Snapshot& s) {
  // Every client now, with the latest of its inputs this frame shows (0: none; a client may
  // have joined since the snapshot).
  for (const Client& c : clients_)
    if (auto sink = c.sink.lock()) {
      long long seq = 0;
      for (const auto& [id, included] : s.seqs)
        if (id == c.id) seq = included;
      frame["seq"] = seq;
      sink->send_frame(frame.dump(), encoded, true);
    }
  frame["seq"] = 0;
  last_frame_text_ = frame.dump();
  last_frame_image_ = std::move(encoded);
  ++counters_.frames_sent;
}

void ViewerSession::screenshot(const std::vector<std::weak_ptr<ClientSink>>& to,
                               const Snapshot& s) {
  std::string png, error;
  int width = s.scene.image.width, height = s.scene.image.height;
  try {
    // The converged frame when there is one; else the whole spp frame at once.
    Image image;
    if (refined_version_ == s.version && full_resolution_image_.width() > 0) {
      image = full_resolution_image_;
    } else if (accumulated_version_ == s.version && accumulator_.samples() >= s.spp) {
      image = accumulator_.mean();
    } else {
      RenderOptions o;
      o.method = s.method;
      o.spp = s.spp;
      o.threads = options_.threads;
      image = renderer_.render(s.scene, o);
    }
    png = encode_png(image, "screenshot");
  } catch (const std::exception& e) {
    error = fmt::format("screenshot: {}", e.what());
  }
  for (const auto& weak : to)
    if (auto sink = weak.lock()) {
      if (!error.empty())
        reply_error(*sink, error);
      else
        sink->send_frame(
            text_of(Json{{"type", "screenshot"}, {"width", width}, {"height", height}}), png,
            false);
    }
}

ViewerSession::Counters ViewerSession::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

std::string ViewerSession::method() const {
  std::lock_guard lock(mutex_);
  return method_;
}

int ViewerSession::spp() const {
  std::lock_guard lock(mutex_);
  return spp_;
}

std::vector<double> ViewerSession::latencies() const {
  std::lock_guard lock(mutex_);
  return latencies_;
}

}  // namespace imx::server
