// Colour tables of label maps: the first byte picks the file's name (a FreeSurfer / ITK-SNAP text
// table, or a 3D Slicer .seg.nrrd) and, for a segmentation, the layer to read; the rest is the
// file. An accepted table must hold unique labels within +-2^24 and colours and opacities in
// [0, 1], which the classifier's tables are then built from.
#include <cmath>
#include <cstdlib>
#include <exception>
#include <set>

#include "harness.hpp"
#include "intermix/labels.hpp"
#include "volume/label_classifier.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const bool nrrd = data[0] & 1;
  const int layer = (data[0] >> 1) & 3;
  const std::filesystem::path file = dir.write(nrrd ? "in.seg.nrrd" : "in.txt", data + 1, size - 1);
  try {
    const std::vector<imx::LabelEntry> table = imx::read_label_table(file, nrrd ? layer : 0);
    std::set<int32_t> values;
    for (const imx::LabelEntry& e : table) {
      bool ok = values.insert(e.value).second && std::abs(int64_t{e.value}) <= (int64_t{1} << 24);
      for (int c = 0; c < 3; ++c) ok = ok && e.color[c] >= 0.0f && e.color[c] <= 1.0f;
      ok = ok && e.opacity >= 0.0f && e.opacity <= 1.0f;
      if (!ok) std::abort();  // a reader let through what the classifier would misread
    }
    imx::LabelMap map;
    map.entries = table;
    map.palette_unlisted = false;
    const imx::LabelLooks looks(map);
    for (const imx::LabelEntry& e : table)
      if (looks.look(e.value) != (e.visible ? glm::vec4(e.color, e.opacity) : glm::vec4(0.0f)))
        std::abort();  // the table the renderer builds disagrees with the file
    accepted(nrrd ? "seg.nrrd" : "text");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
