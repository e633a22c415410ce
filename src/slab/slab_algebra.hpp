// The slab algebra in one include: over, split, mix, OFM/SFM, arrays, kernel, resolve merge.
#pragma once
#include "slab/accumulate.hpp"
#include "slab/greedy_merge.hpp"
#include "slab/intermix_kernel.hpp"
#include "slab/mix.hpp"
#include "slab/ofm.hpp"
#include "slab/over.hpp"
#include "slab/resolve_merge.hpp"
#include "slab/sfm.hpp"
#include "slab/slab.hpp"
#include "slab/slab_array.hpp"
#include "slab/split.hpp"
