#include "core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "intermix/error.hpp"

namespace imx {

int resolve_thread_count(int requested) {
  if (requested > kMaxThreads)
    throw Error(
        fmt::format("threads {} is more than the {} this build allows", requested, kMaxThreads));
  int cores = std::max(1, tbb::info::default_concurrency());
  return requested <= 0 ? cores : requested;
}

void for_each_tile(int width, int height, int tile_size, int threads,
                   const std::function<void(const TileRect&, int)>& fn,
                   const std::function<void(int, int)>& progress) {
  int tiles_x = (width + tile_size - 1) / tile_size;
  int tiles_y = (height + tile_size - 1) / tile_size;
  int total = tiles_x * tiles_y;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  tbb::task_arena arena(resolve_thread_count(threads));
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, total, 1),
        [&](const tbb::blocked_range<int>& r) {
          for (int t = r.begin(); t != r.end(); ++t) {
            int tx = t % tiles_x, ty = t / tiles_x;
            TileRect rect{tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
                          std::min(height, (ty + 1) * tile_size)};
            fn(rect, t);
            int finished = ++done;
            if (progress) {
              std::lock_guard lock(progress_mutex);
              progress(finished, total);
            }
          }
        },
        tbb::simple_partitioner());
  });
}

void parallel_for(long count, int threads, const std::function<void(long, long)>& fn) {
  tbb::task_arena arena(resolve_thread_count(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<long>(0, count),
                      [&](const tbb::blocked_range<long>& r) { fn(r.begin(), r.end()); });
  });
}

}  // namespace imx
