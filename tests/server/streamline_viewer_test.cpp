// The viewer and streamline objects: every edit of a tractogram's look and selection changes the
// image and saves a scene that renders the session's bytes; bad edits change nothing; moving
// frames draw a stride of a large tractogram from a second cached geometry; the reading views draw
// the streamlines within the slab around their plane.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frame/slice_view.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "mrtrix_tracks.hpp"
#include "same_image.hpp"
#include "server/reading_views.hpp"
#include "server/streamline_slab.hpp"
#include "server/viewer_session.hpp"
#include "server/viewer_state.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"
#include "tubes/tube_cache.hpp"

namespace imx::server {
namespace {

using test::TempDir;
using Json = nlohmann::json;
using namespace std::chrono_literals;

constexpr int kSize = 40;

// `count` straight streamlines along y (RAS: .tck files are RAS mm) from y = -30 to 30 in three
// points, spread over x in [-30, 30] at z = 0, with per-point values 0, 0.5, 1 ("fa") in a .tsf.
// The first half is 60 mm long, the second half 30 mm (y from -15 to 15).
std::filesystem::path write_tract(const TempDir& dir, int count) {
  std::vector<std::vector<float>> points, values;
  for (int i = 0; i < count; ++i) {
    const float x = count > 1 ? -30.0f + 60.0f * static_cast<float>(i) / (count - 1) : 0.0f;
    const float half = i < count / 2 ? 30.0f : 15.0f;
    points.push_back({x, -half, 0.0f, x, 0.0f, 0.0f, x, half, 0.0f});
    values.push_back({0.0f, 0.5f, 1.0f});
  }
  test::write_mrtrix_tracks(dir.path() / "tract.tck", "mrtrix tracks", points, 3);
  test::write_mrtrix_tracks(dir.path() / "tract.tsf", "mrtrix track scalars", values, 1);
  return dir.path() / "tract.tck";
}

// A scene of the tractogram alone, seen from above (LPS +z is superior) over a black background.
std::filesystem::path write_scene(const TempDir& dir, int count, Json extra = Json::object()) {
  write_tract(dir, count);
  Json object = {{"name", "tract"},
                 {"type", "streamlines"},
                 {"source", {{"file", "tract.tck"}, {"values", {"tract.tsf"}}}},
                 {"radius", 1.0}};
  for (const auto& [key, value] : extra.items()) object[key] = value;
  const Json scene = {
      {"camera", {{"eye", {0, 0, 150}}, {"target", {0, 0, 0}}, {"up", {0, -1, 0}}}},
      {"image", {{"width", kSize}, {"height", kSize}, {"background", {0, 0, 0, 1}}}},
      {"render", {{"method", "zslab"}, {"spp", 1}}},
      {"objects", {object}}};
  return dir.write("tract.json", scene.dump(2));
}

Image draw(const Scene& scene) {
  RenderOptions options;
  options.method = "zslab";
  options.spp = 1;
  return render(scene, options);
}

using test::same_bytes;

Json edit(Json fields) {
  fields["type"] = "edit";
  fields["seq"] = 1;
  fields["moving"] = false;
  fields["object"] = "tract";
  return fields;
}

// Applies `message`: the image changes and the saved file renders the session's bytes exactly.
void expect_edit_round_trips(ViewerState& state, const Json& message) {
  SCOPED_TRACE(message.dump());
  const Image before = draw(state.scene());
  EXPECT_TRUE(apply_edit(state, message));
  const Image after = draw(state.scene());
  EXPECT_FALSE(same_bytes(before, after)) << "the edit changed nothing";
  TempDir dir;
  std::filesystem::copy(state.file.parent_path() / "tract.tck", dir.path() / "tract.tck");
  std::filesystem::copy(state.file.parent_path() / "tract.tsf", dir.path() / "tract.tsf");
  const std::filesystem::path saved = dir.write("saved.json", state.document.text());
  EXPECT_TRUE(same_bytes(after, draw(load_scene(saved)))) << state.document.text();
}

// Pixels of `image` whose colour is mostly `channel` (0 red, 1 green, 2 blue), and all drawn.
struct Count {
  int mostly = 0, drawn = 0;
};
Count count_pixels(const Image& image, int channel) {
  Count c;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const glm::vec4 p = image.at(x, y);
      const float sum = p.r + p.g + p.b;
      if (sum < 0.05f) continue;
      ++c.drawn;
      if (p[channel] > 0.8f * sum) ++c.mostly;
    }
  return c;
}

TEST(StreamlineViewer, DescribesTheTractogramsLookAndChoices) {
  TempDir dir;
  const ViewerState state = load_viewer_state(write_scene(dir, 20));
  const Json described = describe_state(state);
  ASSERT_EQ(described["objects"].size(), 1u);
  const Json& o = described["objects"][0];
  EXPECT_EQ(o["kind"], "streamlines");
  EXPECT_EQ(o["name"], "tract");
  EXPECT_EQ(o["color_by"], "direction");
  EXPECT_EQ(o["count"], 20);
  EXPECT_EQ(o["stride"], 1);
  EXPECT_EQ(o["radius"], 1.0);
  EXPECT_EQ(o["point_values"], Json::array({"tract"}));
  EXPECT_EQ(o["streamline_values"], Json::array());
  EXPECT_EQ(o["opacity"], 1.0);
  EXPECT_TRUE(o["regions"].empty());
  EXPECT_NE(std::find(o["colormaps"].begin(), o["colormaps"].end(), "viridis"),
            o["colormaps"].end());
}

TEST(StreamlineViewer, EveryEditRoundTrips) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, 40));
  // Along y: direction colours them green.
  EXPECT_GT(count_pixels(draw(state.scene()), 1).mostly, 50);
  expect_edit_round_trips(state, edit({{"color_by", "fixed"}, {"color", {1, 0, 0}}}));
  const Count red = count_pixels(draw(state.scene()), 0);
  EXPECT_GT(red.mostly, 50);
  EXPECT_GE(red.mostly, red.drawn * 3 / 4);  // the rest: edges and highlights
  EXPECT_EQ(count_pixels(draw(state.scene()), 1).mostly, 0);
  expect_edit_round_trips(state, edit({{"opacity", 0.3}}));
  EXPECT_EQ(describe_state(state)["objects"][0]["opacity"], 0.3);
  expect_edit_round_trips(state, edit({{"radius", 0.3}}));
  expect_edit_round_trips(state, edit({{"stride", 3}}));
  expect_edit_round_trips(state, edit({{"min_length", 45}}));
  expect_edit_round_trips(state, edit({{"color_by", "streamline_direction"}}));
  // By values without naming them: the first per-point values.
  expect_edit_round_trips(state, edit({{"color_by", "point_value"}}));
  EXPECT_EQ(state.scene().streamlines[0].value, "tract");
  expect_edit_round_trips(state, edit({{"colormap", "hot"}}));
  expect_edit_round_trips(state, edit({{"range", {0.4, 0.6}}}));
  expect_edit_round_trips(state, edit({{"range", nullptr}}));
  EXPECT_FALSE(state.scene().streamlines[0].range);
  // Undo's form of "no values": an empty name, taken only by colourings without values.
  expect_edit_round_trips(state, edit({{"color_by", "direction"}, {"value", ""}}));
  EXPECT_FALSE(state.document.json()["objects"][0].contains("value"));
  expect_edit_round_trips(state, edit({{"visible", false}}));
  EXPECT_EQ(count_pixels(draw(state.scene()), 0).drawn, 0);
}

