// One row per volume format. A new format: its reader file and one row here (docs/architecture.md).
#include "io/volume/volume_formats.hpp"

#include <vector>

#include "intermix/dicom.hpp"
#include "io/registry/tiff_sniff.hpp"
#include "io/tiff/tiff_reader.hpp"
#include "io/volume/afni.hpp"
#include "io/volume/metaimage.hpp"
#include "io/volume/mgh.hpp"
#include "io/volume/minc.hpp"
#include "io/volume/mrtrix.hpp"
#include "io/volume/nifti.hpp"
#include "io/volume/nrrd.hpp"
#include "io/volume/parrec.hpp"
#include "io/zarr/ome_zarr_reader.hpp"

namespace imx::detail {
namespace {

bool dicom_source(const FileProbe& probe) {
  return is_dicom_source(probe.path);
}

VolumeData read_dicom_volume(const std::filesystem::path& file, int frame) {
  DicomReadOptions options;
  options.frame = frame;
  return read_dicom(file, options).volume;
}

VolumeHeader read_dicom_volume_header(const std::filesystem::path& file) {
  return read_dicom_header(file);
}

// DICOM is read whole and cropped: its voxels come slice file by slice file, decoded (and
// possibly decompressed) by GDCM, with no byte layout to seek in.
VolumeData read_dicom_volume_region(const std::filesystem::path& file, const VoxelBox& box,
                                    int frame) {
  return crop(read_dicom_volume(file, frame), box, file.string());
}

// An OME-Zarr image is a folder: read whole (channel 0, frame = time point) and cropped; a scene's
// "source": {"channel": C} reads another (volume_object_parser.cpp).
VolumeData read_zarr_volume(const std::filesystem::path& dir, int frame) {
  return read_ome_zarr(dir, 0, frame, 0);
}

VolumeData read_zarr_volume_region(const std::filesystem::path& dir, const VoxelBox& box,
                                   int frame) {
  return read_ome_zarr_region(dir, box, 0, frame, 0);
}

// A TIFF's frame is its time point (OME-TIFF, ImageJ hyperstacks), channel 0.
VolumeData read_tiff_volume(const std::filesystem::path& path, int frame) {
  return read_tiff(path, frame, 0);
}

VolumeData read_tiff_volume_region(const std::filesystem::path& path, const VoxelBox& box,
                                   int frame) {
  return read_tiff_region(path, box, frame, 0);
}

}  // namespace

std::span<const VolumeFormat> volume_formats_table() {
  static const std::vector<VolumeFormat> table = {
      // Before DICOM, whose sniff takes any other folder.
      {{.kind = FileKind::volume,
        .name = "OME-Zarr (NGFF 0.4 / 0.5, Zarr v2 / v3 folder)",
        .extensions = {".zarr", ".ome.zarr"},
        .sniff = [](const FileProbe& p) { return p.folder && is_zarr_folder(p.path); },
        .fuzz_target = "fuzz_zarr",
        .reference = "zarr-python 2; v3 spec fixtures"},
       read_zarr_volume,
       [](const std::filesystem::path& dir) { return read_ome_zarr_header(dir); },
       read_zarr_volume_region},
      // Also before DICOM: a folder whose files are all .tif/.tiff is a stack of slices.
      {{.kind = FileKind::volume,
        .name = "TIFF stack, OME-TIFF, BigTIFF (file or folder)",
        .extensions = {".tif", ".tiff", ".ome.tif", ".ome.tiff"},
        .sniff =
            [](const FileProbe& p) {
              if (p.folder) return is_tiff_folder(p.path);
              return !p.name.ends_with(".gz") && is_tiff_head(p.head);
            },
        .fuzz_target = "fuzz_tiff",
        .fuzz_seeds = "*.tif *.tiff",
        .reference = "tifffile"},
       read_tiff_volume,
       read_tiff_header,
       read_tiff_volume_region},
      {{.kind = FileKind::volume,
        .name = "DICOM",
        .extensions = {".dcm", ".dicom", ".dcm.gz"},
        .sniff = dicom_source,
        .fuzz_target = "fuzz_dicom",
        .fuzz_seeds = "*.dcm",
        .reference = "dcm2niix"},
       read_dicom_volume,
       read_dicom_volume_header,
       read_dicom_volume_region},
      {{.kind = FileKind::volume,
        .name = "NRRD",
        .extensions = {".nrrd", ".nhdr"},
        .writes = ".nrrd",
        .fuzz_target = "fuzz_nrrd",
        .fuzz_seeds = "*.nrrd *.nhdr",
        .reference = "teem (unu), pynrrd",
        .gz_wrapped = {".nrrd"}},
       read_nrrd,
       read_nrrd_header,
       read_nrrd_region},
      {{.kind = FileKind::volume,
        .name = "NIfTI-1/2, Analyze 7.5",
        .extensions = {".nii", ".nii.gz", ".hdr", ".hdr.gz", ".img", ".img.gz"},
        .writes = ".nii, .nii.gz",
        .fuzz_target = "fuzz_nifti",
        .fuzz_seeds = "*.nii *.nii.gz",
        .reference = "nibabel"},
       read_nifti,
       read_nifti_header,
       read_nifti_region},
      {{.kind = FileKind::volume,
        .name = "MetaImage",
        .extensions = {".mha", ".mhd"},
        .writes = ".mha",
        .fuzz_target = "fuzz_metaimage",
        .fuzz_seeds = "*.mha *.mhd",
        .reference = "ITK",
        .gz_wrapped = {".mha"}},
       read_metaimage,
       read_metaimage_header,
       read_metaimage_region},
      {{.kind = FileKind::volume,
        .name = "FreeSurfer MGH",
        .extensions = {".mgh", ".mgz", ".mgh.gz"},
        .fuzz_target = "fuzz_mgh",
        .fuzz_seeds = "*.mgh *.mgz",
        .reference = "nibabel"},
       read_mgh,
       read_mgh_header,
       read_mgh_region},
      {{.kind = FileKind::volume,
        .name = "AFNI BRIK/HEAD",
        .extensions = {".head", ".brik", ".brik.gz"},
        .sniff = [](const FileProbe& p) { return is_afni_head(p.head); },
        .fuzz_target = "fuzz_afni",
        .reference = "nibabel.brikhead"},
       read_afni,
       read_afni_header,
       read_afni_region},
      {{.kind = FileKind::volume,
        .name = "MRtrix image",
        .extensions = {".mif", ".mif.gz", ".mih"},
        .sniff = [](const FileProbe& p) { return is_mrtrix_header(p.head); },
        .fuzz_target = "fuzz_mrtrix",
        .fuzz_seeds = "*.mif",
        .reference = "MRtrix3 (mrconvert)"},
       read_mrtrix,
       read_mrtrix_header,
       read_mrtrix_region},
      {{.kind = FileKind::volume,
        .name = "Philips PAR/REC",
        .extensions = {".par", ".rec"},
        .sniff = [](const FileProbe& p) { return is_parrec_header(p.head); },
        .fuzz_target = "fuzz_parrec",
        .fuzz_seeds = "*.par",
        .reference = "nibabel.parrec"},
       read_parrec,
       read_parrec_header,
       read_parrec_region},
      {{.kind = FileKind::volume,
        .name = "MINC-2 (MINC-1 named and refused)",
        .extensions = {".mnc"},
        .sniff = [](const FileProbe& p) { return is_minc(p.head); },
        .fuzz_target = "fuzz_minc",
        .fuzz_seeds = "*.mnc",
        .reference = "nibabel.minc2",
        .gz_wrapped = {".mnc"}},
       read_minc,
       read_minc_header,
       read_minc_region},
  };
  return table;
}

const VolumeFormat* find_volume_format(const FileProbe& probe, bool* wrapped) {
  return find_format(volume_formats_table(), probe, wrapped);
}

}  // namespace imx::detail
