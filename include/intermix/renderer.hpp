// Renderer: renders frame after frame, keeping each object's own slab array so an edit re-renders
// only that object (zslab methods; other methods render as render() does).
#pragma once
#include <cstdint>
#include <memory>

#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

struct RendererStats {
  int stages = 0;                       // pipeline stages of the last frame (0: not staged)
  int stages_run = 0;                   // of them, how many rendered their object again
  double stream_bytes_per_pixel = 0.0;  // tile-local stage buffers, per pixel of a tile
  double kept_bytes_per_pixel = 0.0;    // slab arrays kept for the next frame (both methods)
  int stages_merged = 0;                // deferred stages merged again (kept or new arrays)
  bool recast_unchanged = false;        // zslab-hybrid re-cast its last volume though unchanged
};

class Renderer {
 public:
  // Kept slab arrays are bounded by this many bytes unless set_kept_budget says otherwise.
  static constexpr uint64_t kDefaultKeptBudget = uint64_t{512} << 20;

  Renderer();
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // Renders like imx::render(), with the same bytes. With a zslab method, each deferred object's
  // own slab array (peeled surfaces, or a volume's folded slabs) is kept, keyed by a hash of the
  // camera, the settings and that object only: after changing one object's transfer function,
  // window/level or material, only that object is rendered again, and the kernel merges from
  // its stage on run again (zslab-hybrid also re-casts its last volume: recast_unchanged says
  // when a viewer would have been faster with zslab). Data (voxels, meshes) are recognised by
  // identity: keep the same shared_ptrs. Both zslab methods keep their arrays side by side.
  Image render(const Scene& scene, const RenderOptions& options = {});

  const RendererStats& last_stats() const;
  // Bytes the kept arrays of both zslab methods may take together; the largest arrays are
  // evicted first (and recomputed when needed). 0 keeps nothing.
  void set_kept_budget(uint64_t bytes);
  uint64_t kept_budget() const;
  // Drops every kept array.
  void clear();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace imx
