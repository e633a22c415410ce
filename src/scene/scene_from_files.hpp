// A scene built from files alone (`intermix render FLAIR.nii.gz`, `intermix serve CT/`,
// Python's Scene.from_files): each volume file or DICOM folder a volume object with the
// automatic transfer function of what it is (automatic_look.hpp), each mesh file a mesh object in
// a palette colour, and a camera framing them all from a patient direction. The document it
// returns has every choice written out, so saved and rendered again it gives the same image.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"

namespace imx {

// The document is the scene file for these inputs, every choice explicit (relative paths are
// made absolute). `view` is a patient direction (camera_framing.hpp); `overrides` are --set
// assignments applied to the built document before it is read ("image.width=256",
// "objects.FLAIR.style=mip"). Throws imx::Error naming a file that is neither a volume nor a mesh
// intermix reads, and every error load_scene gives, with "scene from files" as the document's name.
// With `region`, volumes are read by region as load_scene's (the plan of a render in bricks).
// With `coarse_levels`, each OME-Zarr source is at "level": "view": the finest level that fits
// in memory, or a coarser one whose voxels still fit the image's pixels (the viewer's choice,
// where render draws level 0 in bricks).
SceneDocument scene_from_files(const std::vector<std::filesystem::path>& files,
                               const std::string& view = "anterior",
                               const std::vector<std::string>& overrides = {},
                               const VolumeRegionChooser& region = {}, bool coarse_levels = false);

// The colours meshes of a scene from files get, in order (then again from the first).
const std::vector<glm::vec3>& mesh_palette();

}  // namespace imx
