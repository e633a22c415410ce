// The transfer function a volume gets when its scene object names none (and every volume of a
// scene built from files): chosen from what the volume is, as a scene file spells it, so that a
// saved scene renders the same. The rules, in order:
// - a colour volume (VolumeData::colours): opacity rising from 0 at black to 1 at white over its
//   luminance, its voxels' own colours (NiiVue's look of an RGB volume);
// - CT (DICOM modality CT, units HU, or values from air at -1000 up past water): preset ct-bone;
// - PET (modality PT, or units g/ml or BQML): a hot colour ramp over the upper values;
// - a signed map (floats well on both sides of zero: t or z statistics): blue below -t, red to
//   yellow above t, nothing between, with t = 40% of the largest robust magnitude;
// - a mask (one value above a background): its boundary as a shaded surface;
// - anything else (MR, ...): a grey ramp over the robust range (2nd to 98th percentile, as
//   NiiVue's cal_min/cal_max), transparent below its first tenth.
#pragma once
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "intermix/volume.hpp"

namespace imx {

struct AutomaticLook {
  nlohmann::json transfer_function;  // {"preset": ...} or {"points": [...]}
  nlohmann::json shading;            // an object's "shading", or null for the preset's own
  std::string reason;                // "CT (HU): preset ct-bone", for a note
};

// Whether a volume of a scene built from files is a label map (a segmentation: style "labels"
// with the default palette): integer voxels of 3 to 256 distinct values, either at most 16 or
// filling at most half the span between the smallest and largest (an 8-bit MR fills it all; a
// FreeSurfer aseg holds about 45 values of 0 to 255). Two values stay a mask surface.
bool looks_like_label_map(const VolumeData& data);

// `modality` and `units` are the DICOM series' (empty for other files).
AutomaticLook automatic_look(const VolumeData& data, std::string_view modality,
                             std::string_view units);

}  // namespace imx
