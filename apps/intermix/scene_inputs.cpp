#include "scene_inputs.hpp"

#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "io/streams/atomic_file.hpp"
#include "scene/camera_framing.hpp"
#include "scene/scene_from_files.hpp"

namespace imx::cli {

bool SceneInputs::is_scene_file() const {
  return inputs.size() == 1 && std::filesystem::path(inputs[0]).extension() == ".json";
}

std::string SceneInputs::label() const {
  return fmt::format("{}", fmt::join(inputs, " "));
}

void add_scene_inputs(CLI::App& app, SceneInputs& in) {
  app.add_option("inputs", in.inputs,
                 "a scene file (JSON), or volume files, DICOM folders and mesh files to build a "
                 "scene from")
      ->required();
  app.add_option("--view", in.view,
                 "the patient direction the camera looks from: anterior (default), posterior, "
                 "left, right, superior or inferior (a scene file: frames its objects)")
      ->check(CLI::IsMember(patient_view_names()));
  app.add_option("--save-scene", in.save_scene,
                 "with input files: write the scene built from them (JSON), to edit and render "
                 "again");
}

std::vector<std::string> input_overrides(const SceneInputs& in,
                                         std::vector<std::string> overrides) {
  if (in.is_scene_file() && !in.save_scene.empty())
    throw Error("--save-scene applies to a scene built from files; this is a scene file");
  if (in.is_scene_file() && !in.view.empty())
    overrides.push_back("camera={\"view\": \"" + in.view + "\"}");
  return overrides;
}

SceneDocument load_scene_inputs(const SceneInputs& in, const std::vector<std::string>& overrides,
                                bool coarse_levels) {
  if (in.is_scene_file()) return SceneDocument::load(in.inputs[0], overrides);
  const std::vector<std::filesystem::path> files(in.inputs.begin(), in.inputs.end());
  return scene_from_files(files, in.view.empty() ? "anterior" : in.view, overrides, {},
                          coarse_levels);
}

namespace {

// What an outline reads of each volume: one voxel, for its header and placement.
VoxelBox one_voxel(const std::string&, const VolumeHeader&) {
  return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
}

}  // namespace

SceneDocument load_scene_outline(const SceneInputs& in, const std::vector<std::string>& overrides) {
  if (in.is_scene_file()) {
    SceneDocument document = SceneDocument::load(in.inputs[0], overrides, one_voxel);
    document.write_out_choices();
    return document;
  }
  const std::vector<std::filesystem::path> files(in.inputs.begin(), in.inputs.end());
  return scene_from_files(files, in.view.empty() ? "anterior" : in.view, overrides, one_voxel);
}

SceneDocument outline_of(nlohmann::json json, std::string origin, std::filesystem::path base_dir) {
  SceneDocument document(std::move(json), std::move(origin), std::move(base_dir), {}, {},
                         one_voxel);
  document.write_out_choices();
  return document;
}

void save_built_scene(const SceneInputs& in, const SceneDocument& document) {
  if (in.save_scene.empty()) return;
  const std::string text = document.text();
  write_file_atomically(in.save_scene, [&](std::ostream& out) { out << text; });
}

}  // namespace imx::cli
