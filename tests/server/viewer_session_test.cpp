// ViewerSession: frames while moving are reduced JPEGs; still frames accumulate jittered samples
// to the spp frame render() gives; an edit re-renders only its own stage; several clients see
// one state; bad messages get an error and change nothing; save writes a scene file that renders
// what the session converged to.
#include "server/viewer_session.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/math.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using test::TempDir;

using Json = nlohmann::json;
using namespace std::chrono_literals;

constexpr int kSize = 48;

// What a client received, in order: text messages as JSON, and each frame's image beside it.
class Recorder : public ClientSink {
 public:
  struct Message {
    Json json;
    std::string image;
  };

  void send_text(std::string text) override { push({Json::parse(text), {}}); }
  void send_frame(std::string text, std::string image, bool) override {
    push({Json::parse(text), std::move(image)});
  }

  // Waits (at most 60 s) for a message that satisfies `pred`, returns it and forgets all before.
  Message wait_for(const std::function<bool(const Json&)>& pred) {
    std::unique_lock lock(mutex_);
    Message found;
    const bool ok = changed_.wait_for(lock, 60s, [&] {
      for (size_t i = 0; i < messages_.size(); ++i)
        if (pred(messages_[i].json)) {
          found = messages_[i];
          messages_.erase(messages_.begin(), messages_.begin() + static_cast<long>(i) + 1);
          return true;
        }
      return false;
    });
    if (!ok) ADD_FAILURE() << "no such message within 60 s";
    return found;
  }
  size_t count(const std::string& type) {
    std::lock_guard lock(mutex_);
    return static_cast<size_t>(
        std::count_if(messages_.begin(), messages_.end(),
                      [&](const Message& m) { return m.json["type"] == type; }));
  }
  Message wait_type(const std::string& type) {
    return wait_for([&](const Json& j) { return j["type"] == type; });
  }
  Message wait_final() {
    return wait_for([](const Json& j) { return j["type"] == "frame" && j["final"] == true; });
  }

 private:
  void push(Message m) {
    std::lock_guard lock(mutex_);
    messages_.push_back(std::move(m));
    changed_.notify_all();
  }
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Message> messages_;
};

// fusion.json at kSize pixels with small phantoms, copied into `dir` (save writes beside it).
std::filesystem::path small_fusion(const TempDir& dir) {
  return test::write_small_example(dir.path(), "fusion", kSize, 40);
}

Image decode(const std::string& png, const TempDir& dir) {
  const std::filesystem::path file = dir.path() / "frame.png";
  std::ofstream(file, std::ios::binary) << png;
  return read_png(file);
}

SessionOptions quiet_options(int spp) {
  SessionOptions o;
  o.spp = spp;
  o.log = false;
  return o;
}

Json camera_message(long long seq, bool moving, double eye_x) {
  return {{"type", "camera"},
          {"seq", seq},
          {"moving", moving},
          {"eye", {eye_x, -420.0, 200.0}},
          {"target", {0.0, 0.0, 20.0}}};
}

TEST(ViewerSession, StillFramesConvergeToTheSppFrame) {
  TempDir dir;
  const std::filesystem::path file = small_fusion(dir);
  ViewerSession session(load_viewer_state(file), quiet_options(4));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  const Json hello = client->wait_type("hello").json;
  EXPECT_EQ(hello["method"], "zslab");
  EXPECT_EQ(hello["spp"], 4);
  EXPECT_EQ(hello["objects"].size(), 3u);
  EXPECT_TRUE(hello["histograms"].contains("ct"));
  for (int samples = 1; samples <= 4; ++samples) {
    const auto frame = client->wait_type("frame");
    EXPECT_EQ(frame.json["samples"], samples);
    EXPECT_EQ(frame.json["format"], "png");
    EXPECT_EQ(frame.json["width"], kSize);
    EXPECT_EQ(frame.json["final"], samples == 4);
    if (samples == 4) {
      RenderOptions options;
      options.method = "zslab";
      options.spp = 4;
      const Image expected = render(load_scene(file), options);
      const std::filesystem::path want = dir.path() / "want.png";
      write_png(expected, want);
      // Both went through 8-bit sRGB; the mean of samples differs from the whole frame by float
      // rounding only.
      EXPECT_GE(psnr(read_png(want), decode(frame.image, dir)), 60.0);
    }
  }
}

