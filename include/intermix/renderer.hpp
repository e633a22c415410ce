// Renderer: renders frame after frame, keeping stage outputs so an edit re-runs only what it
// affects (zslab methods; other methods render as render() does).
#pragma once
#include <memory>

#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

struct RendererStats {
  int stages = 0;                       // pipeline stages of the last frame (0: not staged)
  int stages_run = 0;                   // of them, how many ran; the others were reused
  double stream_bytes_per_pixel = 0.0;  // tile-local stage buffers, per pixel of a tile
  double kept_bytes_per_pixel = 0.0;    // whole-frame stage outputs kept for the next frame
};

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // Renders like imx::render(). With a zslab method, each stage's output is kept keyed by a hash
  // of what it read (camera, settings, its objects and every earlier stage): after changing one
  // object's transfer function, window/level or material, only the stages from that object on
  // run again. Data (voxels, meshes) are recognised by identity: keep the same shared_ptrs.
  Image render(const Scene& scene, const RenderOptions& options = {});

  const RendererStats& last_stats() const;
  // Drops every kept output.
  void clear();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace imx