TEST(StreamlineViewer, SphereRegionKeepsOrAvoidsAndReplacesOnlySpheres) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, 61));  // one streamline per mm of x
  // Through a 3 mm sphere at x = 10 (LPS; the file's x = -10): the streamlines at x 7..13.
  const Json sphere = {{"sphere", {{"center", {10, 0, 0}}, {"radius", 3}}}};
  expect_edit_round_trips(state, edit({{"regions", {sphere}}}));
  const StreamlineObject& kept = state.scene().streamlines[0];
  ASSERT_EQ(kept.regions.size(), 1u);
  EXPECT_EQ(kept.regions[0].center, glm::dvec3(10, 0, 0));
  EXPECT_FALSE(kept.regions[0].avoid);
  const Image through = draw(state.scene());
  Json avoid = sphere;
  avoid["avoid"] = true;
  expect_edit_round_trips(state, edit({{"regions", {avoid}}}));
  EXPECT_EQ(state.scene().streamlines[0].regions.size(), 1u);
  EXPECT_TRUE(state.scene().streamlines[0].regions[0].avoid);
  const Image avoiding = draw(state.scene());
  // What passes through is drawn where what avoids is not, and the reverse holds too.
  EXPECT_LT(count_pixels(through, 1).drawn, count_pixels(avoiding, 1).drawn);
  expect_edit_round_trips(state, edit({{"regions", Json::array()}}));
  EXPECT_TRUE(state.scene().streamlines[0].regions.empty());
  EXPECT_FALSE(state.document.json()["objects"][0].contains("regions"));
}