TEST(ViewerSession, MovingFramesAreReducedJpegsThenStillFramesRefine) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(4));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  // A frame of 48 px stays whole while moving: it is below the floor (128 px) already.
  session.on_message(client, camera_message(1, true, -300).dump());
  EXPECT_EQ(client->wait_type("frame").json["width"], kSize);
  // A page of 300 px: nothing measured yet at that size, so half of it (150 px, above the floor).
  session.on_message(client, R"({"type": "settings", "viewport": [300, 300]})");
  session.on_message(client, camera_message(1, true, -300).dump());
  const auto moving = client->wait_for([](const Json& j) {
    return j["type"] == "frame" && j["seq"] == 1 && j["format"] == "jpeg" && j["width"] != kSize;
  });
  EXPECT_EQ(moving.json["final"], false);
  EXPECT_EQ(moving.json["scale"].get<double>(), 0.5);
  EXPECT_EQ(moving.json["width"].get<int>(), 150);
  session.on_message(client, camera_message(2, false, -300).dump());
  const auto still = client->wait_type("frame");
  EXPECT_EQ(still.json["seq"], 2);
  EXPECT_EQ(still.json["format"], "png");
  EXPECT_EQ(still.json["width"], 300);
  EXPECT_EQ(still.json["samples"], 1);
  const auto last = client->wait_final();
  EXPECT_EQ(last.json["seq"], 2);
  EXPECT_EQ(last.json["samples"], 4);
  // Idle once the last sample is sent; a new input makes it busy until its frames are out.
  EXPECT_TRUE(session.wait_idle(std::chrono::seconds(60)));
  session.on_message(client, camera_message(3, false, -250).dump());
  EXPECT_TRUE(session.wait_idle(std::chrono::seconds(60)));
  EXPECT_EQ(session.counters().still_frames, 12);  // 4 samples at load, after the release, now
}

TEST(ViewerSession, AnEditRerendersOnlyItsStage) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  const Json first = client->wait_final().json;
  ASSERT_GE(first["stages"].get<int>(), 3);
  EXPECT_EQ(first["stages_run"], first["stages"]);
  const Json edit = {{"type", "edit"},
                     {"seq", 1},
                     {"moving", false},
                     {"object", "pet"},
                     {"transfer_function", {{0, 0, 0, 0, 0}, {1000, 1, 0.2, 0, 0.5}}}};
  session.on_message(client, edit.dump());
  const auto state = client->wait_type("state");
  EXPECT_EQ(state.json["objects"][1]["transfer_function"].size(), 2u);
  const auto frame = client->wait_final();
  EXPECT_EQ(frame.json["seq"], 1);
  EXPECT_EQ(frame.json["stages"], first["stages"]);
  EXPECT_EQ(frame.json["stages_run"], 1);
}

TEST(ViewerSession, EveryClientSeesEveryEdit) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto a = std::make_shared<Recorder>(), b = std::make_shared<Recorder>();
  session.add_client(a);
  a->wait_final();
  session.add_client(b);
  b->wait_type("hello");
  b->wait_type("frame");  // the latest frame, at once
  session.on_message(a, camera_message(7, false, 300).dump());
  const Json state = b->wait_type("state").json;
  EXPECT_EQ(state["camera"]["eye"][0], 300.0);
  const auto frame_b = b->wait_final();
  EXPECT_EQ(frame_b.json["seq"], 0);  // b sent nothing
  EXPECT_EQ(a->wait_final().json["seq"], 7);
  session.remove_client(b.get());
  session.on_message(a, camera_message(8, false, 250).dump());
  EXPECT_EQ(a->wait_final().json["seq"], 8);
}

// An annotations message with a polygon of `n` corners on a circle.
std::string polygon_of(int n) {
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < n; ++i) points.push_back({std::cos(i * 0.02), std::sin(i * 0.02), 0.0});
  return nlohmann::json{{"type", "annotations"},
                        {"annotations", {{{"kind", "polygon"}, {"points", points}}}}}
      .dump();
}

