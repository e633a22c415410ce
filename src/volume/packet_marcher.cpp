#include "volume/packet_marcher.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>

#include "volume/label_classifier.hpp"
#include "volume/lane_bricks.hpp"
#include "volume/lane_grid.hpp"
#include "volume/lane_kernel.hpp"
#include "volume/lanes.hpp"
#include "volume/ray_shading.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {
namespace {

// The reference: one VolumeMarcher per ray.
void composite_each(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                    std::span<const ShadingLight> lights, float ert, std::span<glm::vec4> out,
                    SlabExtent extent) {
  for (size_t i = 0; i < rays.size(); ++i) {
    glm::vec4 acc(0.0f);
    VolumeMarcher m(v, rays[i].ray, rays[i].t0, rays[i].t1, step, lights, extent);
    m.composite(acc, ert);
    out[i] = acc;
  }
}

#if IMX_PACKET_LANES

using namespace lanes;
constexpr int kMaxLights = RayShading::kMaxLights;
constexpr int kMaxLookDelay = 4;  // steps a lane that left its occupied brick may march on

// GradientVolume::sample in lanes. Packed layout: one 32-bit gather per corner, the fields
// split by shifts. Int16 layout: two per corner, (x, y) and (z, next voxel's x); the volume's
// spare entry keeps the last voxel's second word inside.
class LaneGradients {
 public:
  explicit LaneGradients(const GradientVolume& g)
      : words_(g.words()),
        int16_(g.data()),
        packed_(g.packed()),
        lattice_(g.dims()),
        scale_(splat(g.scale())) {}

  void sample(__m256 px, __m256 py, __m256 pz, __m256& gx, __m256& gy, __m256& gz) const {
    __m256 fx, fy, fz;
    const __m256i base = lattice_.locate(px, py, pz, fx, fy, fz);
    const __m256i sy = lattice_.sy(), sz = lattice_.sz();
    const __m256i one = splat(1);
    const __m256i corner[8] = {
        base,
        _mm256_add_epi32(base, one),
        _mm256_add_epi32(base, sy),
        _mm256_add_epi32(_mm256_add_epi32(base, sy), one),
        _mm256_add_epi32(base, sz),
        _mm256_add_epi32(_mm256_add_epi32(base, sz), one),
        _mm256_add_epi32(_mm256_add_epi32(base, sz), sy),
        _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(base, sz), sy), one)};
    __m256 cx[8], cy[8], cz[8];
    if (packed_) {
      for (int c = 0; c < 8; ++c) {
        const __m256i w = gather_words<4>(words_, corner[c]);
        cx[c] = _mm256_cvtepi32_ps(_mm256_srai_epi32(_mm256_slli_epi32(w, 22), 22));
        cy[c] = _mm256_cvtepi32_ps(_mm256_srai_epi32(_mm256_slli_epi32(w, 12), 22));
        cz[c] = _mm256_cvtepi32_ps(_mm256_srai_epi32(_mm256_slli_epi32(w, 2), 22));
      }
    } else {
      // The x-neighbours c and c + 1 are 12 adjacent bytes: per lane one 16-byte load (the
      // volume's spare entries keep the last pair's inside), lanes l and l + 4 in one register,
      // then a transpose, instead of three 8-lane gathers (bench/lane_fetch_bench.cpp).
      alignas(32) int32_t at[4][kLanes];
      for (int k = 0; k < 4; ++k)
        _mm256_store_si256(reinterpret_cast<__m256i*>(at[k]), corner[2 * k]);
      auto pair = [this](int32_t voxel) {
        return _mm_loadu_si128(reinterpret_cast<const __m128i*>(int16_ + 3 * size_t(voxel)));
      };
      // Component q (of x0 y0 z0 x1 y1 z1) of the eight lanes, from the 64-bit half `half` of
      // each 128-bit part of b, where b holds components 2 * (q / 2) and 2 * (q / 2) + 1.
      auto component = [](__m256i b, int half) {
        const __m256i q =
            half ? _mm256_permute4x64_epi64(b, 0x0d) : _mm256_permute4x64_epi64(b, 0x08);
        return _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_castsi256_si128(q)));
      };
      for (int k = 0; k < 4; ++k) {
        __m256i r[4];
        for (int l = 0; l < 4; ++l)
          r[l] = _mm256_inserti128_si256(_mm256_castsi128_si256(pair(at[k][l])), pair(at[k][l + 4]),
                                         1);
        const __m256i a0 = _mm256_unpacklo_epi16(r[0], r[1]),
                      a1 = _mm256_unpackhi_epi16(r[0], r[1]);
        const __m256i a2 = _mm256_unpacklo_epi16(r[2], r[3]),
                      a3 = _mm256_unpackhi_epi16(r[2], r[3]);
        const __m256i b0 = _mm256_unpacklo_epi32(a0, a2);  // x0, y0 of lanes 0-3 | 4-7
        const __m256i b1 = _mm256_unpackhi_epi32(a0, a2);  // z0, x1
        const __m256i b2 = _mm256_unpacklo_epi32(a1, a3);  // y1, z1
        const int c = 2 * k;
        cx[c] = component(b0, 0), cy[c] = component(b0, 1), cz[c] = component(b1, 0);
        cx[c + 1] = component(b1, 1), cy[c + 1] = component(b2, 0), cz[c + 1] = component(b2, 1);
      }
    }
    auto trilinear = [&](const __m256* v) {
      __m256 c00 = lerp(v[0], v[1], fx), c10 = lerp(v[2], v[3], fx);
      __m256 c01 = lerp(v[4], v[5], fx), c11 = lerp(v[6], v[7], fx);
      return _mm256_mul_ps(lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz), scale_);
    };
    gx = trilinear(cx), gy = trilinear(cy), gz = trilinear(cz);
  }

 private:
  const uint32_t* words_;
  const int16_t* int16_;
  bool packed_;
  LaneLattice lattice_;
  __m256 scale_;
};

// The labels of the eight voxels around points in lanes (c000, c100, c010, c110, c001, c101,
// c011, c111, as label_of() reads them), with LaneGrid's clamp and gathers: 8- and 16-bit
// voxels as 32-bit words holding the x-neighbours together.
template <class T>
class LaneLabelCells {
 public:
  explicit LaneLabelCells(const VoxelGrid<T>& g)
      : data_(g.data),
        lattice_(g.dims),
        last_word_(splat(g.dims.x * g.dims.y * g.dims.z - 4)),
        hi2_x_(splat(static_cast<float>(g.dims.x - 2))),
        hi2_y_(splat(static_cast<float>(g.dims.y - 2))),
        hi2_z_(splat(static_cast<float>(g.dims.z - 2))),
        safe_(splat(1 + g.dims.x + g.dims.x * g.dims.y)) {}

  void cell(__m256 px, __m256 py, __m256 pz, __m256i c[8], __m256& fx, __m256& fy,
            __m256& fz) const {
    const __m256i base = lattice_.locate(px, py, pz, fx, fy, fz);
    const __m256i sy = lattice_.sy(), sz = lattice_.sz();
    const __m256i o01 = _mm256_add_epi32(base, sy), o10 = _mm256_add_epi32(base, sz);
    const __m256i offs[4] = {base, o01, o10, _mm256_add_epi32(o01, sz)};
    if constexpr (std::is_same_v<T, float>) {
      for (int k = 0; k < 4; ++k) {
        c[2 * k] = _mm256_cvttps_epi32(gather_floats(data_, offs[k]));
        c[2 * k + 1] =
            _mm256_cvttps_epi32(gather_floats(data_, _mm256_add_epi32(offs[k], splat(1))));
      }
    } else if constexpr (sizeof(T) == 1) {
      for (int k = 0; k < 4; ++k) {
        // Only the last pair can lie within the last 3 bytes (as LaneGrid).
        const __m256i at = k == 3 ? _mm256_min_epi32(offs[k], last_word_) : offs[k];
        const __m256i shift = _mm256_slli_epi32(_mm256_sub_epi32(offs[k], at), 3);
        const __m256i w = _mm256_srlv_epi32(gather_words<1>(data_, at), shift);
        c[2 * k] = _mm256_and_si256(w, splat(0xff));
        c[2 * k + 1] = _mm256_and_si256(_mm256_srli_epi32(w, 8), splat(0xff));
      }
    } else {
      for (int k = 0; k < 4; ++k) {
        const __m256i w = gather_words<2>(data_, offs[k]);
        if constexpr (std::is_signed_v<T>) {
          c[2 * k] = _mm256_srai_epi32(_mm256_slli_epi32(w, 16), 16);
          c[2 * k + 1] = _mm256_srai_epi32(w, 16);
        } else {
          c[2 * k] = _mm256_and_si256(w, splat(0xffff));
          c[2 * k + 1] = _mm256_srli_epi32(w, 16);
        }
      }
    }
  }

