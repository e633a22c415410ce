// The head that ct-head and pet share: its field of view and main ellipsoids (mm, LPS).
#pragma once
#include <glm/vec3.hpp>

namespace imx::detail::head {

// Field of view: x left-right, y anterior(-) to posterior(+), z inferior(-) to superior(+).
inline constexpr glm::dvec3 kFieldOfView{192.0, 230.4, 216.0};
// The cranium's centre sits a little posterior, leaving room for the nose in front.
inline constexpr glm::dvec3 kCentre{0.0, 4.0, 0.0};
inline constexpr glm::dvec3 kSkin{75.0, 95.0, 90.0};        // 150 x 190 x 180 mm head
inline constexpr glm::dvec3 kSkullOuter{71.0, 91.0, 86.0};  // 4 mm of scalp
inline constexpr glm::dvec3 kDiploe{69.0, 89.0, 84.0};      // 2 mm outer table
inline constexpr glm::dvec3 kInnerTable{66.0, 86.0, 81.0};  // 3 mm diploe
inline constexpr glm::dvec3 kSkullInner{64.0, 84.0, 79.0};  // 2 mm inner table
inline constexpr glm::dvec3 kBrain{62.0, 82.0, 77.0};       // 2 mm of CSF around the brain

}  // namespace imx::detail::head
