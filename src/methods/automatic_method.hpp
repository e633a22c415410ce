// The method "auto" stands for (the default of scenes that name none): the fastest method
// within reach of the best image on the scene's kind of content, decided once here from the
// measurements of docs/eval.md (every method against the reference on every example) and of
// real scans (docs/performance.md). The rules, in order:
// - a csg block or exclusive mixing: csg (the one fast method that renders them);
// - surfaces only (meshes and planes, no volume): dfb-sfm, within 0.02 dB of the best on every
//   such example at 1.5x the fastest (mdvr and csg lose up to 6.8 dB where surfaces coincide);
// - volumes with meshes: kbuffer-ofm, within 0.03 dB of the best at 1.4x the fastest (mdvr
//   loses up to 3.4 dB where a surface crosses a volume);
// - volumes with planes and no mesh: peel, the fastest and within 0.01 dB;
// - volumes only: mdvr, 2x to 3.5x faster than any other on real CT and MR, within 0.3-1.5 dB
//   of the best (the others' extra 1 dB costs more than the 2x a user waits for auto to keep).
#pragma once
#include <string>

#include "intermix/scene.hpp"

namespace imx {

struct MethodChoice {
  std::string method;
  std::string reason;  // "volumes only", for the line that reports the render
};

MethodChoice choose_method(const Scene& scene);

}  // namespace imx
