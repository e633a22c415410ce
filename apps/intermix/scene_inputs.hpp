// What render and serve take as their scene: one scene file, or volume files, DICOM folders and
// mesh files to build one from (scene/scene_from_files.hpp), with --view and --save-scene.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "scene/scene_document.hpp"

namespace imx::cli {

struct SceneInputs {
  std::vector<std::string> inputs;
  std::string view, save_scene;

  bool is_scene_file() const;
  // The scene file, or the input files joined by spaces: for messages.
  std::string label() const;
};

// The positional inputs, --view and --save-scene.
void add_scene_inputs(CLI::App& app, SceneInputs& in);

// `overrides` with, for a scene file, --view's camera; refuses --save-scene with a scene file.
std::vector<std::string> input_overrides(const SceneInputs& in, std::vector<std::string> overrides);

// The scene file loaded, or the scene built from the input files (with `coarse_levels`, OME-Zarr
// images at the finest level that fits in memory: scene_from_files).
SceneDocument load_scene_inputs(const SceneInputs& in, const std::vector<std::string>& overrides,
                                bool coarse_levels = false);

// The same read with one-voxel regions, its automatic choices written out: what a render in
// bricks plans from (dist/bricked_render.hpp).
SceneDocument load_scene_outline(const SceneInputs& in, const std::vector<std::string>& overrides);

// The outline of a document's JSON (as load_scene_outline reads a file) that came from `origin`,
// its files relative to `base_dir`.
SceneDocument outline_of(nlohmann::json json, std::string origin, std::filesystem::path base_dir);

// With --save-scene (a scene built from files): writes `document`, which renders the same again.
void save_built_scene(const SceneInputs& in, const SceneDocument& document);

}  // namespace imx::cli
