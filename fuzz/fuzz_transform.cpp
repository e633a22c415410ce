// Every transform reader (registration/transform_file.hpp): the input is a transform file's
// bytes, read under each name the dispatcher knows (.tfm, .txt, .mat, .lta, .aff12.1D), so that
// every reader sees every input. FSL matrices are read with two small NIfTI images written once
// (a neurological and a radiological one, so that both scaled-voxel rules run), and once without
// them (the refusal). A transform that is read must be finite and invertible. An input that
// starts like a NIfTI-1 header (348) is also tried as a displacement field on a small volume.
#include <cmath>
#include <exception>
#include <string>

#include "harness.hpp"
#include "registration/displacement_field.hpp"
#include "registration/transform_file.hpp"

namespace {

imx::VolumeData small_image(glm::dvec3 diagonal) {
  imx::VolumeData v;
  v.dims = {4, 5, 3};
  v.voxels = std::vector<uint8_t>(60, 1);
  v.index_to_world = glm::dmat4(1.0);
  for (int a = 0; a < 3; ++a) v.index_to_world[a][a] = diagonal[a];
  v.index_to_world[3] = glm::dvec4(3.0, -2.0, 1.0, 1.0);
  return v;
}

// The two images, written once in the harness's scratch folder (removed at exit; this harness
// writes nothing else there, so it never clears it).
const imx::TransformFileImages& images() {
  static const imx::TransformFileImages written = [] {
    const std::filesystem::path& dir = imx::fuzz::scratch().path();
    imx::TransformFileImages i{dir / "moving.nii", dir / "reference.nii"};
    imx::write_volume(small_image({-1.5, -1.0, 2.0}), i.moving, false);
    imx::write_volume(small_image({1.0, -1.2, 1.0}), i.reference, false);
    return i;
  }();
  return written;
}

void check(const imx::FileTransform& t) {
  const glm::dmat4& m = t.moving_to_fixed;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) __builtin_trap();
  if (!(std::abs(glm::determinant(glm::dmat3(m))) > 0.0)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const std::string_view bytes = as_view(data, size);
  for (const char* name : {"in.tfm", "in.txt", "in.mat", "in.lta", "in.aff12.1D"}) {
    try {
      check(imx::parse_transform_file(bytes, name));
      accepted(name);
    } catch (const std::exception& e) {
      refused(e);
    }
  }
  try {
    check(imx::parse_transform_file(bytes, "flirt.mat", images()));
    accepted("flirt.mat with images");
  } catch (const std::exception& e) {
    refused(e);
  }
  if (size >= 4 && data[0] == 92 && data[1] == 1 && data[2] == 0 && data[3] == 0) {
    try {
      const std::filesystem::path field = scratch().write("field.nii", data, size);
      if (imx::is_displacement_field(field)) {
        const imx::VolumeData warped = imx::warp_volume(small_image({1.0, 1.0, 1.0}), field);
        check_volume(warped);
        accepted("displacement field");
      }
    } catch (const std::exception& e) {
      refused(e);
    }
  }
  return 0;
}