  // label_gradient in lanes for 8-bit labels where every lane of `vis` lies at least a voxel
  // inside the grid (p in [1, dims - 2) on every axis), so that no fetch is clamped: the six
  // indicator cells around p read 12 rows of four x-neighbours (x0 - 1 .. x0 + 2), one 32-bit
  // gather each, instead of 24 gathers. False (nothing computed) elsewhere or for other types.
  bool interior_gradient(__m256 vis, __m256 px, __m256 py, __m256 pz, __m256i label, __m256& gx,
                         __m256& gy, __m256& gz) const {
    if constexpr (sizeof(T) != 1) {
      (void)vis, (void)px, (void)py, (void)pz, (void)label, (void)gx, (void)gy, (void)gz;
      return false;
    } else {
      const __m256 one = splat(1.0f);
      const __m256 inside = _mm256_and_ps(
          _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(px, one, _CMP_GE_OQ),
                                      _mm256_cmp_ps(px, hi2_x_, _CMP_LT_OQ)),
                        _mm256_and_ps(_mm256_cmp_ps(py, one, _CMP_GE_OQ),
                                      _mm256_cmp_ps(py, hi2_y_, _CMP_LT_OQ))),
          _mm256_and_ps(_mm256_cmp_ps(pz, one, _CMP_GE_OQ), _mm256_cmp_ps(pz, hi2_z_, _CMP_LT_OQ)));
      const int v = _mm256_movemask_ps(vis);
      if ((_mm256_movemask_ps(inside) & v) != v) return false;
      __m256 fx, fy, fz;
      __m256i base = lattice_.locate(px, py, pz, fx, fy, fz);
      // Lanes not shaded read a safe interior row instead.
      base = _mm256_blendv_epi8(safe_, base, _mm256_castps_si256(inside));
      const __m256i at = _mm256_sub_epi32(base, splat(1));
      const __m256i sy = lattice_.sy(), sz = lattice_.sz();
      // The label in every byte: a byte compare then flags the voxels that hold it.
      const __m256i pattern = _mm256_mullo_epi32(label, splat(0x01010101));
      auto row = [&](int dy, int dz) {
        const __m256i o = _mm256_add_epi32(at, _mm256_add_epi32(_mm256_mullo_epi32(sy, splat(dy)),
                                                                _mm256_mullo_epi32(sz, splat(dz))));
        return _mm256_cmpeq_epi8(gather_words<1>(data_, o), pattern);
      };
      // Voxel x0 - 1 + k of a row as 0 or 1.
      auto is = [](__m256i eq, int k) {
        return _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(eq, 8 * k), splat(1)));
      };
      // The indicator of a cell from its four rows (y, z order) and its first x byte.
      auto cell = [&](__m256i r00, __m256i r10, __m256i r01, __m256i r11, int k) {
        const __m256 c00 = lerp(is(r00, k), is(r00, k + 1), fx);
        const __m256 c10 = lerp(is(r10, k), is(r10, k + 1), fx);
        const __m256 c01 = lerp(is(r01, k), is(r01, k + 1), fx);
        const __m256 c11 = lerp(is(r11, k), is(r11, k + 1), fx);
        return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
      };
      const __m256i r00 = row(0, 0), r10 = row(1, 0), r01 = row(0, 1), r11 = row(1, 1);
      const __m256i ym0 = row(-1, 0), ym1 = row(-1, 1), yp0 = row(2, 0), yp1 = row(2, 1);
      const __m256i zm0 = row(0, -1), zm1 = row(1, -1), zp0 = row(0, 2), zp1 = row(1, 2);
      const __m256 half = splat(0.5f);
      gx = _mm256_mul_ps(half,
                         _mm256_sub_ps(cell(r00, r10, r01, r11, 2), cell(r00, r10, r01, r11, 0)));
      gy = _mm256_mul_ps(half,
                         _mm256_sub_ps(cell(r10, yp0, r11, yp1, 1), cell(ym0, r00, ym1, r01, 1)));
      gz = _mm256_mul_ps(half,
                         _mm256_sub_ps(cell(r01, r11, zp0, zp1, 1), cell(zm0, zm1, r00, r10, 1)));
      return true;
    }
  }

  // label_indicator in lanes: the trilinear interpolation of (voxel == label).
  __m256 indicator(__m256 px, __m256 py, __m256 pz, __m256i label) const {
    __m256i c[8];
    __m256 fx, fy, fz;
    cell(px, py, pz, c, fx, fy, fz);
    __m256 is[8];
    for (int k = 0; k < 8; ++k)
      is[k] = _mm256_and_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(c[k], label)), splat(1.0f));
    const __m256 c00 = lerp(is[0], is[1], fx), c10 = lerp(is[2], is[3], fx);
    const __m256 c01 = lerp(is[4], is[5], fx), c11 = lerp(is[6], is[7], fx);
    return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
  }

 private:
  const T* data_;
  LaneLattice lattice_;
  __m256i last_word_;             // the last voxel a 32-bit word may start at (8-bit voxels)
  __m256 hi2_x_, hi2_y_, hi2_z_;  // dims - 2: interior_gradient's bound
  __m256i safe_;                  // voxel (1, 1, 1)
};

// The per-lane state, structure of arrays so that a step loads whole vectors.
struct alignas(32) Lanes {
  float ox[kLanes], oy[kLanes], oz[kLanes];  // the ray in index space, same parameter t
  float dx[kLanes], dy[kLanes], dz[kLanes];
  float front[kLanes];      // where the next piece starts
  float t1[kLanes];         // where the span ends
  float next_cell[kLanes];  // k + 1 for the grid cell [k, k + 1) * step holding `front`
  float s_front[kLanes];    // the scalar at `front`, valid where have_front is set
  int32_t have_front[kLanes];
  int32_t label_front[kLanes];   // label volumes: the winning label at `front`
  float occupied_until[kLanes];  // the lane is in an occupied brick up to here
  float r[kLanes], g[kLanes], b[kLanes], a[kLanes];
  float ex[kLanes], ey[kLanes], ez[kLanes];  // toward the eye, world space
  float lx[kMaxLights][kLanes], ly[kMaxLights][kLanes], lz[kMaxLights][kLanes];  // to the light
  float hx[kMaxLights][kLanes], hy[kMaxLights][kLanes], hz[kMaxLights][kLanes];  // half vector
  int32_t ray[kLanes];
};

// The lane k of a vector holds lane in_order()[k]: no permutation.
inline __m256i in_order() {
  return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
}

// kPackOrder[m]: the set bits of m in rising order, a nibble each from the lowest: the
// permutation that packs the lanes of mask m to the front.
constexpr std::array<uint32_t, 256> kPackOrder = [] {
  std::array<uint32_t, 256> t{};
  for (unsigned m = 0; m < 256; ++m)
    for (unsigned l = 0, n = 0; l < 8; ++l)
      if (m >> l & 1) t[m] |= l << (4 * n++);
  return t;
}();

// Visible pieces waiting to be shaded, packed (PacketKernel::defer): room for one more step's
// eight after at most seven left over.
struct alignas(32) ShadeQueue {
  enum Field { kW, kR, kG, kB, kA, kAx, kAy, kAz, kBx, kBy, kBz, kLane, kTwo, kFields };
  // kW: the weight over() gives the piece's colour; kLane (an int32 bit pattern): the lane of its
  // ray; kTwo: all ones where it is shaded at two points.
  float field[kFields][2 * kLanes] = {};
  int count = 0;
};

// One batch of rays through one volume with voxel type T; with NoData, one whose NaN or inf
// voxels are no data (only float volumes have them, and only they pay for the test).
template <class T, bool NoData = false>
class PacketKernel {
 public:
  PacketKernel(const PreparedVolume& v, const VoxelGrid<T>& grid, std::span<const PacketRay> rays,
               float step, std::span<const ShadingLight> lights, float ert,
               std::span<glm::vec4> out, SlabExtent extent, SlabSink* sink)
      : v_(v),
        grid_(grid),
        voxels_(grid),
        cells_(grid),
        rays_(rays),
        out_(out),
        lights_(lights),
        step_(step),
        ert_(ert),
        preint_(v.accel.preint ? v.accel.preint->view() : PreintegrationView()),
        sink_(sink) {
    if (v.accel.gradients) gradients_.emplace(*v.accel.gradients);
    const Shading& s = v.object->shading;
    shaded_ = s.enabled;
    centre_ = extent == SlabExtent::visible && preint_.moments;
    trim_ = extent == SlabExtent::visible && v.accel.emptiness;  // as VolumeMarcher trims
    labels_ = v.labels.active();
    nearest_ = v.labels.nearest();
    defer_ = shaded_ && !sink_ && !labels_;
    for (int k = 0; k < kAlphaCache; ++k) cached_label_[k] = k + 1;  // no label maps to slot k
    light_count_ = static_cast<int>(lights.size());
    if (v.accel.emptiness) use_runs_ = v.accel.emptiness->value_runs(run_lo_, run_hi_);
    if (v.accel.occupancy) bricks_.emplace(*v.accel.occupancy, v.accel.skip);
  }

  // Packets of eight rays in batch order, each marched until all its rays are done. Refilling
  // each lane as soon as its ray ends kept the lanes fuller but was slower (FLAIR 41 against
  // 37.5 ms, ct-head 39 against 37.5): scattered scalar set-up and incoherent lanes.
  void run() {
    for (;;) {
      unsigned live = fill();
      look_delay_ = 0;
      if (!live) return;
      const unsigned packet = live;
      while (live) {
        const unsigned lit = labels_ ? step_labels(live) : step(live);
        const __m256 active = lane_mask(live);
        __m256 ended = _mm256_or_ps(
            _mm256_cmp_ps(_mm256_load_ps(L_.front), _mm256_load_ps(L_.t1), _CMP_NLT_UQ),
            _mm256_cmp_ps(_mm256_load_ps(L_.a), splat(ert_), _CMP_NLT_UQ));
        unsigned done = static_cast<unsigned>(_mm256_movemask_ps(_mm256_and_ps(ended, active)));
        if (bricks_) {
          // Lanes that left their occupied brick look for the next one, but not at once:
          // - those whose last piece was visible are in matter and look at their next
          //   transparent piece (FLAIR 1.5 ms faster);
          // - the others keep marching until every such lane needs a look or the first has
          //   waited kMaxLookDelay steps. A walk costs the same for one lane as for eight and
          //   several times a step, and the next brick is mostly occupied anyway (ct-head and
          //   FLAIR about 7% faster than when only a lone lane waited, for one step).
          // A deferred look marches pieces a look would have skipped: they are transparent
          // unless one spans two empty bricks whose value ranges straddle a visible value, as
          // plain marching has it too (no 8-bit image here changed).
          __m256 look = _mm256_cmp_ps(_mm256_load_ps(L_.front), _mm256_load_ps(L_.occupied_until),
                                      _CMP_GE_OQ);
          const unsigned open = live & ~lit & ~done;
          const unsigned m = static_cast<unsigned>(_mm256_movemask_ps(look)) & open;
          if (m && (m == open || ++look_delay_ > kMaxLookDelay)) {
            look_delay_ = 0;
            done |= settle(m);
          }
        }
        live &= ~done;
      }
      // A ray's colour is whole once the queue holds none of its pieces.
      if (queue_.count) shade_queued(queue_.count), queue_.count = 0;
      if (!sink_)
        for (unsigned m = packet; m; m &= m - 1) {
          const int l = __builtin_ctz(m);
          out_[L_.ray[l]] = glm::vec4(L_.r[l], L_.g[l], L_.b[l], L_.a[l]);
        }
    }
  }

