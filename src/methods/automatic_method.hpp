// The method "auto" stands for (the default of scenes that name none): the fastest method
// within reach of the best image on the scene's kind of content, decided once here from the
// measurements of docs/eval.md (every method against the reference on every example) and of
// real scans (docs/performance.md). The rules, in order:
// - a csg block or exclusive mixing: csg (the one fast method that renders them);
// - surfaces only (meshes and planes, no volume): dfb-sfm, within 0.02 dB of the best on every
//   such example at 1.5x the fastest (mdvr and csg lose up to 6.8 dB where surfaces coincide);
// - volumes with meshes: zslab-hybrid, the fastest (0.65-0.82x mdvr's time on ct-implant,
//   fusion, mpr-widgets and the Philips CT with its screws, 0.41-0.89x kbuffer-ofm's, which it
//   replaced at stop 43) and within 0.05 dB of the best (mdvr loses up to 3.4 dB where a surface
//   crosses a volume);
// - volumes with planes and no mesh: peel, the fastest and within 0.01 dB;
// - several volumes only: zslab-hybrid, 0.66-0.84x mdvr's time, at most 0.07 dB below mdvr and
//   1.5 dB above it on two-volumes (docs/open_data.md);
// - one volume only: mdvr, 2x to 3.5x faster than the per-sample methods on real CT and MR and
//   within 0.3-1.5 dB of the best (the slab methods in its lanes cost 1.0-1.35x for up to
//   1 dB).
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