TEST(ViewerSession, BadMessagesGetOneErrorAndChangeNothing) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  const std::pair<std::string, std::string> cases[] = {
      {"{", "message: not JSON: "},
      {"[1, 2]", "expected a JSON object"},
      {R"({"type": "launch"})", "launch"},
      {R"({"type": "edit", "object": "/etc/passwd", "visible": false})", "is not an object"},
      {R"({"type": "edit", "object": "pet", "window": [1, 0]})", "window width 0 must be > 0"},
      {R"({"type": "camera", "seq": -1, "eye": [1, 2, 3]})", "seq"},
      {R"({"type": "camera", "moving": "yes"})", "moving"},
      {R"({"type": "settings", "method": "fastest"})", "fastest"},
      {R"({"type": "settings", "spp": 3})", "perfect square"},
      {R"({"type": "settings", "viewport": [1e6, 10]})", "viewport"},
      {R"({"type": "stats", "latency_ms": "fast"})", "latency_ms"},
      {std::string(kMaxMessageBytes + 1, ' '), "bytes"},
      // Numbers beyond a double: nlohmann refuses them while parsing, and the error names where.
      {R"({"type": "edit", "object": "pet", "opacity": 1e400})",
       "message: opacity: 1e400 is beyond the range of a number"},
      {R"({"type": "camera", "eye": [1, -1e999, 3]})", "message: eye[1]: -1e999 is beyond"},
      {R"({"type": "edit", "object": "pet", "transfer_function": [[0, 0, 0, 0, 0], [1, 2e400]]})",
       "message: transfer_function[1][1]: 2e400 is beyond"},
      {"1e400", "message: 1e400 is beyond"},
      // Measurements (issue 47): bad geometry, too many points, an unknown kind.
      {R"({"type": "annotations", "annotations": [{"kind": "ruler", "points": [[0, 0, 0],
        [NaN, 0, 0]]}]})",
       "message: not JSON: "},
      {R"({"type": "annotations", "annotations": [{"kind": "circle", "points": []}]})",
       "annotations: annotations[0].kind: "},
      {R"({"type": "annotations", "annotations": [{"kind": "ruler", "points": [[0, 0, 0],
        [1, 1e999, 0]]}]})",
       "message: annotations[0].points[1][1]: 1e999 is beyond"},
      {polygon_of(300), "annotations[0].points: a polygon has 3 to 256 points, not 300"},
      {R"({"type": "annotations", "annotations": [{"kind": "angle", "points": [[0, 0, 0],
        [0, 0, 0], [1, 0, 0]]}]})",
       "an angle's arms"},
      {R"({"type": "measure", "annotations": [{"kind": "ruler", "points": [[0, 0, 0]]}]})",
       "measure: annotations[0].points: a ruler has 2 points, not 1"},
      {R"({"type": "pick", "x": -1, "y": 0, "width": 8, "height": 8})", "pick: x: "},
  };
  for (const auto& [text, part] : cases) {
    session.on_message(client, text);
    const std::string error = client->wait_type("error").json["message"];
    EXPECT_NE(error.find(part), std::string::npos) << text.substr(0, 80) << " -> " << error;
    EXPECT_EQ(error.find("json.exception"), std::string::npos) << error;  // intermix's own words
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  EXPECT_EQ(session.method(), "zslab");
  EXPECT_EQ(session.spp(), 1);
  EXPECT_EQ(session.counters().frames_sent, 1);  // nothing was rendered again
  auto late = std::make_shared<Recorder>();      // what a new window gets: no annotation kept
  session.add_client(late);
  EXPECT_EQ(late->wait_type("hello").json["annotations"], nlohmann::json::array());
}

// A volume's 2-D window changes no pixel of the 3-D view: the edit reaches every client's state
// and its sender gets the last frame again with its seq (its flow control), and nothing renders.
TEST(ViewerSession, AVolumeWindowEditIsAnsweredWithoutARender) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  const auto sent = session.counters().frames_sent;
  session.on_message(
      client,
      R"({"type": "edit", "seq": 7, "moving": false, "object": "ct", "window": [400, 1800]})");
  const Json state = client->wait_type("state").json;
  EXPECT_EQ(state["objects"][0]["window"], Json::array({400.0, 1800.0}));
  const Json frame =
      client->wait_for([](const Json& j) { return j["type"] == "frame" && j["seq"] == 7; }).json;
  EXPECT_EQ(frame["final"], true);
  EXPECT_TRUE(session.wait_idle(std::chrono::seconds(60)));
  EXPECT_EQ(session.counters().frames_sent, sent);
}