 private:
  // Fills the lanes with the next rays that have something to march, writing out those that do
  // not; returns the lanes filled (none once the batch is used up). An idle lane keeps computing
  // its last ray's positions, which the samplers clamp, and is masked out of everything that
  // writes.
  unsigned fill() {
    unsigned live = 0;
    while (live != kAllLanes && next_ < rays_.size()) {
      unsigned fresh = 0;
      for (int l = 0; l < kLanes && next_ < rays_.size(); ++l) {
        if (live & (1u << l)) continue;
        start(l, next_++);
        fresh |= 1u << l;
      }
      unsigned empty = 0;
      if (!(0.0f < ert_)) {
        empty = fresh;
      } else {
        const __m256 none =
            _mm256_cmp_ps(_mm256_load_ps(L_.front), _mm256_load_ps(L_.t1), _CMP_NLT_UQ);
        empty = fresh & static_cast<unsigned>(_mm256_movemask_ps(none));
        if (bricks_ && (fresh & ~empty)) {
          // The lanes' rays for the brick walk, kept until the packet is filled again.
          const float* const origin[3] = {L_.ox, L_.oy, L_.oz};
          const float* const dir[3] = {L_.dx, L_.dy, L_.dz};
          brick_rays_ = bricks_->load(origin, dir);
          empty |= settle(fresh & ~empty);
        }
      }
      if (!sink_)
        for (unsigned m = empty; m; m &= m - 1) out_[L_.ray[__builtin_ctz(m)]] = glm::vec4(0.0f);
      live |= fresh & ~empty;
    }
    return live;
  }

  // Puts ray i of the batch into lane l.
  void start(int l, size_t i) {
    const PacketRay& pr = rays_[i];
    const glm::vec3 o = v_.to_index(pr.ray.origin);
    const glm::vec3 d = glm::mat3(v_.world_to_index) * pr.ray.dir;
    L_.ox[l] = o.x, L_.oy[l] = o.y, L_.oz[l] = o.z;
    L_.dx[l] = d.x, L_.dy[l] = d.y, L_.dz[l] = d.z;
    L_.front[l] = pr.t0;
    L_.t1[l] = pr.t1;
    L_.next_cell[l] = static_cast<float>(grid_cell(pr.t0, step_) + 1.0);
    L_.have_front[l] = 0;
    L_.occupied_until[l] = -INFINITY;
    L_.r[l] = L_.g[l] = L_.b[l] = L_.a[l] = 0.0f;
    if (shaded_) {
      const glm::vec3 e = -pr.ray.dir;
      L_.ex[l] = e.x, L_.ey[l] = e.y, L_.ez[l] = e.z;
      for (int k = 0; k < light_count_; ++k) {
        // As RayShading's constructor: a light straight behind gets no half vector.
        glm::vec3 to_light = lights_[k].headlight ? e : lights_[k].to_light;
        glm::vec3 h = to_light + e;
        float len = glm::length(h);
        glm::vec3 half = len > 1e-12f ? h / len : glm::vec3(0.0f);
        L_.lx[k][l] = to_light.x, L_.ly[k][l] = to_light.y, L_.lz[k][l] = to_light.z;
        L_.hx[k][l] = half.x, L_.hy[k][l] = half.y, L_.hz[k][l] = half.z;
      }
    }
    L_.ray[l] = static_cast<int32_t>(i);
  }

  // VolumeMarcher::skip_empty for the lanes in m (fresh ones, or ones past their occupied
  // brick): each finds the next occupied brick, moves to the last grid point before it if that
  // lies beyond the piece it is in, and looks again once it leaves that brick. Returns the lanes
  // with nothing left to march.
  unsigned settle(unsigned m) {
    const __m256 front = _mm256_load_ps(L_.front), t1 = _mm256_load_ps(L_.t1);
    __m256 enter = t1, leave = _mm256_load_ps(L_.occupied_until);
    const unsigned none = bricks_->first_occupied(brick_rays_, m, front, t1, enter, leave);
    const __m256 walked = lane_mask(m & ~none);
    _mm256_store_ps(L_.occupied_until,
                    _mm256_blendv_ps(_mm256_load_ps(L_.occupied_until), leave, walked));
    // As VolumeMarcher: resume at the grid point at or before the brick, unless that is still
    // inside the current piece.
    const __m256 next_cell = _mm256_load_ps(L_.next_cell), step = splat(step_);
    const __m256 back = _mm256_min_ps(t1, _mm256_mul_ps(next_cell, step));
    const __m256 jump = _mm256_and_ps(walked, _mm256_cmp_ps(enter, back, _CMP_GE_OQ));
    if (!_mm256_movemask_ps(jump)) return none;
    const __m256 inv_step = splat(1.0f / step_);
    const __m256 to =
        _mm256_max_ps(back, _mm256_mul_ps(_mm256_floor_ps(_mm256_mul_ps(enter, inv_step)), step));
    __m256 cell = _mm256_floor_ps(_mm256_mul_ps(to, inv_step));
    const __m256 one = splat(1.0f);
    cell = _mm256_add_ps(
        cell, _mm256_and_ps(one, _mm256_cmp_ps(_mm256_mul_ps(_mm256_add_ps(cell, one), step), to,
                                               _CMP_LE_OQ)));
    _mm256_store_ps(L_.front, _mm256_blendv_ps(front, to, jump));
    _mm256_store_ps(L_.next_cell, _mm256_blendv_ps(next_cell, _mm256_add_ps(cell, one), jump));
    const __m256i have = _mm256_load_si256(reinterpret_cast<const __m256i*>(L_.have_front));
    _mm256_store_si256(reinterpret_cast<__m256i*>(L_.have_front),
                       _mm256_andnot_si256(_mm256_castps_si256(jump), have));
    // A lane moved to the end of its span has nothing left (no zero-length piece).
    const __m256 at_end = _mm256_and_ps(jump, _mm256_cmp_ps(to, t1, _CMP_GE_OQ));
    return none | static_cast<unsigned>(_mm256_movemask_ps(at_end));
  }

