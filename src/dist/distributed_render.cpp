#include "dist/distributed_render.hpp"

#if IMX_HAVE_MPI

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <new>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <mutex>

#include "core/process_usage.hpp"
#include "core/progress_bar.hpp"
#include "dist/rank_scene.hpp"
#include "dist/slab_message.hpp"
#include "dist/swap_schedule.hpp"
#include "dist_mpi/mpi_plugin_abi.h"
#include "intermix/error.hpp"
#include "intermix/image.hpp"
#include "intermix/io.hpp"
#include "io/registry/plugin_loader.hpp"
#include "io/streams/atomic_file.hpp"
#include "methods/method_table.hpp"
#include "methods/zslab/zslab.hpp"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_MPI_PLUGIN_BUILT
#define IMX_MPI_PLUGIN_BUILT ""
#endif
#ifndef IMX_MPI_PLUGIN_INSTALLED
#define IMX_MPI_PLUGIN_INSTALLED ""
#endif
#ifndef IMX_MPI_PLUGIN_FROM_BINDIR
#define IMX_MPI_PLUGIN_FROM_BINDIR ""
#endif

namespace imx {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Open MPI is a plugin (src/dist_mpi/, libimx_mpi.so) opened when a distributed frame starts:
// start-up loads none of its libraries. RTLD_GLOBAL: Open MPI opens components of its own that
// look for its symbols in the global scope.
constexpr detail::PluginPlace kMpiPlugin{"an intermix MPI plugin",   "IMX_MPI_PLUGIN",
                                         IMX_MPI_PLUGIN_FROM_BINDIR, IMX_MPI_PLUGIN_INSTALLED,
                                         IMX_MPI_PLUGIN_BUILT,       IMX_MPI_PLUGIN_ABI_SYMBOL,
                                         IMX_MPI_PLUGIN_ABI_VERSION, true};

const imx_mpi_calls* loaded_mpi = nullptr;  // set once, by the first MpiSession

// The plugin's calls, loaded once per process; throws imx::Error naming the paths tried.
const imx_mpi_calls& load_mpi() {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  if (loaded_mpi != nullptr) return *loaded_mpi;
  std::string tried;
  if (void* handle = detail::open_plugin(kMpiPlugin, tried)) {
    auto calls = reinterpret_cast<imx_mpi_plugin_calls_fn>(
        detail::plugin_symbol(handle, IMX_MPI_PLUGIN_CALLS_SYMBOL));
    if (calls != nullptr && (loaded_mpi = calls()) != nullptr) return *loaded_mpi;
    tried = "a plugin without " IMX_MPI_PLUGIN_CALLS_SYMBOL;
  }
  throw Error(
      fmt::format("--distributed needs the MPI plugin, which cannot be loaded (tried: {}); set "
                  "IMX_MPI_PLUGIN to the path of libimx_mpi.so",
                  tried));
}

// The calls, once an MpiSession has loaded them (every call below is made within one).
const imx_mpi_calls& mpi_calls() {
  return *loaded_mpi;
}

// MPI for the lifetime of one distributed frame. MPI calls come from the main thread only; the
// renderer's TBB workers never make any.
class MpiSession {
 public:
  MpiSession() {
    int32_t owner = 0;
    load_mpi().init(&rank, &size, &node_ranks, &owner);
    owner_ = owner != 0;
  }
  ~MpiSession() {
    if (owner_) mpi_calls().finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank = 0, size = 1, node_ranks = 1;

 private:
  bool owner_ = false;
};

std::string message_of(std::exception_ptr e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::bad_alloc&) {
    return "out of memory";
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "unknown failure";
  }
}

// A failure every rank knows of, and throws at the same point.
struct AgreedFailure : Error {
  using Error::Error;
};

// Runs `fn` on every rank. When it fails on any, every rank throws the same AgreedFailure: the
// message of the lowest failing rank. A collective, so every rank must call it in turn.
template <class Fn>
void agreed(const MpiSession& mpi, Fn&& fn) {
  std::string failure;
  int failed = mpi.size;
  try {
    fn();
  } catch (...) {
    failure = message_of(std::current_exception());
    failed = mpi.rank;
  }
  int first = mpi.size;
  mpi_calls().allreduce_min_int(&failed, &first);
  if (first == mpi.size) return;
  int length = static_cast<int>(std::min<size_t>(failure.size(), 4096));
  mpi_calls().bcast(&length, 1, IMX_MPI_INT, first);
  failure.resize(static_cast<size_t>(length));
  mpi_calls().bcast(failure.data(), length, IMX_MPI_CHAR, first);
  throw AgreedFailure(fmt::format("rank {} of {}: {}", first, mpi.size, failure));
}

// Messages over 1 GiB go in pieces: MPI counts are ints.
constexpr size_t kPiece = size_t{1} << 30;

void send_bytes(const std::vector<std::byte>& data, int to) {
  uint64_t size = data.size();
  mpi_calls().send(&size, 1, IMX_MPI_UINT64, to, 0);
  for (size_t at = 0; at < data.size(); at += kPiece)
    mpi_calls().send(data.data() + at, static_cast<int>(std::min(kPiece, data.size() - at)),
                     IMX_MPI_BYTE, to, 1);
}

// Refuses an announced size above `limit` before allocating it.
void check_announced(uint64_t size, size_t limit, int from) {
  if (size > limit)
    throw Error(fmt::format("distributed: rank {} announced a {}-byte message, at most {} expected",
                            from, size, limit));
}

std::vector<std::byte> receive_bytes(int from, size_t limit) {
  uint64_t size = 0;
  mpi_calls().recv(&size, 1, IMX_MPI_UINT64, from, 0);
  check_announced(size, limit, from);
  std::vector<std::byte> data(size);
  for (size_t at = 0; at < data.size(); at += kPiece)
    mpi_calls().recv(data.data() + at, static_cast<int>(std::min(kPiece, data.size() - at)),
                     IMX_MPI_BYTE, from, 1);
  return data;
}

// Both partners send and receive at once (sizes first), so neither waits on the other's send.
std::vector<std::byte> exchange_bytes(const std::vector<std::byte>& out, int partner,
                                      size_t limit) {
  uint64_t size_out = out.size(), size_in = 0;
  mpi_calls().sendrecv(&size_out, 1, &size_in, 1, IMX_MPI_UINT64, partner, 2);
  check_announced(size_in, limit, partner);
  std::vector<std::byte> in(size_in);
  for (size_t at = 0; at < std::max(out.size(), in.size()); at += kPiece) {
    int n_out = static_cast<int>(at < out.size() ? std::min(kPiece, out.size() - at) : 0);
    int n_in = static_cast<int>(at < in.size() ? std::min(kPiece, in.size() - at) : 0);
    mpi_calls().sendrecv(out.data() + std::min(at, out.size()), n_out,
                         in.data() + std::min(at, in.size()), n_in, IMX_MPI_BYTE, partner, 3);
  }
  return in;
}

// What one rank measured, gathered on rank 0 as doubles.
struct RankStats {
  double load_s = 0, render_s = 0, composite_s = 0, peak_rss = 0, voxels = 0, slab_bytes = 0;
  // Where compositing's time goes: encoding messages, exchanging them (waiting included),
  // merging received arrays, resolving and gathering the final pixels.
  double encode_s = 0, exchange_s = 0, merge_s = 0, gather_s = 0;
  double encode_cpu_s = 0, merge_cpu_s = 0;  // the CPU time of encoding and merging
  std::vector<double> sent;  // bytes sent per exchange step: the fold, then each swap round
};

constexpr size_t kStatFields = 12;  // the doubles of RankStats before `sent`

std::vector<double> flatten(const RankStats& s, size_t steps) {
  std::vector<double> v{s.load_s,  s.render_s,   s.composite_s,  s.peak_rss,
                        s.voxels,  s.slab_bytes, s.encode_s,     s.exchange_s,
                        s.merge_s, s.gather_s,   s.encode_cpu_s, s.merge_cpu_s};
  v.resize(kStatFields + steps, 0.0);
  std::copy(s.sent.begin(), s.sent.end(), v.begin() + kStatFields);
  return v;
}

// The frame's composite: binary swap, then the final pixels gathered on rank 0 (empty
// elsewhere). `stats.sent` gets the bytes of each step.
std::vector<glm::vec4> composite(const MpiSession& mpi, ZtBuffer& arrays, size_t pixels, int spp,
                                 const Scene& scene, int threads, RankStats& stats) {
  const ZslabParams params = zslab_params(scene.render);
  const SwapSchedule plan = binary_swap(mpi.size, mpi.rank, pixels);
  const PixelRange all{0, pixels};
  stats.sent.assign(1 + plan.rounds.size(), 0.0);
  Clock::time_point t = Clock::now();
  double cpu = process_cpu_seconds();
  // Ends a phase: its wall time into `wall`, its CPU time into `cpu_into` when given.
  auto lap = [&t, &cpu](double& wall, double* cpu_into = nullptr) {
    Clock::time_point now = Clock::now();
    const double cpu_now = process_cpu_seconds();
    wall += std::chrono::duration<double>(now - t).count();
    if (cpu_into) *cpu_into += cpu_now - cpu;
    t = now;
    cpu = cpu_now;
  };
  if (plan.fold_to >= 0) {
    std::vector<std::byte> message = encode_slab_message(arrays, all, spp, threads);
    stats.sent[0] = static_cast<double>(message.size());
    lap(stats.encode_s, &stats.encode_cpu_s);
    send_bytes(message, plan.fold_to);
    lap(stats.exchange_s);
  }
  if (plan.fold_from >= 0) {
    std::vector<std::byte> in =
        receive_bytes(plan.fold_from, max_slab_message_bytes(arrays, all, spp));
    lap(stats.exchange_s);
    merge_slab_message(arrays, all, spp, in, true, params.mix, threads);
    lap(stats.merge_s, &stats.merge_cpu_s);
  }
  for (size_t k = 0; k < plan.rounds.size(); ++k) {
    const SwapRound& r = plan.rounds[k];
    std::vector<std::byte> message = encode_slab_message(arrays, r.send, spp, threads);
    stats.sent[k + 1] = static_cast<double>(message.size());
    lap(stats.encode_s, &stats.encode_cpu_s);
    std::vector<std::byte> in =
        exchange_bytes(message, r.partner, max_slab_message_bytes(arrays, r.keep, spp));
    message = {};
    lap(stats.exchange_s);
    merge_slab_message(arrays, r.keep, spp, in, r.first, params.mix, threads);
    lap(stats.merge_s, &stats.merge_cpu_s);
  }
  std::vector<glm::vec4> mine;
  if (plan.fold_to < 0)
    mine = resolve_slab_arrays(arrays, plan.result, spp, params.mix.a_ert, scene.image.background,
                               threads);
  // Gather: rank 0 knows every rank's range from the schedule.
  std::vector<int> counts(static_cast<size_t>(mpi.size)), displs(static_cast<size_t>(mpi.size));
  for (int r = 0; r < mpi.size; ++r) {
    SwapSchedule s = binary_swap(mpi.size, r, pixels);
    counts[r] = static_cast<int>(s.result.size() * 4);
    displs[r] = static_cast<int>(s.result.first * 4);
  }
  std::vector<glm::vec4> image(mpi.rank == 0 ? pixels : 0);
  mpi_calls().gatherv(mine.data(), static_cast<int>(mine.size() * 4), image.data(), counts.data(),
                      displs.data(), IMX_MPI_FLOAT, 0);
  lap(stats.gather_s);
  return image;
}

nlohmann::json report_json(const DistributedRequest& request, const Partition& partition,
                           const Scene& outline, const std::vector<double>& gathered, size_t row,
                           size_t pixels, int spp, double total_s) {
  const size_t ranks = partition.ranks.size();
  nlohmann::json j;
  j["scene"] = request.scene.string();
  j["ranks"] = ranks;
  j["partition"] = partition_mode_name(partition.mode);
  j["image"] = {{"width", outline.image.width}, {"height", outline.image.height}, {"spp", spp}};
  j["layers"] = outline.render.layers;
  j["slab_format"] = outline.render.slab_format;
  double composite_s = 0.0;
  for (size_t r = 0; r < ranks; ++r) {
    const double* v = gathered.data() + r * row;
    composite_s = std::max(composite_s, v[2]);
    j["per_rank"].push_back({{"part", partition.describe(outline, static_cast<int>(r))},
                             {"load_s", v[0]},
                             {"render_s", v[1]},
                             {"composite_s", v[2]},
                             {"peak_rss_bytes", v[3]},
                             {"voxels", v[4]},
                             {"slab_array_bytes", v[5]},
                             {"encode_s", v[6]},
                             {"exchange_s", v[7]},
                             {"merge_s", v[8]},
                             {"resolve_gather_s", v[9]},
                             {"encode_cpu_s", v[10]},
                             {"merge_cpu_s", v[11]}});
  }
  // Steps: the fold (ranks past the largest power of two), then each binary-swap round.
  for (size_t step = 0; step + kStatFields < row; ++step) {
    double total = 0.0, most = 0.0;
    for (size_t r = 0; r < ranks; ++r) {
      total += gathered[r * row + kStatFields + step];
      most = std::max(most, gathered[r * row + kStatFields + step]);
    }
    if (step == 0 && swap_group(static_cast<int>(ranks)) == static_cast<int>(ranks)) continue;
    j["rounds"].push_back({{"step", step == 0 ? "fold" : fmt::format("swap {}", step)},
                           {"bytes", total},
                           {"bytes_per_pixel", total / static_cast<double>(pixels)},
                           {"max_bytes_one_rank", most}});
  }
  j["gather_bytes"] = static_cast<double>(pixels) * 16.0;
  if (!j.contains("rounds")) j["rounds"] = nlohmann::json::array();
  j["composite_s"] = composite_s;
  j["total_s"] = total_s;
  return j;
}

void render_frame(const MpiSession& mpi, const DistributedRequest& request) {
  const Clock::time_point start = Clock::now();
  const int threads =
      request.threads > 0
          ? request.threads
          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / mpi.node_ranks);
  RankStats stats;

