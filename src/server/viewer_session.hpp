// ViewerSession: one scene shown to any number of clients. Client messages (docs/viewer.md,
// protocol) edit the shared ViewerState; a render thread turns the latest state into frames:
// reduced-resolution JPEG frames while the user moves, then full-resolution PNG frames that
// accumulate one jittered sample each until the target spp, and then, for a scene shown at a
// coarse level of a pyramid, one frame at full resolution (SessionOptions::full_resolution).
// New input cancels a frame in flight.
// The session knows nothing of the network: clients are ClientSinks (http_server.cpp's WebSocket
// connections, or a test's recorder).
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "intermix/renderer.hpp"
#include "server/accumulator.hpp"
#include "server/moving_levels.hpp"
#include "server/reading_views.hpp"
#include "server/resolution_control.hpp"
#include "server/viewer_state.hpp"

namespace imx::server {

// Where the session's messages go. send() is called from the session's threads and must not
// block: a sink queues and writes on its own thread.
class ClientSink {
 public:
  virtual ~ClientSink() = default;
  virtual void send_text(std::string text) = 0;
  // A `state` message: only the newest matters, so a slow client's unsent one may be replaced.
  virtual void send_state(std::string text) { send_text(std::move(text)); }
  // One frame: its JSON text, then its encoded image as one binary message. A slow client may
  // drop whole frames (never half of one); the next one shows the newer state.
  // `droppable` false: never dropped (a screenshot the user asked for).
  virtual void send_frame(std::string text, std::string image, bool droppable) = 0;
};

struct SessionOptions {
  std::string method;              // empty: the scene's render.method, else zslab
  int spp = 0;                     // samples a still frame converges to; 0: the scene's, else 4
  double moving_budget_ms = 45.0;  // what a frame may take while the user moves
  int jpeg_quality = 85;
  int threads = 0;  // rendering threads, 0: all cores
  // The largest side of a frame a page may ask for (`settings` `viewport`: its canvas's CSS size
  // times devicePixelRatio); larger viewports are scaled down, keeping their aspect.
  int max_image_side = 2048;
  // A "moving" input followed by silence this long counts as released (a client gone mid-drag).
  double release_after_ms = 400.0;
  bool log = true;  // one line per client and per latency report on stderr
  // For a scene whose volumes are shown at a coarse pyramid level (too large to hold at full
  // resolution): renders `document` (the session's saved document) at `width`×`height` finer
  // than shown, refinement `step` (0, 1, ...) each finer than the last until one is `last` (full
  // resolution), polling `cancel` (throws imx::Cancelled once it is set). Called once a still
  // frame has converged; each frame replaces the last. Empty: still frames are the last.
  struct Refinement {
    Image image;
    bool last = true;
  };
  std::function<Refinement(const nlohmann::json& document, int width, int height, int step,
                           const std::atomic<bool>& cancel)>
      full_resolution;
};

// The most bytes one client message may have (the WebSocket layer refuses longer ones first).
inline constexpr size_t kMaxMessageBytes = 64 * 1024;

// The frame rendering the viewer uses while still: the number of samples per pixel `spp` comes
// from options, the scene, or 4; a perfect square from 1 to 64.
int viewer_spp(const Scene& scene, int requested);

// The method the viewer starts with: the requested one, else the scene's render.method when the
// file sets one (`state.document`), else csg for a CSG or exclusive-mixing scene, else zslab
// (stage reuse for edits).
std::string viewer_method(const ViewerState& state, const std::string& requested);

class ViewerSession {
 public:
  ViewerSession(ViewerState state, SessionOptions options);
  ~ViewerSession();  // stops the render thread
  ViewerSession(const ViewerSession&) = delete;
  ViewerSession& operator=(const ViewerSession&) = delete;

  // The document shown now, and a count that grows with every change of it (a page's camera or
  // edit message, replace_document): what a program sharing the scene reads back (the Python
  // package's Scene behind a notebook view).
  std::pair<SceneDocument, uint64_t> document() const;
  // Shows `document` instead, as a page's edit does (every client gets the new state and
  // frames), keeping "reset view"'s camera. Throws imx::Error as viewer_state does, changing
  // nothing. Returns the new count.
  uint64_t replace_document(SceneDocument document);