  // One piece in every live lane: sample, range test, classify, shade, composite. Returns the
  // lanes whose piece was visible.
  unsigned step(unsigned live) {
    const __m256 active = lane_mask(live);
    const __m256 ox = _mm256_load_ps(L_.ox), oy = _mm256_load_ps(L_.oy), oz = _mm256_load_ps(L_.oz);
    const __m256 dx = _mm256_load_ps(L_.dx), dy = _mm256_load_ps(L_.dy), dz = _mm256_load_ps(L_.dz);
    const __m256 front = _mm256_load_ps(L_.front), next_cell = _mm256_load_ps(L_.next_cell);
    const __m256 back =
        _mm256_min_ps(_mm256_load_ps(L_.t1), _mm256_mul_ps(next_cell, splat(step_)));
    const __m256 s_b = grid_.sample(_mm256_fmadd_ps(back, dx, ox), _mm256_fmadd_ps(back, dy, oy),
                                    _mm256_fmadd_ps(back, dz, oz));
    __m256 s_f = _mm256_load_ps(L_.s_front);
    const __m256 need_front = _mm256_andnot_ps(
        _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(L_.have_front))),
        active);
    if (_mm256_movemask_ps(need_front)) {
      __m256 s = grid_.sample(_mm256_fmadd_ps(front, dx, ox), _mm256_fmadd_ps(front, dy, oy),
                              _mm256_fmadd_ps(front, dz, oz));
      s_f = _mm256_blendv_ps(s_f, s, need_front);
    }
    const __m256 len = _mm256_sub_ps(back, front);
    _mm256_store_ps(L_.front, back);
    _mm256_store_ps(L_.next_cell, _mm256_add_ps(next_cell, splat(1.0f)));
    _mm256_store_ps(L_.s_front, s_b);
    _mm256_store_si256(reinterpret_cast<__m256i*>(L_.have_front), splat(-1));

    // The range test of VolumeMarcher::next_in.
    __m256 vis = active;
    if (use_runs_) {
      vis = _mm256_andnot_ps(empty_between(s_f, s_b), vis);
    } else if (v_.accel.emptiness) {
      alignas(32) float f[kLanes], b[kLanes];
      _mm256_store_ps(f, s_f);
      _mm256_store_ps(b, s_b);
      unsigned keep = live;
      for (unsigned m = live; m; m &= m - 1) {
        int l = __builtin_ctz(m);
        if (v_.accel.emptiness->is_empty_between(f[l], b[l])) keep &= ~(1u << l);
      }
      vis = lane_mask(keep);
    }
    // A piece with no data at an end is transparent (VolumeMarcher::next_in).
    if constexpr (NoData)
      vis = _mm256_andnot_ps(_mm256_or_ps(no_data_lanes(s_f), no_data_lanes(s_b)), vis);
    if (!_mm256_movemask_ps(vis)) return 0;

    __m256 cr, cg, cb, ca;
    lookup(s_f, s_b, cr, cg, cb, ca);
    vis = _mm256_and_ps(vis, _mm256_cmp_ps(ca, _mm256_setzero_ps(), _CMP_GT_OQ));
    if (!_mm256_movemask_ps(vis)) return 0;
    // Where the light comes from, from the table's moments before the short-piece correction,
    // as PreintegrationView::lookup(s_f, s_b, light) in VolumeMarcher::classify.
    __m256 centre = splat(0.5f), spread = _mm256_setzero_ps();
    if (centre_ && (shaded_ || sink_)) light_of(s_f, s_b, ca, centre, spread);
    const __m256 short_piece =
        _mm256_and_ps(vis, _mm256_cmp_ps(len, splat(0.9999f * step_), _CMP_NGE_UQ));
    if (_mm256_movemask_ps(short_piece)) correct_short(short_piece, len, cr, cg, cb, ca);
    if (shaded_) {
      // VolumeMarcher::shade: one point (the midpoint, or the light's centre) or, where the
      // light is spread, the mean of two points a standard deviation either side of it.
      const __m256 two = _mm256_and_ps(vis, _mm256_cmp_ps(spread, splat(kMinSpread), _CMP_GE_OQ));
      const __m256 u_a = _mm256_blendv_ps(
          centre, _mm256_max_ps(_mm256_setzero_ps(), _mm256_sub_ps(centre, spread)), two);
      const __m256 t_a = _mm256_fmadd_ps(u_a, len, front);
      const __m256 u_b = _mm256_min_ps(splat(1.0f), _mm256_add_ps(centre, spread));
      const __m256 t_b = _mm256_fmadd_ps(u_b, len, front);
      const Points at{{_mm256_fmadd_ps(t_a, dx, ox), _mm256_fmadd_ps(t_a, dy, oy),
                       _mm256_fmadd_ps(t_a, dz, oz)},
                      {_mm256_fmadd_ps(t_b, dx, ox), _mm256_fmadd_ps(t_b, dy, oy),
                       _mm256_fmadd_ps(t_b, dz, oz)}};
      if (defer_) {
        // The opacity composites now (ERT reads it), the colour once eight pieces wait.
        const __m256 aa = _mm256_load_ps(L_.a);
        const __m256 w = _mm256_sub_ps(splat(1.0f), aa);
        _mm256_store_ps(L_.a, _mm256_blendv_ps(aa, _mm256_fmadd_ps(w, ca, aa), vis));
        defer(vis, two, w, cr, cg, cb, ca, at);
        return static_cast<unsigned>(_mm256_movemask_ps(vis));
      }
      shade_points(vis, two, in_order(), at, cr, cg, cb, ca);
    }
    if (sink_) collect(vis, s_f, s_b, front, back, centre, cr, cg, cb, ca);
    // over(acc, c) where the piece is visible.
    const __m256 ar = _mm256_load_ps(L_.r), ag = _mm256_load_ps(L_.g), ab = _mm256_load_ps(L_.b),
                 aa = _mm256_load_ps(L_.a);
    const __m256 w = _mm256_sub_ps(splat(1.0f), aa);
    _mm256_store_ps(L_.r, _mm256_blendv_ps(ar, _mm256_fmadd_ps(w, cr, ar), vis));
    _mm256_store_ps(L_.g, _mm256_blendv_ps(ag, _mm256_fmadd_ps(w, cg, ag), vis));
    _mm256_store_ps(L_.b, _mm256_blendv_ps(ab, _mm256_fmadd_ps(w, cb, ab), vis));
    _mm256_store_ps(L_.a, _mm256_blendv_ps(aa, _mm256_fmadd_ps(w, ca, aa), vis));
    return static_cast<unsigned>(_mm256_movemask_ps(vis));
  }

  // Where a piece is shaded: one point, and a second one where its light is spread.
  struct Points {
    __m256 a[3], b[3];
  };

  // The shading of pieces in lanes: at point a where `two` is clear, else the mean of a and b.
  // Lane k holds a piece of the ray in lane from[k].
  void shade_points(__m256 vis, __m256 two, __m256i from, const Points& at, __m256& cr, __m256& cg,
                    __m256& cb, __m256 ca) const {
    __m256 r2 = cr, g2 = cg, b2 = cb;
    shade(vis, from, at.a[0], at.a[1], at.a[2], cr, cg, cb, ca);
    if (_mm256_movemask_ps(two)) {
      shade(two, from, at.b[0], at.b[1], at.b[2], r2, g2, b2, ca);
      const __m256 half = splat(0.5f);
      cr = _mm256_blendv_ps(cr, _mm256_mul_ps(half, _mm256_add_ps(cr, r2)), two);
      cg = _mm256_blendv_ps(cg, _mm256_mul_ps(half, _mm256_add_ps(cg, g2)), two);
      cb = _mm256_blendv_ps(cb, _mm256_mul_ps(half, _mm256_add_ps(cb, b2)), two);
    }
  }

  // Puts the visible pieces of `vis` in the shading queue, packed in lane order, and shades the
  // first eight once that many wait. A step shades only about half its lanes on real scans
  // (4.5 of 8 on a CT with the bone preset): the queue fills every lane of each shading.
  void defer(__m256 vis, __m256 two, __m256 w, __m256 cr, __m256 cg, __m256 cb, __m256 ca,
             const Points& at) {
    const unsigned m = static_cast<unsigned>(_mm256_movemask_ps(vis));
    const __m256i order =
        _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(static_cast<int>(kPackOrder[m])),
                                           _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28)),
                         splat(0xf));
    const __m256 fields[ShadeQueue::kFields] = {
        w,       cr,      cg,      cb,      ca,      at.a[0],
        at.a[1], at.a[2], at.b[0], at.b[1], at.b[2], _mm256_castsi256_ps(in_order()),
        two};
    for (int f = 0; f < ShadeQueue::kFields; ++f)
      _mm256_storeu_ps(&queue_.field[f][queue_.count], _mm256_permutevar8x32_ps(fields[f], order));
    queue_.count += __builtin_popcount(m);
    if (queue_.count < kLanes) return;
    shade_queued(kLanes);
    queue_.count -= kLanes;
    for (int f = 0; f < ShadeQueue::kFields; ++f)
      _mm256_store_ps(queue_.field[f], _mm256_loadu_ps(&queue_.field[f][kLanes]));
  }

  // Shades the first n queued pieces and adds their colour to their rays, in queue order (each
  // ray's pieces in ray order): acc.rgb += w * colour, as over() would have at the piece.
  void shade_queued(int n) {
    const auto field = [&](int f) { return _mm256_load_ps(queue_.field[f]); };
    const __m256 valid = lane_mask((1u << n) - 1);
    const __m256i from = _mm256_castps_si256(field(ShadeQueue::kLane));
    const Points at{{field(ShadeQueue::kAx), field(ShadeQueue::kAy), field(ShadeQueue::kAz)},
                    {field(ShadeQueue::kBx), field(ShadeQueue::kBy), field(ShadeQueue::kBz)}};
    __m256 cr = field(ShadeQueue::kR), cg = field(ShadeQueue::kG), cb = field(ShadeQueue::kB);
    shade_points(valid, _mm256_and_ps(valid, field(ShadeQueue::kTwo)), from, at, cr, cg, cb,
                 field(ShadeQueue::kA));
    alignas(32) float r[kLanes], g[kLanes], b[kLanes];
    alignas(32) int32_t lane[kLanes];
    _mm256_store_ps(r, cr), _mm256_store_ps(g, cg), _mm256_store_ps(b, cb);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane), from);
    const float* w = queue_.field[ShadeQueue::kW];
    for (int k = 0; k < n; ++k) {
      const int l = lane[k];
      L_.r[l] = std::fma(w[k], r[k], L_.r[l]);
      L_.g[l] = std::fma(w[k], g[k], L_.g[l]);
      L_.b[l] = std::fma(w[k], b[k], L_.b[l]);
    }
  }

  // The visible pieces of the lanes in `vis` as slabs to the sink (march_slab_packets), each
  // trimmed as VolumeMarcher::next trims it: scalar, once per visible piece. A ray the sink
  // declines ends here (its span closes).
  void collect(__m256 vis, __m256 s_f, __m256 s_b, __m256 front, __m256 back, __m256 centre,
               __m256 cr, __m256 cg, __m256 cb, __m256 ca) {
    alignas(32) float f[kLanes], b[kLanes], t0[kLanes], t1[kLanes], at[kLanes];
    alignas(32) float r[kLanes], g[kLanes], bl[kLanes], a[kLanes];
    _mm256_store_ps(f, s_f), _mm256_store_ps(b, s_b), _mm256_store_ps(at, centre);
    _mm256_store_ps(t0, front), _mm256_store_ps(t1, back);
    _mm256_store_ps(r, cr), _mm256_store_ps(g, cg), _mm256_store_ps(bl, cb), _mm256_store_ps(a, ca);
    for (unsigned m = static_cast<unsigned>(_mm256_movemask_ps(vis)); m; m &= m - 1) {
      const int l = __builtin_ctz(m);
      double lo = t0[l], hi = t1[l];
      if (trim_) trim_to_light(*v_.accel.emptiness, f[l], b[l], at[l], lo, hi);
      const Slab slab = Slab::between(static_cast<float>(lo), static_cast<float>(hi),
                                      glm::vec4(r[l], g[l], bl[l], a[l]));
      if (!sink_->take(static_cast<size_t>(L_.ray[l]), slab)) L_.t1[l] = -INFINITY;
    }
  }

  // One piece of a label volume in every live lane, as VolumeMarcher::next_label_in_piece:
  // the winners at the grid points; a piece whose ends agree is one slab of that label, shaded
  // in lanes at its midpoint by the label's indicator gradient; one whose ends differ splits at
  // the bisected boundary, per lane (rare: boundaries only). Returns the lanes with a visible
  // slab.
  unsigned step_labels(unsigned live) {
    const __m256 active = lane_mask(live);
    const __m256 ox = _mm256_load_ps(L_.ox), oy = _mm256_load_ps(L_.oy), oz = _mm256_load_ps(L_.oz);
    const __m256 dx = _mm256_load_ps(L_.dx), dy = _mm256_load_ps(L_.dy), dz = _mm256_load_ps(L_.dz);
    const __m256 front = _mm256_load_ps(L_.front), next_cell = _mm256_load_ps(L_.next_cell);
    const __m256 back =
        _mm256_min_ps(_mm256_load_ps(L_.t1), _mm256_mul_ps(next_cell, splat(step_)));
    const __m256i l_b = winners(_mm256_fmadd_ps(back, dx, ox), _mm256_fmadd_ps(back, dy, oy),
                                _mm256_fmadd_ps(back, dz, oz), live);
    __m256i l_f = _mm256_load_si256(reinterpret_cast<const __m256i*>(L_.label_front));
    const __m256 need_front = _mm256_andnot_ps(
        _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(L_.have_front))),
        active);
    if (const unsigned need = static_cast<unsigned>(_mm256_movemask_ps(need_front)))
      l_f =
          _mm256_blendv_epi8(l_f,
                             winners(_mm256_fmadd_ps(front, dx, ox), _mm256_fmadd_ps(front, dy, oy),
                                     _mm256_fmadd_ps(front, dz, oz), need),
                             _mm256_castps_si256(need_front));
    const __m256 len = _mm256_sub_ps(back, front);
    _mm256_store_ps(L_.front, back);
    _mm256_store_ps(L_.next_cell, _mm256_add_ps(next_cell, splat(1.0f)));
    _mm256_store_si256(reinterpret_cast<__m256i*>(L_.label_front), l_b);
    _mm256_store_si256(reinterpret_cast<__m256i*>(L_.have_front), splat(-1));

    alignas(32) int32_t lf[kLanes], lb[kLanes];
    alignas(32) float fr[kLanes], bk[kLanes], ln[kLanes];
    alignas(32) float cr[kLanes] = {}, cg[kLanes] = {}, cb[kLanes] = {}, ca[kLanes] = {};
    _mm256_store_si256(reinterpret_cast<__m256i*>(lf), l_f);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lb), l_b);
    _mm256_store_ps(fr, front), _mm256_store_ps(bk, back), _mm256_store_ps(ln, len);
    unsigned lit = 0, whole = 0;
    const float unit = v_.labels.unit_distance();
    for (unsigned m = live; m; m &= m - 1) {
      const int l = __builtin_ctz(m);
      if (lf[l] != lb[l]) {
        if (split(l, lf[l], lb[l], fr[l], bk[l])) lit |= 1u << l;
        continue;
      }
      const int k = cached(lb[l]);
      const glm::vec4& look = cached_look_[k];
      if (look.a <= 0.0f || !(ln[l] > 0.0f)) continue;
      const float a =
          ln[l] >= 0.9999f * step_ ? cached_alpha_[k] : correct_opacity(look.a, ln[l], unit);
      if (!(a > 0.0f)) continue;
      cr[l] = look.r * a, cg[l] = look.g * a, cb[l] = look.b * a, ca[l] = a;
      whole |= 1u << l;
    }
    if (!whole) return lit;
    const __m256 vis = lane_mask(whole);
    __m256 r = _mm256_load_ps(cr), g = _mm256_load_ps(cg), b = _mm256_load_ps(cb),
           a = _mm256_load_ps(ca);
    if (shaded_) {
      const __m256 t_mid = _mm256_fmadd_ps(splat(0.5f), len, front);
      const __m256 px = _mm256_fmadd_ps(t_mid, dx, ox), py = _mm256_fmadd_ps(t_mid, dy, oy),
                   pz = _mm256_fmadd_ps(t_mid, dz, oz);
      // label_gradient in lanes: central differences of the label's indicator.
      __m256 gx, gy, gz;
      if (!cells_.interior_gradient(vis, px, py, pz, l_b, gx, gy, gz)) {
        const __m256 one = splat(1.0f), half = splat(0.5f);
        gx = _mm256_mul_ps(half,
                           _mm256_sub_ps(cells_.indicator(_mm256_add_ps(px, one), py, pz, l_b),
                                         cells_.indicator(_mm256_sub_ps(px, one), py, pz, l_b)));
        gy = _mm256_mul_ps(half,
                           _mm256_sub_ps(cells_.indicator(px, _mm256_add_ps(py, one), pz, l_b),
                                         cells_.indicator(px, _mm256_sub_ps(py, one), pz, l_b)));
        gz = _mm256_mul_ps(half,
                           _mm256_sub_ps(cells_.indicator(px, py, _mm256_add_ps(pz, one), l_b),
                                         cells_.indicator(px, py, _mm256_sub_ps(pz, one), l_b)));
      }
      shade_gradient(vis, in_order(), gx, gy, gz, r, g, b, a);
    }
    composite(vis, r, g, b, a);
    return lit | whole;
  }

  // winning_label at the lanes' points, for the lanes in m: the common label where all eight
  // voxels around a point agree (most points), else the scalar classifier.
  __m256i winners(__m256 px, __m256 py, __m256 pz, unsigned m) const {
    alignas(32) int32_t out[kLanes] = {};
    unsigned mixed = m;
    if (!nearest_) {
      __m256i c[8];
      __m256 fx, fy, fz;
      cells_.cell(px, py, pz, c, fx, fy, fz);
      __m256i same = _mm256_cmpeq_epi32(c[1], c[0]);
      for (int k = 2; k < 8; ++k) same = _mm256_and_si256(same, _mm256_cmpeq_epi32(c[k], c[0]));
      mixed &= ~static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(same)));
      if (!mixed) return c[0];
      _mm256_store_si256(reinterpret_cast<__m256i*>(out), c[0]);
    }
    alignas(32) float x[kLanes], y[kLanes], z[kLanes];
    _mm256_store_ps(x, px), _mm256_store_ps(y, py), _mm256_store_ps(z, pz);
    for (; mixed; mixed &= mixed - 1) {
      const int l = __builtin_ctz(mixed);
      out[l] = winning_label(voxels_, glm::vec3(x[l], y[l], z[l]), nearest_);
    }
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(out));
  }

  // The slot of a small cache that holds the label's look and the opacity of a whole step of
  // it (a segmentation shows a few labels, each costing one look-up and one pow per batch).
  int cached(int32_t label) {
    const int k = label & (kAlphaCache - 1);
    if (cached_label_[k] != label) {
      cached_label_[k] = label;
      cached_look_[k] = v_.labels.look(label);
      cached_alpha_[k] = correct_opacity(cached_look_[k].a, step_, v_.labels.unit_distance());
    }
    return k;
  }
  static constexpr int kAlphaCache = 64;

  // A piece of lane l whose ends' labels differ: split at the bisected boundary into a slab of
  // each label, composited in order while the lane is below ERT (VolumeMarcher's pending
  // slab). Returns whether either showed.
  bool split(int l, int32_t l_f, int32_t l_b, float front, float back) {
    const glm::vec3 o(L_.ox[l], L_.oy[l], L_.oz[l]), d(L_.dx[l], L_.dy[l], L_.dz[l]);
    double lo = front, hi = back;
    for (int i = 0; i < VolumeMarcher::kLabelBisections; ++i) {
      const double m = 0.5 * (lo + hi);
      (winning_label(voxels_, o + static_cast<float>(m) * d, nearest_) == l_f ? lo : hi) = m;
    }
    const double cut = 0.5 * (lo + hi);
    glm::vec4 acc(L_.r[l], L_.g[l], L_.b[l], L_.a[l]);
    const glm::vec4 first = label_slab(l, l_f, front, cut);
    bool shown = false;
    if (first.a > 0.0f) acc = over(acc, first), shown = true;
    if (acc.a < ert_ && cut < back) {
      const glm::vec4 second = label_slab(l, l_b, cut, back);
      if (second.a > 0.0f) acc = over(acc, second), shown = true;
    }
    L_.r[l] = acc.r, L_.g[l] = acc.g, L_.b[l] = acc.b, L_.a[l] = acc.a;
    return shown;
  }

  // VolumeMarcher::label_slab for lane l.
  glm::vec4 label_slab(int l, int32_t label, double front, double back) const {
    const glm::vec4 look = v_.labels.look(label);
    if (look.a <= 0.0f || !(back > front)) return glm::vec4(0.0f);
    const float a =
        correct_opacity(look.a, static_cast<float>(back - front), v_.labels.unit_distance());
    const glm::vec4 c(glm::vec3(look) * a, a);
    if (!shaded_) return c;
    const glm::vec3 o(L_.ox[l], L_.oy[l], L_.oz[l]), d(L_.dx[l], L_.dy[l], L_.dz[l]);
    const glm::vec3 g =
        label_gradient(voxels_, o + static_cast<float>(0.5 * (front + back)) * d, label);
    const RayShading shading(v_.object->shading, v_.specular, lights_,
                             -rays_[static_cast<size_t>(L_.ray[l])].ray.dir);
    return shading.apply(c, v_.gradient_to_world * g);
  }

  // over(acc, c) in the lanes of vis.
  void composite(__m256 vis, __m256 cr, __m256 cg, __m256 cb, __m256 ca) {
    const __m256 ar = _mm256_load_ps(L_.r), ag = _mm256_load_ps(L_.g), ab = _mm256_load_ps(L_.b),
                 aa = _mm256_load_ps(L_.a);
    const __m256 w = _mm256_sub_ps(splat(1.0f), aa);
    _mm256_store_ps(L_.r, _mm256_blendv_ps(ar, _mm256_fmadd_ps(w, cr, ar), vis));
    _mm256_store_ps(L_.g, _mm256_blendv_ps(ag, _mm256_fmadd_ps(w, cg, ag), vis));
    _mm256_store_ps(L_.b, _mm256_blendv_ps(ab, _mm256_fmadd_ps(w, cb, ab), vis));
    _mm256_store_ps(L_.a, _mm256_blendv_ps(aa, _mm256_fmadd_ps(w, ca, aa), vis));
  }

  // TfEmptiness::is_empty_between in lanes (NaN ends as there: a NaN front is never empty, a
  // NaN back counts as the front).
  __m256 empty_between(__m256 a, __m256 b) const {
    b = _mm256_blendv_ps(a, b, _mm256_cmp_ps(b, b, _CMP_ORD_Q));
    const __m256 lo = _mm256_min_ps(a, b), hi = _mm256_max_ps(a, b);
    __m256 empty = _mm256_setzero_ps();
    for (int k = 0; k < TfEmptiness::kMaxRuns; ++k)
      empty = _mm256_or_ps(empty, _mm256_and_ps(_mm256_cmp_ps(lo, splat(run_lo_[k]), _CMP_GE_OQ),
                                                _mm256_cmp_ps(hi, splat(run_hi_[k]), _CMP_LE_OQ)));
    return _mm256_and_ps(empty, _mm256_cmp_ps(a, a, _CMP_ORD_Q));
  }

  // PreintegrationView::lookup(s_f, s_b) in lanes.
  void lookup(__m256 s_f, __m256 s_b, __m256& r, __m256& g, __m256& b, __m256& a) const {
    const __m256 lo = splat(preint_.lo), inv = splat(preint_.inv_step);
    const __m256 last = splat(static_cast<float>(preint_.size - 1));
    const __m256i last_cell = splat(preint_.size - 2);
    // max(x, 0) returns 0 for a NaN x, as PreintegrationView::axis does.
    const __m256 x = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(s_f, lo), inv), _mm256_setzero_ps()), last);
    const __m256 y = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(s_b, lo), inv), _mm256_setzero_ps()), last);
    const __m256i i = _mm256_min_epi32(_mm256_cvttps_epi32(x), last_cell);
    const __m256i j = _mm256_min_epi32(_mm256_cvttps_epi32(y), last_cell);
    const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
    const __m256 fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(j));
    // Per lane, the two entries of each row are one 32-byte load: four loads and a transpose
    // instead of sixteen gathers.
    alignas(32) int32_t entry[kLanes];
    alignas(32) float wx[kLanes], wy[kLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(entry),
                       _mm256_add_epi32(_mm256_mullo_epi32(i, splat(preint_.size)), j));
    _mm256_store_ps(wx, fx), _mm256_store_ps(wy, fy);
    const float* table = reinterpret_cast<const float*>(preint_.data);
    const size_t row = 4 * static_cast<size_t>(preint_.size);
    __m128 e[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const float* r0 = table + 4 * static_cast<size_t>(entry[l]);
      __m256 r = lerp(_mm256_loadu_ps(r0), _mm256_loadu_ps(r0 + row), _mm256_broadcast_ss(&wx[l]));
      __m128 lo = _mm256_castps256_ps128(r), hi = _mm256_extractf128_ps(r, 1);
      e[l] = _mm_fmadd_ps(_mm_broadcast_ss(&wy[l]), _mm_sub_ps(hi, lo), lo);
    }
    __m256 v0 = _mm256_set_m128(e[4], e[0]), v1 = _mm256_set_m128(e[5], e[1]);
    __m256 v2 = _mm256_set_m128(e[6], e[2]), v3 = _mm256_set_m128(e[7], e[3]);
    __m256 t0 = _mm256_unpacklo_ps(v0, v1), t1 = _mm256_unpackhi_ps(v0, v1);
    __m256 t2 = _mm256_unpacklo_ps(v2, v3), t3 = _mm256_unpackhi_ps(v2, v3);
    r = _mm256_shuffle_ps(t0, t2, 0x44), g = _mm256_shuffle_ps(t0, t2, 0xee);
    b = _mm256_shuffle_ps(t1, t3, 0x44), a = _mm256_shuffle_ps(t1, t3, 0xee);
  }

  // PreintegrationView::light_of(a, the moments at (s_f, s_b)) in lanes: the centre and the
  // spread of where a piece's light comes from (0.5 and 0 where a is not positive).
  void light_of(__m256 s_f, __m256 s_b, __m256 a, __m256& centre, __m256& spread) const {
    const __m256 lo = splat(preint_.lo), inv = splat(preint_.inv_step);
    const __m256 last = splat(static_cast<float>(preint_.size - 1));
    const __m256i last_cell = splat(preint_.size - 2);
    const __m256 x = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(s_f, lo), inv), _mm256_setzero_ps()), last);
    const __m256 y = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(s_b, lo), inv), _mm256_setzero_ps()), last);
    const __m256i i = _mm256_min_epi32(_mm256_cvttps_epi32(x), last_cell);
    const __m256i j = _mm256_min_epi32(_mm256_cvttps_epi32(y), last_cell);
    alignas(32) int32_t entry[kLanes];
    alignas(32) float wx[kLanes], wy[kLanes], m1[kLanes], m2[kLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(entry),
                       _mm256_add_epi32(_mm256_mullo_epi32(i, splat(preint_.size)), j));
    _mm256_store_ps(wx, _mm256_sub_ps(x, _mm256_cvtepi32_ps(i)));
    _mm256_store_ps(wy, _mm256_sub_ps(y, _mm256_cvtepi32_ps(j)));
    const float* table = reinterpret_cast<const float*>(preint_.moments);
    const size_t row = 2 * static_cast<size_t>(preint_.size);
    for (int l = 0; l < kLanes; ++l) {
      // Entries j and j + 1 of rows i and i + 1: one 16-byte load per row.
      const float* r0 = table + 2 * static_cast<size_t>(entry[l]);
      const __m128 r =
          _mm_fmadd_ps(_mm_set1_ps(wx[l]), _mm_sub_ps(_mm_loadu_ps(r0 + row), _mm_loadu_ps(r0)),
                       _mm_loadu_ps(r0));
      const __m128 m = _mm_fmadd_ps(_mm_set1_ps(wy[l]), _mm_sub_ps(_mm_movehl_ps(r, r), r), r);
      m1[l] = _mm_cvtss_f32(m);
      m2[l] = _mm_cvtss_f32(_mm_shuffle_ps(m, m, 1));
    }
    const __m256 lit = _mm256_cmp_ps(a, _mm256_setzero_ps(), _CMP_GT_OQ);
    const __m256 inv_a = _mm256_div_ps(splat(1.0f), a);
    const __m256 mean = _mm256_min_ps(
        _mm256_max_ps(_mm256_mul_ps(_mm256_load_ps(m1), inv_a), _mm256_setzero_ps()), splat(1.0f));
    const __m256 variance = _mm256_fnmadd_ps(mean, mean, _mm256_mul_ps(_mm256_load_ps(m2), inv_a));
    const __m256 sd = _mm256_and_ps(_mm256_sqrt_ps(_mm256_max_ps(variance, _mm256_setzero_ps())),
                                    _mm256_cmp_ps(variance, _mm256_setzero_ps(), _CMP_GT_OQ));
    centre = _mm256_blendv_ps(splat(0.5f), mean, lit);
    spread = _mm256_and_ps(sd, lit);
  }
  static constexpr float kMinSpread = 1.0f / 64.0f;  // VolumeMarcher::kMinSpread

  // The opacity correction of pieces shorter than the table's step (span ends only: rare).
  void correct_short(__m256 mask, __m256 len, __m256& r, __m256& g, __m256& b, __m256& a) const {
    alignas(32) float lr[kLanes], lg[kLanes], lb[kLanes], la[kLanes], ll[kLanes];
    _mm256_store_ps(lr, r), _mm256_store_ps(lg, g), _mm256_store_ps(lb, b), _mm256_store_ps(la, a);
    _mm256_store_ps(ll, len);
    for (unsigned m = static_cast<unsigned>(_mm256_movemask_ps(mask)); m; m &= m - 1) {
      int l = __builtin_ctz(m);
      float alpha = la[l] >= 1.0f ? 1.0f : 1.0f - std::pow(1.0f - la[l], ll[l] / step_);
      float k = alpha / la[l];
      lr[l] *= k, lg[l] *= k, lb[l] *= k, la[l] *= k;
    }
    r = _mm256_load_ps(lr), g = _mm256_load_ps(lg), b = _mm256_load_ps(lb), a = _mm256_load_ps(la);
  }

  // RayShading::apply with the gradient at index-space point p, in lanes (lane k on the ray of
  // lane from[k]).
  void shade(__m256 vis, __m256i from, __m256 px, __m256 py, __m256 pz, __m256& r, __m256& g,
             __m256& b, __m256 a) const {
    __m256 gx, gy, gz;
    if (gradients_) {
      gradients_->sample(px, py, pz, gx, gy, gz);
    } else if constexpr (NoData) {
      gradient_of_data(px, py, pz, gx, gy, gz);
    } else {
      const __m256 one = splat(1.0f), half = splat(0.5f);
      gx = _mm256_mul_ps(half, _mm256_sub_ps(grid_.sample(_mm256_add_ps(px, one), py, pz),
                                             grid_.sample(_mm256_sub_ps(px, one), py, pz)));
      gy = _mm256_mul_ps(half, _mm256_sub_ps(grid_.sample(px, _mm256_add_ps(py, one), pz),
                                             grid_.sample(px, _mm256_sub_ps(py, one), pz)));
      gz = _mm256_mul_ps(half, _mm256_sub_ps(grid_.sample(px, py, _mm256_add_ps(pz, one)),
                                             grid_.sample(px, py, _mm256_sub_ps(pz, one))));
    }
    shade_gradient(vis, from, gx, gy, gz, r, g, b, a);
  }

  // RayShading::apply with the index-space gradient g, in lanes (lane k on the ray of lane
  // from[k], whose eye and light directions it takes).
  void shade_gradient(__m256 vis, __m256i from, __m256 gx, __m256 gy, __m256 gz, __m256& r,
                      __m256& g, __m256& b, __m256 a) const {
    const auto ray_field = [from](const float* f) {
      return _mm256_permutevar8x32_ps(_mm256_load_ps(f), from);
    };
    const glm::mat3& m = v_.gradient_to_world;
    __m256 nx = dot3(splat(m[0][0]), splat(m[1][0]), splat(m[2][0]), gx, gy, gz);
    __m256 ny = dot3(splat(m[0][1]), splat(m[1][1]), splat(m[2][1]), gx, gy, gz);
    __m256 nz = dot3(splat(m[0][2]), splat(m[1][2]), splat(m[2][2]), gx, gy, gz);

    const Shading& s = v_.object->shading;
    const __m256 zero = _mm256_setzero_ps();
    const __m256 len2 = dot3(nx, ny, nz, nx, ny, nz);
    const __m256 has_normal = _mm256_cmp_ps(len2, splat(1e-24f), _CMP_GT_OQ);
    const __m256 inv = _mm256_div_ps(splat(1.0f), _mm256_sqrt_ps(len2));
    nx = _mm256_mul_ps(nx, inv), ny = _mm256_mul_ps(ny, inv), nz = _mm256_mul_ps(nz, inv);
    const __m256 ex = ray_field(L_.ex), ey = ray_field(L_.ey), ez = ray_field(L_.ez);
    // Two-sided: the normal turned toward the viewer.
    const __m256 flip =
        _mm256_and_ps(_mm256_cmp_ps(dot3(nx, ny, nz, ex, ey, ez), zero, _CMP_LT_OQ), splat(-0.0f));
    nx = _mm256_xor_ps(nx, flip), ny = _mm256_xor_ps(ny, flip), nz = _mm256_xor_ps(nz, flip);

    const __m256 amb = splat(s.ambient), dif = splat(s.diffuse), spec = splat(s.specular);
    __m256 out_r = _mm256_mul_ps(amb, r), out_g = _mm256_mul_ps(amb, g),
           out_b = _mm256_mul_ps(amb, b);
    for (int k = 0; k < light_count_; ++k) {
      const glm::vec3& col = lights_[k].color;
      const __m256 ndotl =
          dot3(nx, ny, nz, ray_field(L_.lx[k]), ray_field(L_.ly[k]), ray_field(L_.lz[k]));
      const __m256 ndoth = _mm256_max_ps(
          dot3(nx, ny, nz, ray_field(L_.hx[k]), ray_field(L_.hy[k]), ray_field(L_.hz[k])), zero);
      // Lit lanes: diffuse N.L and the highlight; lanes without a normal: diffuse head-on.
      const __m256 kd = _mm256_blendv_ps(dif, _mm256_mul_ps(dif, ndotl), has_normal);
      const __m256 ks =
          _mm256_and_ps(_mm256_mul_ps(_mm256_mul_ps(spec, specular(ndoth)), a), has_normal);
      const __m256 on =
          _mm256_or_ps(_mm256_andnot_ps(has_normal, vis), _mm256_cmp_ps(ndotl, zero, _CMP_GT_OQ));
      const __m256 cr = splat(col.r), cg = splat(col.g), cb = splat(col.b);
      out_r = _mm256_add_ps(out_r, _mm256_and_ps(on, _mm256_fmadd_ps(_mm256_mul_ps(kd, r), cr,
                                                                     _mm256_mul_ps(ks, cr))));
      out_g = _mm256_add_ps(out_g, _mm256_and_ps(on, _mm256_fmadd_ps(_mm256_mul_ps(kd, g), cg,
                                                                     _mm256_mul_ps(ks, cg))));
      out_b = _mm256_add_ps(out_b, _mm256_and_ps(on, _mm256_fmadd_ps(_mm256_mul_ps(kd, b), cb,
                                                                     _mm256_mul_ps(ks, cb))));
    }
    r = out_r, g = out_g, b = out_b;
  }

  // VoxelGrid::gradient_of_data in lanes: one-sided against the centre where a side is no data,
  // 0 where that is not possible either.
  void gradient_of_data(__m256 px, __m256 py, __m256 pz, __m256& gx, __m256& gy, __m256& gz) const {
    const __m256 one = splat(1.0f), half = splat(0.5f), zero = _mm256_setzero_ps();
    const __m256 c = grid_.sample(px, py, pz);
    const __m256 centre = _mm256_andnot_ps(no_data_lanes(c), _mm256_castsi256_ps(splat(-1)));
    auto axis = [&](__m256 up, __m256 down) {
      const __m256 has_up = _mm256_andnot_ps(no_data_lanes(up), centre);
      const __m256 has_down = _mm256_andnot_ps(no_data_lanes(down), centre);
      const __m256 both = _mm256_andnot_ps(
          no_data_lanes(up), _mm256_andnot_ps(no_data_lanes(down), _mm256_castsi256_ps(splat(-1))));
      __m256 g = _mm256_blendv_ps(zero, _mm256_sub_ps(c, down), has_down);
      g = _mm256_blendv_ps(g, _mm256_sub_ps(up, c), has_up);
      return _mm256_blendv_ps(g, _mm256_mul_ps(half, _mm256_sub_ps(up, down)), both);
    };
    gx = axis(grid_.sample(_mm256_add_ps(px, one), py, pz),
              grid_.sample(_mm256_sub_ps(px, one), py, pz));
    gy = axis(grid_.sample(px, _mm256_add_ps(py, one), pz),
              grid_.sample(px, _mm256_sub_ps(py, one), pz));
    gz = axis(grid_.sample(px, py, _mm256_add_ps(pz, one)),
              grid_.sample(px, py, _mm256_sub_ps(pz, one)));
  }

  // SpecularTable::operator() in lanes: the same table, two gathers and a lerp.
  __m256 specular(__m256 x) const {
    const SpecularTable::View t = v_.specular.view();
    const __m256 last = splat(static_cast<float>(SpecularTable::kEntries - 1));
    __m256 u = _mm256_mul_ps(_mm256_sub_ps(x, splat(t.x_min)), splat(t.inv_step));
    const __m256 above = _mm256_cmp_ps(u, _mm256_setzero_ps(), _CMP_GT_OQ);  // false for NaN
    u = _mm256_min_ps(_mm256_max_ps(u, _mm256_setzero_ps()), last);
    const __m256i i = _mm256_cvttps_epi32(u);
    const __m256 f = _mm256_sub_ps(u, _mm256_cvtepi32_ps(i));
    const __m256 lo = gather_floats(t.values, i);
    const __m256 hi = gather_floats(t.values, _mm256_add_epi32(i, splat(1)));
    return _mm256_and_ps(lerp(lo, hi, f), above);
  }

  const PreparedVolume& v_;
  LaneGrid<T> grid_;
  VoxelGrid<T> voxels_;                     // the same voxels, for the scalar label classifier
  LaneLabelCells<T> cells_;                 // label volumes
  std::optional<LaneGradients> gradients_;  // empty: gradients on the fly
  std::optional<LaneBricks> bricks_;        // empty: no skipping
  LaneBricks::Rays brick_rays_{};
  int look_delay_ = 0;  // steps with a look put off since the last look
  std::span<const PacketRay> rays_;
  std::span<glm::vec4> out_;
  std::span<const ShadingLight> lights_;
  size_t next_ = 0;
  float step_, ert_;
  PreintegrationView preint_;
  bool shaded_ = false;
  bool centre_ = false;  // SlabExtent::visible: shade where each piece's light comes from
  bool trim_ = false;    // SlabExtent::visible: collected slabs cover their visible part
  SlabSink* sink_;       // null: composite only
  bool labels_ = false, nearest_ = false;  // a label volume (label_classifier.hpp)
  int32_t cached_label_[kAlphaCache];
  float cached_alpha_[kAlphaCache] = {};
  glm::vec4 cached_look_[kAlphaCache];
  int light_count_ = 0;
  bool use_runs_ = false;
  float run_lo_[TfEmptiness::kMaxRuns] = {}, run_hi_[TfEmptiness::kMaxRuns] = {};
  bool defer_ = false;  // shading waits in queue_ (composite only)
  ShadeQueue queue_;
  Lanes L_{};  // zeros in lanes that never get a ray
};