  // 1. The scene's outline: every object, volumes from their headers (one voxel read), and
  // the same partition planned on every rank.
  Scene outline;
  Partition partition;
  agreed(mpi, [&] {
    const MethodInfo* method = find_method(request.method);
    if (!request.method.empty() && !(method && method->distributable))
      throw Error(
          fmt::format("--distributed composites zSlab arrays: --method is '{}', expected zslab",
                      request.method));
    outline =
        load_scene(request.scene, request.overrides, [](const std::string&, const VolumeHeader&) {
          return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
        });
    partition = plan_partition(outline, mpi.size, request.partition);
  });
  const int spp = request.spp > 0 ? request.spp : std::max(outline.render.spp, 1);
  const size_t pixels = static_cast<size_t>(outline.image.width) * outline.image.height;
  if (mpi.rank == 0)
    std::fprintf(stderr, "distributed: %d ranks, partition %s, %d thread(s) each\n", mpi.size,
                 partition_mode_name(partition.mode), threads);

  // 2. This rank's part, reading only its bricks; 3. rendered into slab arrays.
  ZtBuffer arrays;
  agreed(mpi, [&] {
    Clock::time_point t = Clock::now();
    Scene part = rank_scene(
        load_scene(request.scene, request.overrides, rank_regions(partition, mpi.rank, outline)),
        partition, mpi.rank);
    stats.load_s = seconds_since(t);
    for (const VolumeObject& v : part.volumes)
      stats.voxels += static_cast<double>(v.data->voxel_count());
    t = Clock::now();
    RenderOptions options;
    options.threads = threads;
    ProgressBar bar(fmt::format("render (rank 0 of {})", mpi.size),
                    request.progress && mpi.rank == 0);
    options.progress = [&bar](double f) { bar.update(f); };
    render_zslab_arrays(part, spp, options, arrays);
    bar.finish();
    stats.render_s = seconds_since(t);
    stats.slab_bytes = static_cast<double>(arrays.bytes());
  });

