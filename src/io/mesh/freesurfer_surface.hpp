// FreeSurfer binary surfaces (lh.pial, lh.white, lh.inflated, ...): the triangle format, known by
// its magic number 0xFFFFFE whatever the file is called.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Whether `head` (a file's first bytes) starts with the triangle surface's magic number.
bool is_freesurfer_surface(std::string_view head);

struct FreeSurferSurface {
  Mesh mesh;         // scanner RAS, mm (the caller converts RAS to LPS)
  std::string note;  // how tkr-RAS became scanner RAS, for the user
};

// Reads a triangle surface as nibabel.freesurfer.read_geometry does (big-endian: magic, a
// "created by" line and one more line, vertex and face counts, float32 x y z, int32 faces),
// then its optional volume-geometry footer (read_metadata=True: "valid", "filename", "volume",
// "voxelsize", "xras", "yras", "zras", "cras"). The vertices are in tkr-RAS, the RAS of the
// conformed volume's centre; with a valid geometry they are moved to scanner RAS as FreeSurfer
// does, vox2ras * inverse(tkr vox2ras): for the usual LIA geometry that adds c_ras. Without a
// valid geometry tkr-RAS is kept and the note says so. Quad surfaces (0xFFFFFF, 0xFFFFFD) are
// refused. Every count and index is checked against the file: an imx::Error names the fault.
FreeSurferSurface read_freesurfer_surface(const std::filesystem::path& file);

}  // namespace imx::detail