#endif  // IMX_PACKET_LANES

}  // namespace

bool packet_marching_supported(const PreparedVolume& v, std::span<const ShadingLight> lights) {
  if (v.colours.active()) return false;  // a colour volume's colours: VolumeMarcher, ray by ray
#if IMX_PACKET_LANES
  const glm::ivec3 d = v.grid.dims;
  const bool labels = v.labels.active();  // classified by label, not by a table
  if ((!labels && !v.accel.preint) || d.x < 2 || d.y < 2 || d.z < 2) return false;
  if (labels && v.has_no_data) return false;
  // Gathers take int32 indices: voxels, and the byte offsets of int16 gradients.
  const double voxels = static_cast<double>(d.x) * d.y * d.z;
  const bool int16_gradients = v.accel.gradients && !v.accel.gradients->packed();
  if (voxels * (int16_gradients ? 6.0 : 1.0) + 4.0 >= 2147483647.0) return false;
  // LaneBricks computes brick indices in floats, exact below 2^24 bricks.
  if (v.accel.occupancy && v.accel.occupancy->grid().count() >= (size_t{1} << 24)) return false;
  const Shading& s = v.object->shading;
  if (!s.enabled) return true;
  return lights.size() <= static_cast<size_t>(RayShading::kMaxLights) && !v.specular.exact();
#else
  (void)v, (void)lights;
  return false;
#endif
}

