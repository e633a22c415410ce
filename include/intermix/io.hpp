// Reading and writing files: volumes (NRRD, NIfTI, MetaImage), meshes (assimp), images (PNG),
// phantoms.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "intermix/image.hpp"
#include "intermix/mesh.hpp"
#include "intermix/volume.hpp"

namespace imx {

// Reads a volume; the format comes from the extension (.nrrd/.nhdr; .nii/.nii.gz, NIfTI-1 or
// NIfTI-2; .hdr/.img pairs, named by either and either gzipped, NIfTI-1, NIfTI-2 or Analyze 7.5;
// .mha/.mhd; FreeSurfer .mgh/.mgz), and a folder, DICOMDIR or DICOM file gives its largest series
// (read_dicom, intermix/dicom.hpp, chooses another and says what it chose).
// World space is LPS: NIfTI's, Analyze's and MGH's RAS is converted (Analyze, which stores no
// orientation, and MGH are placed as nibabel places them), MetaImage is LPS already (as in ITK).
// Throws imx::Error naming the file and the fault.
// A 4-D file (NIfTI or Analyze dim[4] or dim[5], MGH frames, a NRRD list/vector axis, a
// multi-volume DICOM series) holds several frames on one grid: `frame` picks one (0-based; out
// of range: imx::Error), and only that frame's voxels are read and held.
VolumeData read_volume(const std::filesystem::path& file, int frame = 0);

// True when read_volume takes `file` by its name: a volume format's extension, or a DICOM
// source (is_dicom_source). volume_formats() lists them for messages.
bool is_volume_file(const std::filesystem::path& file);
std::string volume_formats();

// What a volume file holds, from its header alone (DICOM: the series' headers are read), with
// its frame count and labels.
VolumeHeader read_volume_header(const std::filesystem::path& file);

// Only the voxels of `box` (within the file's dims, else imx::Error), as crop(read_volume(file),
// box) gives them, but reading no more than it must: uncompressed NRRD, MetaImage and NIfTI data
// are read row by row with seeks past the rest; gzip/zlib data is inflated as a stream, keeping
// only the box; DICOM series are read whole and cropped. The file is checked as read_volume
// checks it: the whole grid's data must be there, and a stream is inflated to its end so that
// its checksum is checked (time as for the whole, memory as for the box).
VolumeData read_volume_region(const std::filesystem::path& file, const VoxelBox& box,
                              int frame = 0);

// Writes a NRRD file (gzip-encoded when `gzip`), atomically.
void write_nrrd(const VolumeData& volume, const std::filesystem::path& file, bool gzip = true);

// Writes a MetaImage .mha file with attached data (zlib-compressed when `compress`), atomically.
void write_metaimage(const VolumeData& volume, const std::filesystem::path& file,
                     bool compress = true);

// Writes a NIfTI-1 .nii file (gzip-compressed when `gzip`, for .nii.gz), atomically. The
// affine goes to the sform exactly and to the qform as its nearest rotation, both RAS.
void write_nifti(const VolumeData& volume, const std::filesystem::path& file, bool gzip = true);

// Writes a 4-D NIfTI-1 .nii file (gzip-compressed when `gzip`) of `frames` as its time points
// (dim[0] 4, dim[4] the frame count, even of one), atomically, as write_nifti writes one volume;
// pixdim[4] is `frame_seconds` with xyzt_units in seconds when it is > 0 (0: unknown). The
// frames must share dims, voxel type and placement (their affines equal to NIfTI's float
// precision), else imx::Error naming the file and the frame.
void write_nifti_frames(const std::vector<VolumeData>& frames, const std::filesystem::path& file,
                        double frame_seconds = 0.0, bool gzip = true);

// Writes `volume` in the format its extension names: .nii.gz, .nii, .nrrd or .mha, atomically.
// `compress` applies to NRRD and MetaImage (NIfTI follows the .gz). Throws imx::Error naming
// the file for any other extension; can_write_volume says beforehand.
void write_volume(const VolumeData& volume, const std::filesystem::path& file,
                  bool compress = true);
bool can_write_volume(const std::filesystem::path& file);

// Which way a mesh file's x and y axes point: LPS (intermix's world, DICOM) or RAS (3D Slicer
// before 4.11, FreeSurfer, GIfTI). RAS becomes LPS by negating x and y (a rotation).
enum class MeshSpace { lps, ras };
// Where the space of a mesh file came from.
enum class MeshSpaceSource { assumed, header, format, option };

struct MeshReadOptions {
  std::optional<MeshSpace> space;  // overrides what the file says
  double crease_angle_deg = 60.0;  // computed normals: sharper edges keep a normal per side
};

// What read_mesh_file found out about the file besides its mesh.
struct MeshFileInfo {
  MeshSpace space = MeshSpace::lps;  // the file's space; the mesh is in LPS whatever it is
  MeshSpaceSource space_source = MeshSpaceSource::assumed;
  bool file_normals = false;  // per-vertex normals from the file, else computed (angle-weighted)
  bool file_colors = false;   // per-vertex colours from the file
  size_t file_vertices = 0;   // vertices as read, before computed normals weld and split them
  // What reading chose that the user should know (a FreeSurfer surface's c_ras offset).
  std::vector<std::string> notes;
};

// Values a mesh file gives its vertices (VTK point data): `components` values per file vertex.
struct MeshPointData {
  std::string name;
  int components = 1;
  std::vector<double> values;  // file_vertices * components, vertex after vertex
};

struct MeshFile {
  Mesh mesh;
  MeshFileInfo info;
  // The file's vertex each vertex of `mesh` came from (computed normals weld and split
  // vertices): what maps per-vertex values of the file, or of an overlay file, onto the mesh.
  std::vector<uint32_t> file_vertex;
  std::vector<MeshPointData> point_data;  // scalars other than normals, by the file's names
};

// Reads a triangle mesh (.obj, .stl, .off, .gltf, .glb through assimp; .ply, GIfTI .gii,
// FreeSurfer surfaces (lh.pial, ..., known by their magic number), VTK legacy .vtk and XML .vtp
// polydata by hand), triangulated, in LPS mm. The space is options.space, else a 3D Slicer
// header comment (SPACE=RAS / SPACE=LPS in an STL header, the leading comments of an OBJ, a PLY
// comment, a VTK file's title line, a VTP's SPACE field), else the format's own (GIfTI and
// FreeSurfer: RAS; a FreeSurfer surface's tkr-RAS is moved to scanner RAS by its volume
// geometry's c_ras), else LPS. Normals come from the
// file where it stores them per vertex (not STL's per-facet ones), else are computed
// angle-weighted with vertices split at edges sharper than the crease angle.
// Throws imx::Error naming the file and the fault.
MeshFile read_mesh_file(const std::filesystem::path& file, const MeshReadOptions& options = {});
// True for the extensions read_mesh_file reads; mesh_formats() lists them for messages.
bool is_mesh_file(const std::filesystem::path& file);
std::string mesh_formats();

// read_mesh_file(file).mesh.
Mesh read_mesh(const std::filesystem::path& file);
// "LPS" or "RAS".
const char* mesh_space_name(MeshSpace space);

// Names of the built-in volume phantoms.
std::vector<std::string> phantom_names();

// A built-in phantom volume; `size` is the voxel count along its largest axis.
VolumeData make_phantom(const std::string& name, int size);
// The dims and placement make_phantom(name, size) gives, without making it.
VolumeHeader phantom_header(const std::string& name, int size);
// crop(make_phantom(name, size), box), computing only the voxels of `box`.
VolumeData make_phantom_region(const std::string& name, int size, const VoxelBox& box);

// Writes a premultiplied linear image as 8-bit RGBA PNG (straight alpha, sRGB-encoded colour
// unless `linear`), atomically: a temporary file beside it, then a rename.
void write_png(const Image& image, const std::filesystem::path& file, bool linear = false);

// The same PNG in memory; `what` names the image in errors; a zlib level 0-9 (-1: spng's).
std::string encode_png(const Image& image, const std::string& what, bool linear = false,
                       int compression_level = -1);

// What write_png stores: 8-bit straight RGBA, sRGB-encoded unless `linear`, row 0 first.
std::vector<uint8_t> display_rgba8(const Image& image, bool linear = false);

// Reads an 8-bit or 16-bit PNG back to premultiplied linear RGBA (sRGB decoded unless `linear`).
Image read_png(const std::filesystem::path& file, bool linear = false);

}  // namespace imx
