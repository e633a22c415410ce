#include "dist/slab_message.hpp"

#include <cstring>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "slab/accumulate.hpp"
#include "slab/zslab_params.hpp"

namespace imx {

std::vector<std::byte> encode_slab_message(const ZtBuffer& arrays, PixelRange pixels, int spp,
                                           int threads) {
  const size_t first = pixels.first * static_cast<size_t>(spp);
  const size_t samples = pixels.size() * static_cast<size_t>(spp);
  const size_t slab_size = static_cast<size_t>(slab_bytes(arrays.format()));
  const size_t mask_bytes = (samples + 7) / 8;
  // Blocks of samples, a multiple of 8 so that no two share a mask byte: counted in parallel,
  // then written in parallel at offsets from the counts' prefix sums.
  constexpr size_t kBlock = 4096;
  const size_t blocks = (samples + kBlock - 1) / kBlock;
  std::vector<size_t> count_at(blocks + 1, 0), slab_at(blocks + 1, 0);
  parallel_for(static_cast<long>(blocks), threads, [&](long b0, long b1) {
    for (size_t b = static_cast<size_t>(b0); b < static_cast<size_t>(b1); ++b)
      for (size_t i = b * kBlock; i < std::min(samples, (b + 1) * kBlock); ++i) {
        const size_t n = static_cast<size_t>(arrays.count(first + i));
        count_at[b + 1] += n > 0;
        slab_at[b + 1] += n * slab_size;
      }
  });
  count_at[0] = mask_bytes;
  for (size_t b = 0; b < blocks; ++b) count_at[b + 1] += count_at[b];
  slab_at[0] = count_at[blocks];
  for (size_t b = 0; b < blocks; ++b) slab_at[b + 1] += slab_at[b];

  std::vector<std::byte> out(slab_at[blocks], std::byte{0});
  parallel_for(static_cast<long>(blocks), threads, [&](long b0, long b1) {
    for (size_t b = static_cast<size_t>(b0); b < static_cast<size_t>(b1); ++b) {
      std::byte* count_to = out.data() + count_at[b];
      std::byte* slab_to = out.data() + slab_at[b];
      for (size_t i = b * kBlock; i < std::min(samples, (b + 1) * kBlock); ++i) {
        const int n = arrays.count(first + i);
        if (n == 0) continue;
        out[i / 8] |= std::byte(1u << (i % 8));
        *count_to++ = std::byte(static_cast<uint8_t>(n));
        std::memcpy(slab_to, arrays.slots(first + i), static_cast<size_t>(n) * slab_size);
        slab_to += static_cast<size_t>(n) * slab_size;
      }
    }
  });
  return out;
}

size_t max_slab_message_bytes(const ZtBuffer& arrays, PixelRange pixels, int spp) {
  const size_t samples = pixels.size() * static_cast<size_t>(spp);
  const size_t slab_size = static_cast<size_t>(slab_bytes(arrays.format()));
  return (samples + 7) / 8 + samples * (1 + static_cast<size_t>(arrays.capacity()) * slab_size);
}

void merge_slab_message(ZtBuffer& arrays, PixelRange pixels, int spp,
                        std::span<const std::byte> message, bool mine_first,
                        const IntermixSettings& mix, int threads) {
  const size_t first = pixels.first * static_cast<size_t>(spp);
  const size_t samples = pixels.size() * static_cast<size_t>(spp);
  const size_t slab_size = static_cast<size_t>(slab_bytes(arrays.format()));
  const size_t mask_bytes = (samples + 7) / 8;
  auto malformed = [&](const std::string& why) {
    return Error(fmt::format("distributed: a slab message of {} bytes for {} samples {}",
                             message.size(), samples, why));
  };
  if (message.size() < mask_bytes) throw malformed("is shorter than its sample mask");
  // Where each sample's slabs start (SIZE_MAX: empty), checked against the message's size.
  std::vector<size_t> offset(samples, SIZE_MAX);
  std::vector<uint8_t> count(samples, 0);
  size_t nonempty = 0;
  for (size_t i = 0; i < samples; ++i)
    nonempty += (std::to_integer<unsigned>(message[i / 8]) >> (i % 8)) & 1u;
  size_t at = mask_bytes + nonempty, k = 0;
  if (message.size() < at) throw malformed("is shorter than its counts");
  for (size_t i = 0; i < samples; ++i) {
    if (((std::to_integer<unsigned>(message[i / 8]) >> (i % 8)) & 1u) == 0) continue;
    uint8_t n = std::to_integer<uint8_t>(message[mask_bytes + k++]);
    if (n == 0 || n > arrays.capacity())
      throw malformed(fmt::format("holds {} slabs for one sample (1 to {})", n, arrays.capacity()));
    offset[i] = at;
    count[i] = n;
    at += n * slab_size;
  }
  if (at != message.size()) throw malformed(fmt::format("should have {} bytes", at));

  const int n = arrays.capacity();
  parallel_for(static_cast<long>(samples), threads, [&](long begin, long end) {
    Slab mine[kMaxZslabLayers], theirs[kMaxZslabLayers], merged[kMaxZslabLayers];
    for (long s = begin; s < end; ++s) {
      const size_t i = static_cast<size_t>(s);
      if (offset[i] == SIZE_MAX) continue;
      int own = arrays.load(first + i, std::span<Slab>(mine, static_cast<size_t>(n)));
      for (int j = 0; j < count[i]; ++j)
        theirs[j] = unpack_bytes(message.data() + offset[i] + j * slab_size, arrays.format());
      std::span<const Slab> a(mine, static_cast<size_t>(own)), b(theirs, count[i]);
      SlabList out(std::span<Slab>(merged, static_cast<size_t>(n)));
      intermix(mine_first ? a : b, mine_first ? b : a, out, mix);
      arrays.store(first + i, out.items());
    }
  });
}

std::vector<glm::vec4> resolve_slab_arrays(const ZtBuffer& arrays, PixelRange pixels, int spp,
                                           float a_ert, const glm::vec4& background, int threads) {
  std::vector<glm::vec4> out(pixels.size());
  const float weight = 1.0f / static_cast<float>(spp);
  parallel_for(static_cast<long>(pixels.size()), threads, [&](long begin, long end) {
    Slab slabs[kMaxZslabLayers];
    for (long p = begin; p < end; ++p) {
      glm::vec4 sum(0.0f);
      for (int s = 0; s < spp; ++s) {
        size_t sample = (pixels.first + static_cast<size_t>(p)) * static_cast<size_t>(spp) +
                        static_cast<size_t>(s);
        int count = arrays.load(sample, slabs);
        sum += accumulate(std::span<const Slab>(slabs, static_cast<size_t>(count)), a_ert).color;
      }
      out[static_cast<size_t>(p)] = over_background(sum * weight, background);
    }
  });
  return out;
}

}  // namespace imx