PacketCamera::PacketCamera(const CameraModel& camera)
    : at_(camera.pixel_basis().at),
      per_x_(camera.pixel_basis().per_x),
      per_y_(camera.pixel_basis().per_y),
      eye_(camera.eye()),
      forward_(camera.forward()),
      perspective_(camera.perspective()) {}

void PacketCamera::block(int x, int y, PacketRay* out, glm::vec2 at) const {
#if IMX_PACKET_LANES
  const __m256 px = _mm256_add_ps(splat(static_cast<float>(x) + at.x),
                                  _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 0.0f, 1.0f, 2.0f, 3.0f));
  const __m256 py = _mm256_add_ps(splat(static_cast<float>(y) + at.y),
                                  _mm256_setr_ps(0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f));
  __m256 v[3];
  for (int a = 0; a < 3; ++a)
    v[a] =
        _mm256_fmadd_ps(py, splat(per_y_[a]), _mm256_fmadd_ps(px, splat(per_x_[a]), splat(at_[a])));
  alignas(32) float point[3][kLanes];
  if (perspective_) {
    const __m256 inv =
        _mm256_div_ps(splat(1.0f), _mm256_sqrt_ps(dot3(v[0], v[1], v[2], v[0], v[1], v[2])));
    for (int a = 0; a < 3; ++a) _mm256_store_ps(point[a], _mm256_mul_ps(v[a], inv));
  } else {
    for (int a = 0; a < 3; ++a) _mm256_store_ps(point[a], v[a]);
  }
  for (int l = 0; l < kLanes; ++l) {
    const glm::vec3 p(point[0][l], point[1][l], point[2][l]);
    out[l].ray = perspective_ ? Ray{eye_, p} : Ray{p, forward_};
  }