  // 4. Compositing. A failure here (out of memory mid-exchange) cannot be agreed on while a
  // partner waits in a send, so it ends the job.
  std::vector<glm::vec4> pixels_rgba;
  mpi_calls().barrier();
  Clock::time_point t = Clock::now();
  try {
    pixels_rgba = composite(mpi, arrays, pixels, spp, outline, threads, stats);
  } catch (...) {
    std::fprintf(stderr, "error: rank %d of %d: compositing failed: %s\n", mpi.rank, mpi.size,
                 message_of(std::current_exception()).c_str());
    mpi_calls().abort(1);
  }
  stats.composite_s = seconds_since(t);
  arrays = ZtBuffer();
  stats.peak_rss = peak_resident_bytes();

  const size_t steps =
      1 + static_cast<size_t>(std::countr_zero(static_cast<unsigned>(swap_group(mpi.size))));
  std::vector<double> mine = flatten(stats, steps);
  std::vector<double> gathered(mpi.rank == 0 ? mine.size() * mpi.size : 0);
  mpi_calls().gather(mine.data(), static_cast<int>(mine.size()), gathered.data(), IMX_MPI_DOUBLE,
                     0);

  // 5. Rank 0 writes the image (and the report); the others learn whether it could.
  agreed(mpi, [&] {
    if (mpi.rank != 0) return;
    Image image(outline.image.width, outline.image.height);
    for (size_t p = 0; p < pixels; ++p)
      image.at(static_cast<int>(p % outline.image.width),
               static_cast<int>(p / outline.image.width)) = pixels_rgba[p];
    write_png(image, request.output, request.linear);
    nlohmann::json report = report_json(request, partition, outline, gathered, mine.size(), pixels,
                                        spp, seconds_since(start));
    double most_rss = 0.0;
    for (const nlohmann::json& r : report["per_rank"])
      most_rss = std::max(most_rss, r["peak_rss_bytes"].get<double>());
    double bytes = 0.0;
    for (const nlohmann::json& r : report["rounds"]) bytes += r["bytes"].get<double>();
    std::fprintf(stderr,
                 "distributed: compositing %.1f ms, %.2f bytes/pixel exchanged in %zu step(s), "
                 "peak memory %.0f MiB (largest rank)\n",
                 report["composite_s"].get<double>() * 1e3, bytes / static_cast<double>(pixels),
                 report["rounds"].size(), most_rss / (1 << 20));
    if (!request.report.empty())
      write_file_atomically(request.report,
                            [&](std::ostream& out) { out << report.dump(2) << "\n"; });
  });
}

}  // namespace

