// Reading and writing files: volumes (NRRD, NIfTI, MetaImage), meshes (assimp), images (PNG),
// phantoms.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/image.hpp"
#include "intermix/mesh.hpp"
#include "intermix/volume.hpp"

namespace imx {

// Reads a volume; the format comes from the extension (.nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd).
// World space is LPS: NIfTI's RAS is converted, MetaImage is LPS already (as in ITK).
// Throws imx::Error naming the file and the fault.
VolumeData read_volume(const std::filesystem::path& file);

// Writes a NRRD file (gzip-encoded when `gzip`), atomically.
void write_nrrd(const VolumeData& volume, const std::filesystem::path& file, bool gzip = true);

// Writes a MetaImage .mha file with attached data (zlib-compressed when `compress`), atomically.
void write_metaimage(const VolumeData& volume, const std::filesystem::path& file,
                     bool compress = true);

// Reads a triangle mesh through assimp (OBJ, PLY, STL, glTF, ...), triangulated, in file units.
Mesh read_mesh(const std::filesystem::path& file);

// Names of the built-in volume phantoms.
std::vector<std::string> phantom_names();

// A built-in phantom volume; `size` is the voxel count along its largest axis.
VolumeData make_phantom(const std::string& name, int size);

// Writes a premultiplied linear image as 8-bit RGBA PNG (straight alpha, sRGB-encoded colour
// unless `linear`), atomically: a temporary file beside it, then a rename.
void write_png(const Image& image, const std::filesystem::path& file, bool linear = false);

// Reads an 8-bit or 16-bit PNG back to premultiplied linear RGBA (sRGB decoded unless `linear`).
Image read_png(const std::filesystem::path& file, bool linear = false);

}  // namespace imx