TEST(ViewerSession, SettingsChangeMethodAndSpp) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  session.on_message(client, R"({"type": "settings", "seq": 3, "method": "mdvr", "spp": 4})");
  const Json state = client->wait_type("state").json;
  EXPECT_EQ(state["method"], "mdvr");
  EXPECT_EQ(state["spp"], 4);
  const auto frame = client->wait_final();
  EXPECT_EQ(frame.json["samples"], 4);
  EXPECT_EQ(frame.json["seq"], 3);
}

TEST(ViewerSession, StillFramesTakeThePagesViewportWithinTheLargestSide) {
  TempDir dir;
  SessionOptions options = quiet_options(1);
  options.max_image_side = 60;
  ViewerSession session(load_viewer_state(small_fusion(dir)), options);
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  EXPECT_EQ(client->wait_final().json["width"], kSize);  // the scene's size until a page says
  session.on_message(client, R"({"type": "settings", "seq": 1, "viewport": [40, 30]})");
  Json frame =
      client->wait_for([](const Json& j) { return j["type"] == "frame" && j["seq"] == 1; }).json;
  EXPECT_EQ(frame["width"], 40);
  EXPECT_EQ(frame["height"], 30);
  // A larger canvas is scaled down to the largest side, keeping its aspect.
  session.on_message(client, R"({"type": "settings", "seq": 2, "viewport": [120, 90]})");
  frame =
      client->wait_for([](const Json& j) { return j["type"] == "frame" && j["seq"] == 2; }).json;
  EXPECT_EQ(frame["width"], 60);
  EXPECT_EQ(frame["height"], 45);
  // Saving keeps the scene's own image size: the viewport is the page's, not the scene's.
  session.on_message(client, R"({"type": "save"})");
  const Json saved = Json::parse(client->wait_type("saved").json["text"].get<std::string>());
  EXPECT_EQ(saved["image"]["width"], kSize);
}

TEST(ViewerSession, SaveWritesASceneThatRendersTheConvergedFrame) {
  TempDir dir;
  const std::filesystem::path file = small_fusion(dir);
  ViewerSession session(load_viewer_state(file), quiet_options(4));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  session.on_message(client, camera_message(1, false, 100).dump());
  const Json hide = {{"type", "edit"}, {"seq", 2}, {"object", "target"}, {"visible", false}};
  session.on_message(client, hide.dump());
  const auto converged = client->wait_for(
      [](const Json& j) { return j["type"] == "frame" && j["seq"] == 2 && j["final"] == true; });
  session.on_message(client, R"({"type": "save"})");
  const Json saved = client->wait_type("saved").json;
  // Saved beside the scene under a numbered name; the reply names the file, not where it is.
  EXPECT_EQ(saved["file"], "fusion.viewer-1.json");
  EXPECT_FALSE(saved.contains("path"));
  const std::filesystem::path path = dir.path() / "fusion.viewer-1.json";
  const Scene reloaded = load_scene(path);
  EXPECT_EQ(reloaded.render.method, "zslab");
  EXPECT_EQ(reloaded.render.spp, 4);
  const std::filesystem::path want = dir.path() / "want.png";
  write_png(render(reloaded), want);
  EXPECT_GE(psnr(read_png(want), decode(converged.image, dir)), 60.0);
  // The screenshot is that converged frame, at full quality.
  session.on_message(client, R"({"type": "screenshot"})");
  const auto shot = client->wait_type("screenshot");
  EXPECT_GE(psnr(read_png(want), decode(shot.image, dir)), 60.0);
}

// Screenshots are replies a client cannot lose, so a client asking again and again before one
// is taken is answered once, not once per request (its queue of replies is bounded).
TEST(ViewerSession, RepeatedScreenshotRequestsAreAnsweredOnce) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  constexpr int kRequests = 50;
  for (int i = 0; i < kRequests; ++i) session.on_message(client, R"({"type": "screenshot"})");
  client->wait_type("screenshot");
  ASSERT_TRUE(session.wait_idle(std::chrono::seconds(60)));
  // The render thread takes the requests made while it encoded the first as one.
  EXPECT_LT(client->count("screenshot") + 1, static_cast<size_t>(kRequests / 2));
}