TEST(StreamlineViewer, RegionsInARasDocumentAreWrittenInRas) {
  TempDir dir;
  const std::filesystem::path file = write_scene(dir, 20);
  Json scene = Json::parse(std::ifstream(file));
  scene["space"] = "RAS";
  scene["camera"]["eye"] = {0, 0, 150};
  std::ofstream(file) << scene.dump(2);
  ViewerState state = load_viewer_state(file);
  apply_edit(state, edit({{"regions", {{{"sphere", {{"center", {10, 20, 5}}, {"radius", 4}}}}}}}));
  EXPECT_EQ(state.scene().streamlines[0].regions.at(0).center, glm::dvec3(10, 20, 5));
  EXPECT_EQ(state.document.json()["objects"][0]["regions"][0]["sphere"]["center"],
            Json::array({-10.0, -20.0, 5.0}));
}

TEST(StreamlineViewer, BadEditsGiveOneErrorAndChangeNothing) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, 20));
  const std::string before = state.document.text();
  const std::pair<Json, const char*> cases[] = {
      {edit({{"color_by", "fixd"}}), "fixed"},
      {edit({{"color_by", "streamline_value"}}), "no per-streamline values"},
      {edit({{"color_by", "point_value"}, {"value", "md"}}), "md"},
      {edit({{"colormap", "virdis"}}), "viridis"},
      {edit({{"range", {2, 1}}}), "low < high"},
      {edit({{"stride", 0}}), "stride"},
      {edit({{"radius", -1}}), "radius"},
      {edit({{"color", {2, 0, 0}}}), "color"},
      {edit({{"regions", {{{"sphere", {{"center", {0, 0, 0}}}}}}}}), "radius"},
      {edit({{"regions", {{{"label_map", {{"file", "x.nii"}}}}}}}), "label_map"},
      {edit({{"window", {1, 2}}}), "planes only"},
  };
  for (const auto& [message, expected] : cases) {
    SCOPED_TRACE(message.dump());
    try {
      apply_edit(state, message);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_EQ(state.document.text(), before);
  }
}

TEST(StreamlineViewer, PreviewStrideDrawsAtMostTheBoundAndKeepsTheObjectsOwn) {
  StreamlineObject o;
  auto s = std::make_shared<Streamlines>();
  s->offsets.assign(25001, 0);
  o.streamlines = s;
  EXPECT_EQ(preview_stride(o), 3);  // 25000 / 3 = 8334 <= 10^4
  o.stride = 7;
  EXPECT_EQ(preview_stride(o), 7);
  s->offsets.assign(101, 0);
  o.stride = 1;
  EXPECT_EQ(preview_stride(o), 1);
}

// A session's moving frames draw a stride of a large tractogram, and still frames all of it, each
// geometry built once however often the camera stops and starts.
TEST(StreamlineViewer, MovingFramesUseASecondCachedGeometry) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, 12000));
  const std::shared_ptr<TubeCache> cache = state.scene().streamlines.at(0).cache;
  ASSERT_TRUE(cache);
  SessionOptions options;
  options.spp = 1;
  options.log = false;
  ViewerSession session(std::move(state), options);
  ASSERT_TRUE(session.wait_idle(60s));
  EXPECT_EQ(cache->builds(), 1u);
  class Sink : public ClientSink {
   public:
    void send_text(std::string) override {}
    void send_frame(std::string, std::string, bool) override {}
  };
  auto client = std::make_shared<Sink>();
  session.add_client(client);
  long long seq = 1;
  for (int round = 0; round < 2; ++round) {
    const int moving_before = session.counters().moving_frames;
    const Json move = {{"type", "camera"},
                       {"seq", seq++},
                       {"moving", true},
                       {"eye", {1, 5 * round, 150}},
                       {"target", {0, 0, 0}}};
    session.on_message(client, move.dump());
    // The release once a moving frame was sent (a release at once would leave none to render).
    for (int wait = 0; wait < 3000 && session.counters().moving_frames == moving_before; ++wait)
      std::this_thread::sleep_for(10ms);
    EXPECT_GT(session.counters().moving_frames, moving_before);
    const Json release = {{"type", "camera"},
                          {"seq", seq++},
                          {"moving", false},
                          {"eye", {3, 1, 150}},
                          {"target", {0, 0, 0}}};
    session.on_message(client, release.dump());
    ASSERT_TRUE(session.wait_idle(60s));
  }
  EXPECT_GE(session.counters().moving_frames, 1);
  EXPECT_EQ(cache->builds(), 2u) << "the full and the moving geometry, once each";
}

