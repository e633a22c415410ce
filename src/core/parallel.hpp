// Parallel loops over image tiles and index ranges (TBB), with a thread-count limit.
#pragma once
#include <functional>

namespace imx {

struct TileRect {
  int x0, y0, x1, y1;  // pixels [x0, x1) x [y0, y1)
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

// The most worker threads a caller may ask for: far above any core count here, far below what
// makes TBB's arena fail (2^31 - 1 crashed inside TBB).
inline constexpr int kMaxThreads = 1024;

// Number of threads `requested` resolves to (0 or less = all cores); throws imx::Error above
// kMaxThreads.
int resolve_thread_count(int requested);

// Calls fn(tile, tile_index) for every tile of a width x height image, in parallel on up to
// `threads` threads (0 = all). Tiles are disjoint, so results do not depend on the schedule.
// `progress(done, total)` is called after each tile, serialized.
void for_each_tile(int width, int height, int tile_size, int threads,
                   const std::function<void(const TileRect&, int)>& fn,
                   const std::function<void(int, int)>& progress = {});

// Calls fn(begin, end) over sub-ranges of [0, count) in parallel on up to `threads` threads.
void parallel_for(long count, int threads, const std::function<void(long, long)>& fn);

}  // namespace imx