// A method that refuses the scene (zslab on a CSG scene) is reported, and the session goes back
// to the last method that rendered, so the user keeps a picture.
TEST(ViewerSession, AMethodThatRefusesTheSceneFallsBack) {
  ViewerSession session(load_viewer_state(test::example_scene("csg-cutaway"),
                                          test::small_example_overrides(24, {"skin", "bone"}, 32)),
                        quiet_options(1));
  EXPECT_EQ(session.method(), "csg");  // the default for a CSG scene
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_final();
  session.on_message(client, R"({"type": "settings", "seq": 1, "method": "zslab"})");
  const Json error = client->wait_type("error").json;
  EXPECT_NE(error["message"].get<std::string>().find("back to csg"), std::string::npos)
      << error["message"];
  const Json state = client->wait_type("state").json;
  EXPECT_EQ(state["method"], "csg");
  EXPECT_EQ(client->wait_final().json["format"], "png");
  EXPECT_EQ(session.method(), "csg");
}

}  // namespace
}  // namespace imx::server

namespace imx::server {
namespace {

// The reading views' messages: a slice is an image of the asked size through the asked point,
// with the volumes' values where the slice view says; a probe reads each volume's voxel there.
TEST(ViewerSession, SlicesAndProbesAnswerTheReadingViews) {
  TempDir dir;
  ViewerSession session(load_viewer_state(small_fusion(dir)), quiet_options(1));
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  client->wait_type("hello");
  const Scene scene = load_scene(small_fusion(dir));
  const VolumeObject& ct = scene.volumes[0];
  const glm::ivec3 voxel = ct.data->dims / 2;
  const glm::dvec3 point = transform_point(ct.index_to_world, glm::dvec3(voxel));
  session.on_message(client,
                     Json{{"type", "probe"}, {"point", {point.x, point.y, point.z}}}.dump());
  const Json probe = client->wait_type("probe").json;
  ASSERT_EQ(probe["values"].size(), scene.volumes.size());
  EXPECT_EQ(probe["values"][0]["name"], ct.name);
  EXPECT_EQ(probe["values"][0]["index"], Json::array({voxel.x, voxel.y, voxel.z}));
  EXPECT_EQ(probe["values"][0]["value"].get<double>(),
            ct.data->value_at(voxel.x, voxel.y, voxel.z));

  // A coronal slice through the point, 40 x 30 pixels of 2 mm; `window` for its base volume.
  const auto slice_of = [&](int seq, const Json& window) {
    Json m = {{"type", "slice"},    {"seq", seq},
              {"view", "coronal"},  {"point", {point.x, point.y, point.z}},
              {"width", 40},        {"height", 30},
              {"mm_per_pixel", 2.0}};
    if (!window.is_null()) m["window"] = window;
    session.on_message(client, m.dump());
    return client->wait_for([&](const Json& j) { return j["type"] == "slice" && j["seq"] == seq; });
  };
  const auto brightness = [](const Image& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) sum += image.at(x, y).r;
    return sum;
  };
  const auto slice = slice_of(4, nullptr);
  EXPECT_EQ(slice.json["view"], "coronal");
  const Image image = decode(slice.image, dir);
  EXPECT_EQ(image.width(), 40);
  EXPECT_EQ(image.height(), 30);
  const double lit = brightness(image);
  EXPECT_GT(lit, 0.0) << "the slice through the CT's centre is black";
  // A W/L preset's window for the base volume: everything below a level of 1e5 is black.
  EXPECT_LT(brightness(decode(slice_of(5, Json::array({1e5, 10})).image, dir)), 0.1 * lit);
  // A bad slice gets one error naming the field.
  session.on_message(client, R"({"type": "slice", "view": "oblique", "point": [0, 0, 0],
                                  "width": 8, "height": 8, "mm_per_pixel": 1})");
  EXPECT_NE(client->wait_type("error").json["message"].get<std::string>().find("slice: view"),
            std::string::npos);
  // A zoom of 1e9 either way, and a window of no width: one error each naming the field, and
  // the next slice is answered as before (nothing lost).
  const struct {
    const char* fields;
    const char* says;
  } bad[] = {{R"("mm_per_pixel": 2e9)", "slice: mm_per_pixel: 2000000000.0 is not in"},
             {R"("mm_per_pixel": 2e-9)", "slice: mm_per_pixel"},
             {R"("mm_per_pixel": 2, "window": [40, 0])", "slice: window[1]: window width 0"},
             {R"("mm_per_pixel": 2, "window": [40, "80"])", "slice: window[1]: expected a number"}};
  for (const auto& b : bad) {
    session.on_message(client, std::string(R"({"type": "slice", "view": "axial", "point": [0, 0, 0],
                                              "width": 8, "height": 8, )") +
                                   b.fields + "}");
    const std::string said = client->wait_type("error").json["message"].get<std::string>();
    EXPECT_NE(said.find(b.says), std::string::npos) << said;
    EXPECT_EQ(said.find('\n'), std::string::npos) << said;
  }
  EXPECT_EQ(decode(slice_of(6, nullptr).image, dir).width(), 40);
}