bool distributed_available(std::string*) {
  return true;
}

int render_distributed(const DistributedRequest& request,
                       const std::function<void(const std::string&)>& print_error) {
  MpiSession mpi;
  try {
    render_frame(mpi, request);
    return 0;
  } catch (const AgreedFailure& e) {
    // Every rank says it before any exits: mpirun ends the job at the first non-zero exit.
    print_error(e.what());
    std::fflush(stderr);
    mpi_calls().barrier();
    return 1;
  } catch (...) {  // this rank alone: the others may wait on it in a collective
    print_error(
        fmt::format("rank {} of {}: {}", mpi.rank, mpi.size, message_of(std::current_exception())));
    std::fflush(stderr);
    mpi_calls().abort(1);
    return 1;
  }
}

}  // namespace imx

#else  // built without MPI

#include "intermix/error.hpp"

namespace imx {

namespace {
constexpr const char* kNoMpi =
    "this intermix was built without MPI (libopenmpi-dev was not found when it was configured); "
    "install it with scripts/install-deps and build again to use --distributed";
}

bool distributed_available(std::string* why) {
  if (why) *why = kNoMpi;
  return false;
}

int render_distributed(const DistributedRequest&, const std::function<void(const std::string&)>&) {
  throw Error(kNoMpi);
}

}  // namespace imx

#endif