#else
  for (int l = 0; l < 8; ++l) {
    const float px = static_cast<float>(x) + at.x + static_cast<float>(l % 4),
                py = static_cast<float>(y) + at.y + static_cast<float>(l / 4);
    const glm::vec3 p = at_ + px * per_x_ + py * per_y_;
    out[l].ray = perspective_ ? Ray{eye_, glm::normalize(p)} : Ray{p, forward_};
  }
#endif
}

void intersect_packets(const PreparedVolume& v, std::span<PacketRay> rays) {
  size_t first = 0;
#if IMX_PACKET_LANES
  const glm::mat4& m = v.world_to_index;
  const glm::vec3 hi = glm::vec3(v.grid.dims - 1);
  const __m256 zero = _mm256_setzero_ps(), tiny = splat(1e-12f), sign = splat(-0.0f);
  for (; first + kLanes <= rays.size(); first += kLanes) {
    alignas(32) float o[3][kLanes], d[3][kLanes];
    for (int l = 0; l < kLanes; ++l)
      for (int a = 0; a < 3; ++a)
        o[a][l] = rays[first + l].ray.origin[a], d[a][l] = rays[first + l].ray.dir[a];
    __m256 wo[3], wd[3];
    for (int a = 0; a < 3; ++a) wo[a] = _mm256_load_ps(o[a]), wd[a] = _mm256_load_ps(d[a]);
    __m256 t0 = zero, t1 = splat(INFINITY), outside = zero;
    for (int a = 0; a < 3; ++a) {
      // Row a of the index map: the ray's origin and direction in index space.
      const __m256 io =
          _mm256_fmadd_ps(splat(m[2][a]), wo[2],
                          _mm256_fmadd_ps(splat(m[1][a]), wo[1],
                                          _mm256_fmadd_ps(splat(m[0][a]), wo[0], splat(m[3][a]))));
      const __m256 id = dot3(splat(m[0][a]), splat(m[1][a]), splat(m[2][a]), wd[0], wd[1], wd[2]);
      const __m256 parallel = _mm256_cmp_ps(_mm256_andnot_ps(sign, id), tiny, _CMP_LT_OQ);
      const __m256 beyond = _mm256_or_ps(_mm256_cmp_ps(io, zero, _CMP_LT_OQ),
                                         _mm256_cmp_ps(io, splat(hi[a]), _CMP_GT_OQ));
      outside = _mm256_or_ps(outside, _mm256_and_ps(parallel, beyond));
      const __m256 inv = _mm256_div_ps(splat(1.0f), id);
      const __m256 ta = _mm256_mul_ps(_mm256_sub_ps(zero, io), inv);
      const __m256 tb = _mm256_mul_ps(_mm256_sub_ps(splat(hi[a]), io), inv);
      const __m256 swap = _mm256_cmp_ps(ta, tb, _CMP_GT_OQ);
      const __m256 near = _mm256_blendv_ps(ta, tb, swap), far = _mm256_blendv_ps(tb, ta, swap);
      // As std::max(t0, near) and std::min(t1, far): a NaN bound leaves the interval alone.
      t0 = _mm256_blendv_ps(_mm256_max_ps(near, t0), t0, parallel);
      t1 = _mm256_blendv_ps(_mm256_min_ps(far, t1), t1, parallel);
    }
    for (const ClipPlane& c : v.object->clip_planes) {
      const glm::vec3 n(c.normal), p(c.point);
      const __m256 side =
          dot3(_mm256_sub_ps(wo[0], splat(p.x)), _mm256_sub_ps(wo[1], splat(p.y)),
               _mm256_sub_ps(wo[2], splat(p.z)), splat(n.x), splat(n.y), splat(n.z));
      const __m256 rate = dot3(wd[0], wd[1], wd[2], splat(n.x), splat(n.y), splat(n.z));
      const __m256 parallel = _mm256_cmp_ps(_mm256_andnot_ps(sign, rate), tiny, _CMP_LT_OQ);
      outside =
          _mm256_or_ps(outside, _mm256_and_ps(parallel, _mm256_cmp_ps(side, zero, _CMP_LT_OQ)));
      const __m256 t = _mm256_div_ps(_mm256_xor_ps(side, sign), rate);
      const __m256 entering = _mm256_cmp_ps(rate, zero, _CMP_GT_OQ);
      t0 = _mm256_blendv_ps(t0, _mm256_max_ps(t, t0), _mm256_andnot_ps(parallel, entering));
      t1 = _mm256_blendv_ps(t1, _mm256_min_ps(t, t1),
                            _mm256_andnot_ps(parallel, _mm256_cmp_ps(rate, zero, _CMP_LE_OQ)));
    }
    t0 = _mm256_blendv_ps(t0, zero, outside);
    t1 = _mm256_blendv_ps(t1, splat(-1.0f), outside);
    alignas(32) float lo[kLanes], up[kLanes];
    _mm256_store_ps(lo, t0), _mm256_store_ps(up, t1);
    for (int l = 0; l < kLanes; ++l) rays[first + l].t0 = lo[l], rays[first + l].t1 = up[l];
  }
#endif
  for (; first < rays.size(); ++first) {
    const RayInterval span = v.intersect(rays[first].ray);
    rays[first].t0 = span.t0, rays[first].t1 = span.t1;
  }
}

