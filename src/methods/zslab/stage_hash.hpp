// StageHash: the hash of what a pipeline stage reads, the key of its kept output.
#pragma once
#include "core/fnv1a.hpp"

namespace imx {

using StageHash = Fnv1a;

}  // namespace imx
