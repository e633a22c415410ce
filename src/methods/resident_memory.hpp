// What rendering a scene holds resident per volume, as the method that renders it accelerates
// its volumes: `intermix info FILE --memory` and `intermix-lab bench` report it.
#pragma once
#include <string>
#include <vector>

#include "intermix/scene.hpp"
#include "volume/volume_acceleration.hpp"

namespace imx {

// resident_parts() of each of `scene`'s volumes, in scene order, when `method` (a name
// resolve_method returns) renders it: a method that marches one volume alone in lanes takes
// `auto` gradients on the fly (accelerate_for_packets), the others keep the copy.
std::vector<std::vector<ResidentPart>> resident_parts(const Scene& scene,
                                                      const std::string& method);

}  // namespace imx