  // Sends `hello` and the latest frame to a new client; it gets every frame and state from now.
  void add_client(const std::shared_ptr<ClientSink>& client);
  void remove_client(const ClientSink* client);
  // One text message from `client`. Errors are answered to that client as `error` messages;
  // nothing a client sends throws out of here.
  void on_message(const std::shared_ptr<ClientSink>& client, std::string_view text);

  // Stops the render thread (also done by the destructor).
  void stop();
  // Waits until every frame the latest input asked for was sent (or `timeout`); false on timeout.
  // For tests and the fuzz harness, which must not exit while a frame renders.
  bool wait_idle(std::chrono::milliseconds timeout);

  // Counters for tests and logs.
  struct Counters {
    int frames_sent = 0;
    int frames_cancelled = 0;
    int moving_frames = 0;
    int still_frames = 0;
    int full_resolution_frames = 0;
  };
  Counters counters() const;
  std::string method() const;
  int spp() const;
  // Input-to-frame latencies the clients reported (`stats` messages), in ms.
  std::vector<double> latencies() const;

 private:
  struct Client {
    std::weak_ptr<ClientSink> sink;
    const ClientSink* id = nullptr;
    long long seq = 0;  // the latest input of this client applied to the state
  };
  struct Snapshot;

  void render_loop();
  bool take_work(std::unique_lock<std::mutex>& lock, Snapshot& out);
  void render_and_send(Snapshot& snapshot);
  void render_full_resolution(const Snapshot& snapshot);
  // Sends a frame to every client, each with its latest input the frame shows, and keeps it for
  // clients that join. Holds mutex_.
  void send_to_clients(nlohmann::json frame, std::string encoded, const Snapshot& snapshot);
  void screenshot(const std::vector<std::weak_ptr<ClientSink>>& to, const Snapshot& snapshot);
  void handle(const std::shared_ptr<ClientSink>& client, const nlohmann::json& message);
  void input_applied(const ClientSink* client, const nlohmann::json& message);
  // An input that leaves the image as it is: its client's frame (the last one, sent again with
  // its seq once the render thread is idle) without a render; the state goes to every client.
  void input_acknowledged(const ClientSink* client, const nlohmann::json& message);
  void resend_last_frame();
  nlohmann::json state_message() const;
  void broadcast_text(const std::string& text);
  void broadcast_state();
  nlohmann::json saved_document() const;
  std::string save();
  static void reply_error(ClientSink& client, const std::string& message);

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  ViewerState state_;
  SessionOptions options_;
  std::string method_;
  std::string last_good_method_;
  int spp_ = 1;
  std::optional<std::pair<int, int>> viewport_;  // the latest page's canvas size, else the scene's
  nlohmann::json histograms_, tf_presets_;       // sent in every hello
  std::vector<Client> clients_;
  uint64_t version_ = 1;           // grows with every change of what the image shows
  uint64_t document_version_ = 1;  // grows with every change of state_.document
  uint64_t rendered_version_ = 0;
  uint64_t failed_version_ = 0;  // a version whose frame failed is not rendered again
  bool moving_ = false;
  std::chrono::steady_clock::time_point last_input_;
  std::vector<std::weak_ptr<ClientSink>> screenshot_requests_;
  // The latest frame, for clients that join: its JSON (seq 0) and image.
  std::string last_frame_text_, last_frame_image_;
  Counters counters_;
  std::vector<double> latencies_;
  bool stopping_ = false;
  bool idle_ = false;         // the render thread waits with nothing to do
  bool acknowledge_ = false;  // an input the image did not change awaits its frame
  std::condition_variable idle_changed_;
  std::atomic<bool> cancel_{false};

  // Render thread only.
  Renderer renderer_;
  Accumulator accumulator_;
  uint64_t accumulated_version_ = 0;
  uint64_t full_resolution_version_ = 0;  // the version whose full-resolution frame was sent
  uint64_t refined_version_ = 0;          // the version refined `refined_steps_` steps so far
  int refined_steps_ = 0;
  Image full_resolution_image_;  // the latest refined frame, for screenshots
  ResolutionControl resolution_;
  MovingLevels moving_levels_;  // the render thread's
  int moving_level_ = 0;        // the level the last moving frame drew
  std::thread thread_;
};

}  // namespace imx::server