// A scene shown at coarse pyramid levels: once its still frame has converged, the session asks
// for refinements (SessionOptions::full_resolution) with the saved document, step 0 then 1,
// sends each as a final frame until one is the last, and asks again only after an input; an
// input while one renders cancels it.
TEST(ViewerSession, AConvergedCoarseFrameIsFollowedByRefinementsToFullResolution) {
  TempDir dir;
  SessionOptions options = quiet_options(4);
  std::mutex seen_mutex;
  Json seen;
  std::atomic<int> calls{0};
  std::atomic<bool> hold_next{false}, holding{false};
  options.full_resolution = [&](const Json& document, int width, int height, int step,
                                const std::atomic<bool>& cancel) {
    ++calls;
    {
      std::lock_guard lock(seen_mutex);
      seen = document;
    }
    if (hold_next.exchange(false)) {  // a long render, until the input cancels it
      holding = true;
      for (int i = 0; i < 6000 && !cancel; ++i) std::this_thread::sleep_for(10ms);
      holding = false;
      if (cancel) throw Cancelled();
    }
    // Step 0 green, step 1 (the last) red.
    Image image(width, height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) image.at(x, y) = glm::vec4(step, 1 - step, 0, 1);
    return SessionOptions::Refinement{image, step == 1};
  };
  ViewerSession session(load_viewer_state(small_fusion(dir)), options);
  auto client = std::make_shared<Recorder>();
  session.add_client(client);
  const auto coarse = client->wait_final();
  EXPECT_EQ(coarse.json["samples"], 4);
  EXPECT_EQ(coarse.json["full_resolution"], false);
  const auto finer = client->wait_for([](const Json& j) { return j.value("refinement", -1) == 0; });
  EXPECT_EQ(finer.json["full_resolution"], false);
  EXPECT_NEAR(decode(finer.image, dir).at(kSize / 2, kSize / 2).g, 1.0f, 1e-3);
  const auto full =
      client->wait_for([](const Json& j) { return j.value("full_resolution", false); });
  EXPECT_EQ(full.json["final"], true);
  EXPECT_EQ(full.json["width"], kSize);
  const Image shown = decode(full.image, dir);
  EXPECT_NEAR(shown.at(kSize / 2, kSize / 2).r, 1.0f, 1e-3);
  EXPECT_NEAR(shown.at(kSize / 2, kSize / 2).g, 0.0f, 1e-3);
  {
    std::lock_guard lock(seen_mutex);
    EXPECT_EQ(seen["render"]["spp"], 4);
    EXPECT_EQ(seen["objects"].size(), 3u);
  }
  EXPECT_EQ(full.json["refinement"], 1);
  ASSERT_TRUE(session.wait_idle(60s));
  EXPECT_EQ(calls, 2);  // idle: not asked again
  EXPECT_EQ(session.counters().full_resolution_frames, 2);

  hold_next = true;
  session.on_message(client, camera_message(1, false, -300).dump());
  for (int i = 0; i < 6000 && !holding; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(holding);
  session.on_message(client, camera_message(2, false, -250).dump());
  const auto second = client->wait_for(
      [](const Json& j) { return j.value("full_resolution", false) && j.value("seq", 0) == 2; });
  EXPECT_EQ(second.json["final"], true);
  ASSERT_TRUE(session.wait_idle(60s));
  EXPECT_EQ(calls, 5);  // two steps of each version, and the cancelled one
  EXPECT_EQ(session.counters().full_resolution_frames, 4);
  EXPECT_GE(session.counters().frames_cancelled, 1);
  std::lock_guard lock(seen_mutex);
  EXPECT_DOUBLE_EQ(seen["camera"]["eye"][0].get<double>(), -250.0);
}

}  // namespace
}  // namespace imx::server