// An axial view at z through lines along y at z = 0: their pixels in their colour within the slab,
// nothing beyond it.
TEST(StreamlineViewer, SliceShowsTheStreamlinesWithinTheSlab) {
  TempDir dir;
  const ViewerState state =
      load_viewer_state(write_scene(dir, 5, {{"color", {0, 0, 1}}, {"opacity", 1.0}}));
  const StreamlineObject& o = state.scene().streamlines.at(0);
  const Streamlines& s = *o.streamlines;
  for (const double z : {0.0, 0.9, 1.5, 3.0}) {
    SCOPED_TRACE(z);
    const SliceView view = slice_view(SliceAxis::axial, {0, 0, z}, 80, 80, 1.0);
    Image image(80, 80, glm::vec4(0, 0, 0, 1));
    const size_t drawn = draw_streamline_slab(image, view, o, 2.0, 1);
    const bool within = z <= 1.0;
    EXPECT_EQ(drawn > 0, within) << drawn;
    // The middle point of every streamline: blue when within the slab, black beyond.
    for (size_t i = 0; i < s.count(); ++i) {
      const glm::dvec2 q = view.pixel(glm::dvec3(s.points[s.offsets[i] + 1]));
      const glm::vec4 p = image.at(static_cast<int>(q.x), static_cast<int>(q.y));
      if (within)
        EXPECT_GT(p.b, 0.95f) << i;
      else
        EXPECT_LT(p.b, 0.05f) << i;
      EXPECT_LT(p.r + p.g, 0.05f);
    }
  }
  // A coronal view through y = 0 crosses each line once: a dot per streamline, not a line.
  const SliceView coronal = slice_view(SliceAxis::coronal, {0, 0, 0}, 80, 80, 1.0);
  Image image(80, 80, glm::vec4(0, 0, 0, 1));
  draw_streamline_slab(image, coronal, o, 2.0, 1);
  const Count blue = count_pixels(image, 2);
  EXPECT_GE(blue.drawn, 5);
  EXPECT_LE(blue.drawn, 5 * 3 * 2);  // 2 mm of each line, at most a pixel either side
}

TEST(StreamlineViewer, SliceAnswerDrawsShownStreamlinesOnly) {
  TempDir dir;
  ViewerState state = load_viewer_state(write_scene(dir, 5, {{"color", {1, 0, 0}}}));
  const Json message = {{"type", "slice"}, {"view", "axial"}, {"point", {0, 0, 0}},
                        {"width", 64},     {"height", 64},    {"mm_per_pixel", 1.0}};
  const SliceAnswer shown = answer_slice(state, message);
  EXPECT_EQ(Json::parse(shown.text)["slab"], kDefaultStreamlineSlab);
  Json thin = message;
  thin["point"] = {0, 0, 5};
  thin["slab"] = 4.0;
  const SliceAnswer beyond = answer_slice(state, thin);
  apply_edit(state, edit({{"visible", false}}));
  const SliceAnswer hidden = answer_slice(state, message);
  EXPECT_NE(shown.png, hidden.png);
  EXPECT_EQ(beyond.png, hidden.png);
  Json bad = message;
  bad["slab"] = -1;
  EXPECT_THROW(answer_slice(state, bad), Error);
}

// A connectome is drawn as tubes but is no tractogram: the page gets its opacity and visibility
// only, and a tractogram's field is refused by name instead of written into its document.
TEST(StreamlineViewer, AConnectomeTakesOpacityButNoTractFields) {
  SKIP_WITHOUT_SHARED_DATA("neuro/connectomes/connectome.jcon");
  TempDir dir;
  const nlohmann::json scene = {
      {"image", {{"width", kSize}, {"height", kSize}, {"background", {0, 0, 0, 1}}}},
      {"objects",
       {{{"name", "net"},
         {"type", "connectome"},
         {"source",
          {{"file", test::shared_data("neuro/connectomes/connectome.jcon").string()}}}}}}};
  ViewerState state = load_viewer_state(dir.write("net.json", scene.dump(2)));
  const Json described = describe_state(state);
  bool found = false;
  for (const Json& o : described["objects"])
    if (o["name"] == "net") {
      found = true;
      EXPECT_EQ(o.value("connectome", false), true) << o.dump();
      EXPECT_FALSE(o.contains("color_by")) << o.dump();
    }
  EXPECT_TRUE(found) << described.dump();
  Json radius = edit({{"radius", 2.0}});
  radius["object"] = "net";
  try {
    apply_edit(state, radius);
    ADD_FAILURE() << "a tractogram's radius was accepted for a connectome";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("this object is a connectome"), std::string::npos)
        << e.what();
  }
  const Image before = draw(state.scene());
  Json opacity = edit({{"opacity", 0.4}});
  opacity["object"] = "net";
  EXPECT_TRUE(apply_edit(state, opacity));
  EXPECT_FALSE(same_bytes(before, draw(state.scene())));
}

}  // namespace
}  // namespace imx::server
