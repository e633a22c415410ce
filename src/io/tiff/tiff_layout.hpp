// Which page of which file holds each slice of a TIFF volume, and where its voxels lie: a
// multi-page TIFF (plain, ImageJ hyperstack or OME-TIFF) or a folder of single-page TIFFs.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "intermix/volume.hpp"
#include "io/tiff/tiff_file.hpp"

namespace imx::detail {

// One plane: the file (an index into TiffLayout::files) and its page's directory number (-1 in
// a folder stack: the file's one full page).
struct TiffPlane {
  int file = 0;
  int directory = 0;
};

struct TiffLayout {
  std::string what;  // the file or folder, for messages
  std::vector<std::filesystem::path> files;
  std::shared_ptr<TiffFile> opened;  // files[0], already open
  bool folder = false;               // one single-page file per slice
  glm::ivec3 dims{0};
  RawType type = RawType::u8;
  uint32_t first_directory = 0;  // the page every other is compared with
  glm::dvec3 spacing{1.0};       // mm, x y z
  int frames = 1, channels = 1;
  std::vector<TiffPlane> planes;  // z + dims.z * (c + channels * t); empty for a folder

  TiffPlane plane(int z, int channel, int frame) const;
  glm::dmat4 index_to_world() const;
};

// The layout of `path`, a TIFF file or a folder of them (is_tiff_folder). Every page a slice
// uses is checked here: readable (TiffPage::problem), and the first's size and type. Throws
// imx::Error naming the file, page and field.
TiffLayout tiff_layout(const std::filesystem::path& path);

// Whether `a` sorts before `b` with runs of digits compared as numbers: z2.tif before z10.tif.
bool natural_less(const std::string& a, const std::string& b);

// Throws imx::Error naming `what`, the page (or file) and field unless `page` can be a slice of
// `layout`: readable, of the layout's width, height and type.
void check_slice_page(const TiffLayout& layout, const TiffPage& page, const std::string& what);

}  // namespace imx::detail