void composite_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                       std::span<const ShadingLight> lights, float ert, std::span<glm::vec4> out,
                       SlabExtent extent) {
#if IMX_PACKET_LANES
  if (packet_marching_supported(v, lights)) {
    run_lane_kernel<PacketKernel>(v, rays, step, lights, ert, out, extent,
                                  static_cast<SlabSink*>(nullptr));
    return;
  }
#endif
  composite_each(v, rays, step, lights, ert, out, extent);
}

void march_slab_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                        std::span<const ShadingLight> lights, float ert, SlabSink& sink) {
#if IMX_PACKET_LANES
  if (packet_marching_supported(v, lights) && !v.labels.active()) {
    run_lane_kernel<PacketKernel>(v, rays, step, lights, ert, std::span<glm::vec4>(),
                                  SlabExtent::visible, &sink);
    return;
  }
#endif
  // One ray at a time (builds without lanes, label maps): the lanes' pieces, empty ones left out
  // as the lanes leave out the invisible.
  for (size_t i = 0; i < rays.size(); ++i) {
    VolumeMarcher m(v, rays[i].ray, rays[i].t0, rays[i].t1, step, lights, SlabExtent::visible);
    glm::vec4 acc(0.0f);
    Slab s;
    while (!(acc.a >= ert) && m.next(s)) {
      if (s.is_empty()) continue;
      if (!sink.take(i, s)) break;
      acc = over(acc, s.color);
    }
  }
}

void collect_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                     std::span<const ShadingLight> lights, float a_ert,
                     const SlabCollection& collection) {
  struct Lists final : SlabSink {
    const SlabCollection& c;
    explicit Lists(const SlabCollection& collection) : c(collection) {}
    bool take(size_t ray, const Slab& slab) override {
      c.lists[ray].push_back(slab, c.overflow);
      return true;
    }
  } lists(collection);
  for (SlabList& list : collection.lists) list.clear();
  // ert_reached: an ERT opacity of 1 or more never stops a volume's own array.
  march_slab_packets(v, rays, step, lights, a_ert < 1.0f ? a_ert : 2.0f, lists);
}

}  // namespace imx
