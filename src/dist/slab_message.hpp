// SlabMessage: the slab arrays of a range of pixels as one rank sends them to another, and the
// merge of a received message into the receiver's arrays by the intermix kernel.
//
// Layout: one bit per sample (1: its array is not empty), then one count byte per non-empty
// sample, then those samples' slabs as stored (12-byte RGBA8 or 24-byte RGBA32F), so empty
// pixels cost a bit and a slab crosses processes bit for bit.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "dist/swap_schedule.hpp"
#include "slab/intermix_kernel.hpp"
#include "slab/zt_buffer.hpp"

namespace imx {

// The message of `pixels` (spp samples each) of `arrays`, encoded on up to `threads` threads.
std::vector<std::byte> encode_slab_message(const ZtBuffer& arrays, PixelRange pixels, int spp,
                                           int threads = 1);

// The largest message of `pixels` `arrays` can send: every sample's array full. A receiver
// allocates no more than this, whatever size its partner announces.
size_t max_slab_message_bytes(const ZtBuffer& arrays, PixelRange pixels, int spp);

// Merges a message of the same range, sent by a rank with the same capacity and format, into
// `arrays`: per sample, intermix(front, back) where front is `arrays`' own array when
// `mine_first`, else the received one, folding overflow as `mix` says. Throws imx::Error when
// the message does not match the range (its size or a count), before changing anything.
void merge_slab_message(ZtBuffer& arrays, PixelRange pixels, int spp,
                        std::span<const std::byte> message, bool mine_first,
                        const IntermixSettings& mix, int threads);

// The final composite of `pixels`: each sample's array accumulated (ERT at `a_ert`), the
// pixel's samples averaged, over `background`: premultiplied linear RGBA, as render_zslab's.
std::vector<glm::vec4> resolve_slab_arrays(const ZtBuffer& arrays, PixelRange pixels, int spp,
                                           float a_ert, const glm::vec4& background, int threads);

}  // namespace imx
