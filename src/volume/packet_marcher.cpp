#include "volume/packet_marcher.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>

#include "volume/label_classifier.hpp"
#include "volume/ray_shading.hpp"
#include "volume/simd_targets.hpp"
#include "volume/volume_marcher.hpp"
#include "volume/wide_scalar.hpp"

// One source for every SIMD target (Google Highway): foreach_target compiles the part between
// HWY_BEFORE_NAMESPACE and HWY_AFTER_NAMESPACE once per target; the public functions at the end
// (HWY_ONCE) dispatch to the widest target the machine has.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/packet_marcher.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "volume/lane_bricks-inl.hpp"
#include "volume/lane_grid-inl.hpp"
#include "volume/lane_kernel-inl.hpp"
#include "volume/lanes-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {
namespace {

namespace hn = hwy::HWY_NAMESPACE;
using namespace lanes;
constexpr int kMaxLights = RayShading::kMaxLights;
constexpr int kMaxLookDelay = 4;  // steps a lane that left its occupied brick may march on

// GradientVolume::sample in lanes. Packed layout: one 32-bit word per corner, the fields split
// by shifts. Int16 layout: the x-neighbours c and c + 1 are 12 adjacent bytes, three words,
// (x0, y0), (z0, x1) and (y1, z1), split into their 16-bit halves: three fetches per pair.
class LaneGradients {
 public:
  explicit LaneGradients(const GradientVolume& g)
      : words_(g.words()),
        int16_(g.data()),
        packed_(g.packed()),
        lattice_(g.dims()),
        scale_(g.scale()) {}

  void sample(VF px, VF py, VF pz, VF& gx, VF& gy, VF& gz) const {
    VF fx, fy, fz;
    const VI base = lattice_.locate(px, py, pz, fx, fy, fz);
    const VI sy = lattice_.sy(), sz = lattice_.sz();
    const VI one = splat(1);
    const VI corner[8] = {base,
                          hn::Add(base, one),
                          hn::Add(base, sy),
                          hn::Add(hn::Add(base, sy), one),
                          hn::Add(base, sz),
                          hn::Add(hn::Add(base, sz), one),
                          hn::Add(hn::Add(base, sz), sy),
                          hn::Add(hn::Add(hn::Add(base, sz), sy), one)};
    VF cx[8], cy[8], cz[8];
    if (packed_) {
      for (int c = 0; c < 8; ++c) {
        const VI w = gather_words<4>(words_, corner[c]);
        cx[c] = hn::ConvertTo(DF(), hn::ShiftRight<22>(hn::ShiftLeft<22>(w)));
        cy[c] = hn::ConvertTo(DF(), hn::ShiftRight<22>(hn::ShiftLeft<12>(w)));
        cz[c] = hn::ConvertTo(DF(), hn::ShiftRight<22>(hn::ShiftLeft<2>(w)));
      }
    } else {
      // The voxel pair (c, c + 1) of each lane: 12 bytes from voxel c, inside for the last pair
      // too (c + 1 is at most the last voxel), as three words.
      for (int k = 0; k < 4; ++k) {
        const VI at = hn::Mul(corner[2 * k], splat(3));  // in int16 entries
        const VI w0 = gather_words<2>(int16_, at);
        const VI w1 = gather_words<2>(int16_, hn::Add(at, splat(2)));
        const VI w2 = gather_words<2>(int16_, hn::Add(at, splat(4)));
        const int c = 2 * k;
        cx[c] = hn::ConvertTo(DF(), low_half<int16_t>(w0));
        cy[c] = hn::ConvertTo(DF(), high_half<int16_t>(w0));
        cz[c] = hn::ConvertTo(DF(), low_half<int16_t>(w1));
        cx[c + 1] = hn::ConvertTo(DF(), high_half<int16_t>(w1));
        cy[c + 1] = hn::ConvertTo(DF(), low_half<int16_t>(w2));
        cz[c + 1] = hn::ConvertTo(DF(), high_half<int16_t>(w2));
      }
    }
    const VF scale = splat(scale_);
    gx = hn::Mul(trilinear(cx, fx, fy, fz), scale);
    gy = hn::Mul(trilinear(cy, fx, fy, fz), scale);
    gz = hn::Mul(trilinear(cz, fx, fy, fz), scale);
  }

 private:
  const uint32_t* words_;
  const int16_t* int16_;
  bool packed_;
  LaneLattice lattice_;
  float scale_;
};

// The labels of the eight voxels around points in lanes (c000, c100, c010, c110, c001, c101,
// c011, c111, as label_of() reads them), with LaneGrid's clamp and fetches (LaneGrid::corners).
template <class T>
class LaneLabelCells {
 public:
  explicit LaneLabelCells(const VoxelGrid<T>& g) : data_(g.data), grid_(g) {}

  void cell(VF px, VF py, VF pz, VI c[8], VF& fx, VF& fy, VF& fz) const {
    grid_.corners(px, py, pz, c, fx, fy, fz);
  }

  // label_gradient in lanes for 8-bit labels where every lane of `vis` lies at least a voxel
  // inside the grid (p in [1, dims - 2) on every axis), so that no fetch is clamped: the six
  // indicator cells around p read 12 rows of four x-neighbours (x0 - 1 .. x0 + 2), one 32-bit
  // word each, instead of 24 fetches. False (nothing computed) elsewhere or for other types.
  bool interior_gradient(MF vis, VF px, VF py, VF pz, VI label, VF& gx, VF& gy, VF& gz) const {
    if constexpr (sizeof(T) != 1) {
      (void)vis, (void)px, (void)py, (void)pz, (void)label, (void)gx, (void)gy, (void)gz;
      return false;
    } else {
      const LaneLattice& lattice = grid_.lattice();
      const MF inside = lattice.interior(px, py, pz);
      const unsigned v = bits_of(vis);
      if ((bits_of(inside) & v) != v) return false;
      VF fx, fy, fz;
      VI base = lattice.locate(px, py, pz, fx, fy, fz);
      // Lanes not shaded read a safe interior row instead.
      base = hn::IfThenElse(to_int(inside), base, splat(lattice.interior_base()));
      const int sy = lattice.stride_y(), sz = lattice.stride_z();
      const VI at = hn::Sub(base, splat(1));
      // The label in every byte: a byte compare then flags the voxels that hold it.
      const VI pattern = hn::Mul(label, splat(0x01010101));
      // Bit 8k of a row's flags: voxel x0 - 1 + k holds the label.
      auto row = [&](int dy, int dz) HWY_ATTR {
        const VI w = gather_words<1>(data_, hn::Add(at, splat(sy * dy + sz * dz)));
#if HWY_TARGET == HWY_SCALAR
        // One lane: the zero bytes of w ^ pattern, found without carries between bytes.
        const VU x = hn::BitCast(DU(), hn::Xor(w, pattern));
        const VU low7 = hn::Set(DU(), 0x7f7f7f7fu);
        const VU nonzero = hn::Or(hn::Add(hn::And(x, low7), low7), x);
        return hn::BitCast(DI(),
                           hn::ShiftRight<7>(hn::AndNot(nonzero, hn::Set(DU(), 0x80808080u))));
#else
        const hn::Repartition<uint8_t, DI> d8;
        return hn::BitCast(
            DI(), hn::VecFromMask(d8, hn::Eq(hn::BitCast(d8, w), hn::BitCast(d8, pattern))));
#endif
      };
      // Voxel x0 - 1 + k of a row as 0 or 1.
      auto is = [](VI eq, int k) HWY_ATTR {
        return hn::ConvertTo(DF(), hn::And(hn::ShiftRightSame(eq, 8 * k), splat(1)));
      };
      // The indicator of a cell from its four rows (y, z order) and its first x byte.
      auto cell = [&](VI r00, VI r10, VI r01, VI r11, int k) HWY_ATTR {
        const VF c[8] = {is(r00, k), is(r00, k + 1), is(r10, k), is(r10, k + 1),
                         is(r01, k), is(r01, k + 1), is(r11, k), is(r11, k + 1)};
        return trilinear(c, fx, fy, fz);
      };
      const VI r00 = row(0, 0), r10 = row(1, 0), r01 = row(0, 1), r11 = row(1, 1);
      const VI ym0 = row(-1, 0), ym1 = row(-1, 1), yp0 = row(2, 0), yp1 = row(2, 1);
      const VI zm0 = row(0, -1), zm1 = row(1, -1), zp0 = row(0, 2), zp1 = row(1, 2);
      const VF half = splat(0.5f);
      gx = hn::Mul(half, hn::Sub(cell(r00, r10, r01, r11, 2), cell(r00, r10, r01, r11, 0)));
      gy = hn::Mul(half, hn::Sub(cell(r10, yp0, r11, yp1, 1), cell(ym0, r00, ym1, r01, 1)));
      gz = hn::Mul(half, hn::Sub(cell(r01, r11, zp0, zp1, 1), cell(zm0, zm1, r00, r10, 1)));
      return true;
    }
  }

  // label_indicator in lanes: the trilinear interpolation of (voxel == label).
  VF indicator(VF px, VF py, VF pz, VI label) const {
    VI c[8];
    VF fx, fy, fz;
    cell(px, py, pz, c, fx, fy, fz);
    VF is[8];
    for (int k = 0; k < 8; ++k)
      is[k] = hn::IfThenElseZero(to_float(hn::Eq(c[k], label)), splat(1.0f));
    return trilinear(is, fx, fy, fz);
  }

 private:
  const T* data_;
  LaneGrid<T> grid_;
};

// kPackOrder[m]: the set bits of m in rising order, a nibble each from the lowest: the
// permutation that packs the lanes of mask m to the front, for up to eight lanes.
constexpr std::array<uint32_t, 256> kPackOrder = [] {
  std::array<uint32_t, 256> t{};
  for (unsigned m = 0; m < 256; ++m)
    for (unsigned l = 0, n = 0; l < 8; ++l)
      if (m >> l & 1) t[m] |= l << (4 * n++);
  return t;
}();

// The lanes of `m` packed to the front, in lane order, as lane indices (what hn::Compress does
// to Iota). Up to eight lanes from kPackOrder: Highway 1.0's Compress for AVX2 vectors copies
// its 1 KiB table onto the stack at every call (GCC 12), which about doubled the AVX2 frame
// times of FLAIR and the bone CT; AVX-512 has an instruction for it.
HWY_INLINE VI pack_order(MF m) {
  if constexpr (kLanes > 8) {
    return hn::Compress(hn::Iota(DI(), 0), to_int(m));
  } else {
    const VU packed = hn::Set(DU(), kPackOrder[bits_of(m)]);
    const VU shift = hn::ShiftLeft<2>(hn::BitCast(DU(), hn::Iota(DI(), 0)));
    return hn::BitCast(DI(), hn::And(hn::Shr(packed, shift), hn::Set(DU(), 0xfu)));
  }
}

// The per-lane state, structure of arrays so that a step loads whole vectors.
struct Lanes {
  HWY_ALIGN float ox[kLanes], oy[kLanes], oz[kLanes];  // the ray in index space, same parameter t
  HWY_ALIGN float dx[kLanes], dy[kLanes], dz[kLanes];
  HWY_ALIGN float front[kLanes];      // where the next piece starts
  HWY_ALIGN float t1[kLanes];         // where the span ends
  HWY_ALIGN float next_cell[kLanes];  // k + 1 for the grid cell [k, k + 1) * step holding `front`
  HWY_ALIGN float s_front[kLanes];    // the scalar at `front`, valid where have_front is set
  HWY_ALIGN int32_t have_front[kLanes];
  HWY_ALIGN int32_t label_front[kLanes];   // label volumes: the winning label at `front`
  HWY_ALIGN float occupied_until[kLanes];  // the lane is in an occupied brick up to here
  HWY_ALIGN float r[kLanes], g[kLanes], b[kLanes], a[kLanes];
  HWY_ALIGN float ex[kLanes], ey[kLanes], ez[kLanes];  // toward the eye, world space
  HWY_ALIGN float lx[kMaxLights][kLanes], ly[kMaxLights][kLanes], lz[kMaxLights][kLanes];
  HWY_ALIGN float hx[kMaxLights][kLanes], hy[kMaxLights][kLanes], hz[kMaxLights][kLanes];
  HWY_ALIGN int32_t ray[kLanes];
};

// Visible pieces waiting to be shaded, packed (PacketKernel::defer): room for one more step's
// lanes after at most kLanes - 1 left over.
struct ShadeQueue {
  enum Field {
    kW,
    kR,
    kG,
    kB,
    kA,
    kAx,
    kAy,
    kAz,
    kBx,
    kBy,
    kBz,
    kLane,
    kTwo,
    kSf,
    kSb,
    kT0,
    kT1,
    kCentre,
    kFields
  };
  // kW: the weight over() gives the piece's colour; kLane (an int32 bit pattern): the lane of its
  // ray; kTwo: all ones where it is shaded at two points. A composite needs the fields up to
  // kTwo; a sink's slab (PacketKernel::collect) also the piece's scalars, span and light centre.
  static constexpr int kCompositeFields = kTwo + 1;
  HWY_ALIGN float field[kFields][2 * kLanes] = {};
  int count = 0;
};

// Whose eye and light directions the lanes of a shading take: lane k those of the ray in lane
// from[k] (the shading queue's pieces), or its own (`own`).
struct RayOf {
  VI from;
  bool own;
};
HWY_INLINE RayOf own_rays() {
  return {hn::Zero(DI()), true};
}

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
    defer_ = shaded_ && !labels_;
    for (int k = 0; k < kAlphaCache; ++k) cached_label_[k] = k + 1;  // no label maps to slot k
    light_count_ = static_cast<int>(lights.size());
    if (v.accel.emptiness) use_runs_ = v.accel.emptiness->value_runs(run_lo_, run_hi_);
    if (v.accel.occupancy) bricks_.emplace(*v.accel.occupancy, v.accel.skip);
  }

  // Packets of kLanes rays in batch order, each marched until all its rays are done. Refilling
  // each lane as soon as its ray ends kept the lanes fuller but was slower (FLAIR 41 against
  // 37.5 ms, ct-head 39 against 37.5, with AVX2): scattered scalar set-up and incoherent lanes.
  void run() {
    for (;;) {
      unsigned live = fill();
      look_delay_ = 0;
      if (!live) return;
      const unsigned packet = live;
      while (live) {
        const unsigned lit = labels_ ? step_labels(live) : step(live);
        const MF active = lane_mask(live);
        const MF ended = hn::Or(hn::Not(hn::Lt(load(L_.front), load(L_.t1))),
                                hn::Not(hn::Lt(load(L_.a), splat(ert_))));
        unsigned done = bits_of(hn::And(ended, active));
        if (bricks_) {
          // Lanes that left their occupied brick look for the next one, but not at once:
          // - those whose last piece was visible are in matter and look at their next
          //   transparent piece (FLAIR 1.5 ms faster);
          // - the others keep marching until every such lane needs a look or the first has
          //   waited kMaxLookDelay steps. A walk costs the same for one lane as for all and
          //   several times a step, and the next brick is mostly occupied anyway (ct-head and
          //   FLAIR about 7% faster than when only a lone lane waited, for one step, in AVX2).
          // A deferred look marches pieces a look would have skipped: they are transparent
          // unless one spans two empty bricks whose value ranges straddle a visible value, as
          // plain marching has it too (no 8-bit image here changed).
          const MF look = hn::Ge(load(L_.front), load(L_.occupied_until));
          const unsigned open = live & ~lit & ~done;
          const unsigned m = bits_of(look) & open;
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
        const MF none = hn::Not(hn::Lt(load(L_.front), load(L_.t1)));
        empty = fresh & bits_of(none);
        if (bricks_ && (fresh & ~empty)) {
          // The lanes' rays for the brick walk, kept until the packet is filled again.
          const float* const origin[3] = {L_.ox, L_.oy, L_.oz};
          const float* const dir[3] = {L_.dx, L_.dy, L_.dz};
          bricks_->rays(origin, dir, brick_rays_);
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
    declined_ &= ~(1u << l);
  }

  // VolumeMarcher::skip_empty for the lanes in m (fresh ones, or ones past their occupied
  // brick): each finds the next occupied brick, moves to the last grid point before it if that
  // lies beyond the piece it is in, and looks again once it leaves that brick. Returns the lanes
  // with nothing left to march.
  unsigned settle(unsigned m) {
    const VF front = load(L_.front), t1 = load(L_.t1);
    VF enter = t1, leave = load(L_.occupied_until);
    const unsigned none = bricks_->first_occupied(brick_rays_, m, front, t1, enter, leave);
    const MF walked = lane_mask(m & ~none);
    store(hn::IfThenElse(walked, leave, load(L_.occupied_until)), L_.occupied_until);
    // As VolumeMarcher: resume at the grid point at or before the brick, unless that is still
    // inside the current piece.
    const VF next_cell = load(L_.next_cell), step = splat(step_);
    const VF back = hn::Min(t1, hn::Mul(next_cell, step));
    const MF jump = hn::And(walked, hn::Ge(enter, back));
    if (hn::AllFalse(DF(), jump)) return none;
    const VF inv_step = splat(1.0f / step_);
    const VF to = hn::Max(back, hn::Mul(hn::Floor(hn::Mul(enter, inv_step)), step));
    VF cell = hn::Floor(hn::Mul(to, inv_step));
    const VF one = splat(1.0f);
    cell = hn::Add(cell, hn::IfThenElseZero(hn::Le(hn::Mul(hn::Add(cell, one), step), to), one));
    store(hn::IfThenElse(jump, to, front), L_.front);
    store(hn::IfThenElse(jump, hn::Add(cell, one), next_cell), L_.next_cell);
    store(hn::IfThenZeroElse(to_int(jump), load(L_.have_front)), L_.have_front);
    // A lane moved to the end of its span has nothing left (no zero-length piece).
    const MF at_end = hn::And(jump, hn::Ge(to, t1));
    return none | bits_of(at_end);
  }

  // One piece in every live lane: sample, range test, classify, shade, composite. Returns the
  // lanes whose piece was visible.
  unsigned step(unsigned live) {
    const MF active = lane_mask(live);
    const VF ox = load(L_.ox), oy = load(L_.oy), oz = load(L_.oz);
    const VF dx = load(L_.dx), dy = load(L_.dy), dz = load(L_.dz);
    const VF front = load(L_.front), next_cell = load(L_.next_cell);
    const VF back = hn::Min(load(L_.t1), hn::Mul(next_cell, splat(step_)));
    const VF s_b =
        grid_.sample(hn::MulAdd(back, dx, ox), hn::MulAdd(back, dy, oy), hn::MulAdd(back, dz, oz));
    VF s_f = load(L_.s_front);
    const MF need_front = hn::AndNot(to_float(hn::MaskFromVec(load(L_.have_front))), active);
    if (!hn::AllFalse(DF(), need_front)) {
      const VF s = grid_.sample(hn::MulAdd(front, dx, ox), hn::MulAdd(front, dy, oy),
                                hn::MulAdd(front, dz, oz));
      s_f = hn::IfThenElse(need_front, s, s_f);
    }
    const VF len = hn::Sub(back, front);
    store(back, L_.front);
    store(hn::Add(next_cell, splat(1.0f)), L_.next_cell);
    store(s_b, L_.s_front);
    store(splat(-1), L_.have_front);

    // The range test of VolumeMarcher::next_in.
    MF vis = active;
    if (use_runs_) {
      vis = hn::AndNot(empty_between(s_f, s_b), vis);
    } else if (v_.accel.emptiness) {
      HWY_ALIGN float f[kLanes], b[kLanes];
      store(s_f, f);
      store(s_b, b);
      unsigned keep = live;
      for (unsigned m = live; m; m &= m - 1) {
        int l = __builtin_ctz(m);
        if (v_.accel.emptiness->is_empty_between(f[l], b[l])) keep &= ~(1u << l);
      }
      vis = lane_mask(keep);
    }
    // A piece with no data at an end is transparent (VolumeMarcher::next_in).
    if constexpr (NoData) vis = hn::AndNot(hn::Or(no_data_lanes(s_f), no_data_lanes(s_b)), vis);
    if (hn::AllFalse(DF(), vis)) return 0;

    VF cr, cg, cb, ca;
    lookup(s_f, s_b, cr, cg, cb, ca);
    vis = hn::And(vis, hn::Gt(ca, hn::Zero(DF())));
    if (hn::AllFalse(DF(), vis)) return 0;
    // Where the light comes from, from the table's moments before the short-piece correction,
    // as PreintegrationView::lookup(s_f, s_b, light) in VolumeMarcher::classify.
    VF centre = splat(0.5f), spread = hn::Zero(DF());
    if (centre_ && (shaded_ || sink_)) light_of(s_f, s_b, ca, centre, spread);
    const MF short_piece = hn::And(vis, hn::Not(hn::Ge(len, splat(0.9999f * step_))));
    if (!hn::AllFalse(DF(), short_piece)) correct_short(short_piece, len, cr, cg, cb, ca);
    if (shaded_) {
      // VolumeMarcher::shade: one point (the midpoint, or the light's centre) or, where the
      // light is spread, the mean of two points a standard deviation either side of it.
      const MF two = hn::And(vis, hn::Ge(spread, splat(kMinSpread)));
      const VF u_a = hn::IfThenElse(two, hn::Max(hn::Zero(DF()), hn::Sub(centre, spread)), centre);
      const VF t_a = hn::MulAdd(u_a, len, front);
      const VF u_b = hn::Min(splat(1.0f), hn::Add(centre, spread));
      const VF t_b = hn::MulAdd(u_b, len, front);
      const Points at{{hn::MulAdd(t_a, dx, ox), hn::MulAdd(t_a, dy, oy), hn::MulAdd(t_a, dz, oz)},
                      {hn::MulAdd(t_b, dx, ox), hn::MulAdd(t_b, dy, oy), hn::MulAdd(t_b, dz, oz)}};
      // A step with more than half its lanes visible shades them at once: packing them into the
      // queue costs more than the idle lanes it would fill (MR T2-Brain on avg152T1, AVX3: 34.8
      // against 27.3 ms; the bone CTs 6-15% faster). Pieces still queued are shaded first, so
      // that every ray adds its pieces' colours in its order, whatever the lane count: AVX2 and
      // AVX3 give the same bytes as with the queue alone. A sink still takes every piece through
      // the queue: in place, the implants and fusion scenes took 1.02-1.05x as long.
      const bool dense = 2 * __builtin_popcount(bits_of(vis)) > kLanes;
      if (defer_ && (sink_ || !dense)) {
        // The opacity composites now (ERT reads it), the colour once kLanes pieces wait.
        const VF aa = load(L_.a);
        const VF w = hn::Sub(splat(1.0f), aa);
        store(hn::IfThenElse(vis, hn::MulAdd(w, ca, aa), aa), L_.a);
        defer(vis, two, w, cr, cg, cb, ca, at, {s_f, s_b, front, back, centre});
        return bits_of(vis);
      }
      if (queue_.count) shade_queued(queue_.count), queue_.count = 0;
      shade_points(vis, two, own_rays(), at, cr, cg, cb, ca);
    }
    if (sink_) collect(vis, s_f, s_b, front, back, centre, cr, cg, cb, ca);
    composite(vis, cr, cg, cb, ca);
    return bits_of(vis);
  }

  // Where a piece is shaded: one point, and a second one where its light is spread.
  struct Points {
    VF a[3], b[3];
  };
  // What collect() makes a sink's slab of besides the colour: the scalars at the piece's ends,
  // its span and its light's centre.
  struct Piece {
    VF s_f, s_b, front, back, centre;
  };

  // The shading of pieces in lanes: at point a where `two` is clear, else the mean of a and b.
  void shade_points(MF vis, MF two, const RayOf& from, const Points& at, VF& cr, VF& cg, VF& cb,
                    VF ca) const {
    VF r2 = cr, g2 = cg, b2 = cb;
    shade(vis, from, at.a[0], at.a[1], at.a[2], cr, cg, cb, ca);
    if (!hn::AllFalse(DF(), two)) {
      shade(two, from, at.b[0], at.b[1], at.b[2], r2, g2, b2, ca);
      const VF half = splat(0.5f);
      cr = hn::IfThenElse(two, hn::Mul(half, hn::Add(cr, r2)), cr);
      cg = hn::IfThenElse(two, hn::Mul(half, hn::Add(cg, g2)), cg);
      cb = hn::IfThenElse(two, hn::Mul(half, hn::Add(cb, b2)), cb);
    }
  }

  // Puts the visible pieces of `vis` in the shading queue, packed in lane order, and shades the
  // first kLanes once that many wait. Many steps shade only a few lanes on real scans (4.5 of 8
  // on average on a CT with the bone preset): the queue fills every lane of each shading. With a
  // sink, the slabs go to it once shaded, each ray's in its order.
  void defer(MF vis, MF two, VF w, VF cr, VF cg, VF cb, VF ca, const Points& at,
             const Piece& piece) {
    const VF fields[ShadeQueue::kFields] = {w,
                                            cr,
                                            cg,
                                            cb,
                                            ca,
                                            at.a[0],
                                            at.a[1],
                                            at.a[2],
                                            at.b[0],
                                            at.b[1],
                                            at.b[2],
                                            hn::BitCast(DF(), hn::Iota(DI(), 0)),
                                            hn::VecFromMask(DF(), two),
                                            piece.s_f,
                                            piece.s_b,
                                            piece.front,
                                            piece.back,
                                            piece.centre};
    const int used = sink_ ? ShadeQueue::kFields : ShadeQueue::kCompositeFields;
    // The visible lanes first, in lane order; the lanes past them are overwritten later.
    const auto order = hn::IndicesFromVec(DF(), pack_order(vis));
    for (int f = 0; f < used; ++f)
      hn::StoreU(hn::TableLookupLanes(fields[f], order), DF(), &queue_.field[f][queue_.count]);
    queue_.count += __builtin_popcount(bits_of(vis));
    if (queue_.count < kLanes) return;
    shade_queued(kLanes);
    queue_.count -= kLanes;
    for (int f = 0; f < used; ++f)
      store(hn::LoadU(DF(), &queue_.field[f][kLanes]), queue_.field[f]);
  }

  // Shades the first n queued pieces and adds their colour to their rays, in queue order (each
  // ray's pieces in ray order): acc.rgb += w * colour, as over() would have at the piece; with a
  // sink, gives it their slabs in that order instead.
  void shade_queued(int n) {
    const auto field = [&](int f) HWY_ATTR { return load(queue_.field[f]); };
    const MF valid = lane_mask((1u << n) - 1);
    const VI from = hn::BitCast(DI(), field(ShadeQueue::kLane));
    const Points at{{field(ShadeQueue::kAx), field(ShadeQueue::kAy), field(ShadeQueue::kAz)},
                    {field(ShadeQueue::kBx), field(ShadeQueue::kBy), field(ShadeQueue::kBz)}};
    VF cr = field(ShadeQueue::kR), cg = field(ShadeQueue::kG), cb = field(ShadeQueue::kB);
    shade_points(valid, hn::And(valid, hn::MaskFromVec(field(ShadeQueue::kTwo))), {from, false}, at,
                 cr, cg, cb, field(ShadeQueue::kA));
    HWY_ALIGN float r[kLanes], g[kLanes], b[kLanes];
    HWY_ALIGN int32_t lane[kLanes];
    store(cr, r), store(cg, g), store(cb, b);
    store(from, lane);
    if (sink_) {
      const auto* q = queue_.field;
      for (int k = 0; k < n; ++k)
        collect_one(lane[k], q[ShadeQueue::kSf][k], q[ShadeQueue::kSb][k], q[ShadeQueue::kT0][k],
                    q[ShadeQueue::kT1][k], q[ShadeQueue::kCentre][k],
                    glm::vec4(r[k], g[k], b[k], q[ShadeQueue::kA][k]));
      return;
    }
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
  void collect(MF vis, VF s_f, VF s_b, VF front, VF back, VF centre, VF cr, VF cg, VF cb, VF ca) {
    HWY_ALIGN float f[kLanes], b[kLanes], t0[kLanes], t1[kLanes], at[kLanes];
    HWY_ALIGN float r[kLanes], g[kLanes], bl[kLanes], a[kLanes];
    store(s_f, f), store(s_b, b), store(centre, at);
    store(front, t0), store(back, t1);
    store(cr, r), store(cg, g), store(cb, bl), store(ca, a);
    for (unsigned m = bits_of(vis); m; m &= m - 1) {
      const int l = __builtin_ctz(m);
      collect_one(l, f[l], b[l], t0[l], t1[l], at[l], glm::vec4(r[l], g[l], bl[l], a[l]));
    }
  }

  // One piece of the ray in lane l to the sink, unless the sink has declined that ray: a piece
  // the queue held past the decline is dropped.
  void collect_one(int l, float s_f, float s_b, float front, float back, float centre,
                   const glm::vec4& colour) {
    if (declined_ >> l & 1u) return;
    double lo = front, hi = back;
    if (trim_) trim_to_light(*v_.accel.emptiness, s_f, s_b, centre, lo, hi);
    const Slab slab = Slab::between(static_cast<float>(lo), static_cast<float>(hi), colour);
    if (!sink_->take(static_cast<size_t>(L_.ray[l]), slab)) {
      L_.t1[l] = -INFINITY;
      declined_ |= 1u << l;
    }
  }

  // One piece of a label volume in every live lane, as VolumeMarcher::next_label_in_piece:
  // the winners at the grid points; a piece whose ends agree is one slab of that label, shaded
  // in lanes at its midpoint by the label's indicator gradient; one whose ends differ splits at
  // the bisected boundary, per lane (rare: boundaries only). Returns the lanes with a visible
  // slab.
  unsigned step_labels(unsigned live) {
    const MF active = lane_mask(live);
    const VF ox = load(L_.ox), oy = load(L_.oy), oz = load(L_.oz);
    const VF dx = load(L_.dx), dy = load(L_.dy), dz = load(L_.dz);
    const VF front = load(L_.front), next_cell = load(L_.next_cell);
    const VF back = hn::Min(load(L_.t1), hn::Mul(next_cell, splat(step_)));
    const VI l_b =
        winners(hn::MulAdd(back, dx, ox), hn::MulAdd(back, dy, oy), hn::MulAdd(back, dz, oz), live);
    VI l_f = load(L_.label_front);
    const MF need_front = hn::AndNot(to_float(hn::MaskFromVec(load(L_.have_front))), active);
    if (const unsigned need = bits_of(need_front))
      l_f = hn::IfThenElse(to_int(need_front),
                           winners(hn::MulAdd(front, dx, ox), hn::MulAdd(front, dy, oy),
                                   hn::MulAdd(front, dz, oz), need),
                           l_f);
    const VF len = hn::Sub(back, front);
    store(back, L_.front);
    store(hn::Add(next_cell, splat(1.0f)), L_.next_cell);
    store(l_b, L_.label_front);
    store(splat(-1), L_.have_front);

    HWY_ALIGN int32_t lf[kLanes], lb[kLanes];
    HWY_ALIGN float fr[kLanes], bk[kLanes], ln[kLanes];
    HWY_ALIGN float cr[kLanes] = {}, cg[kLanes] = {}, cb[kLanes] = {}, ca[kLanes] = {};
    store(l_f, lf);
    store(l_b, lb);
    store(front, fr), store(back, bk), store(len, ln);
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
    const MF vis = lane_mask(whole);
    VF r = load(cr), g = load(cg), b = load(cb), a = load(ca);
    if (shaded_) {
      const VF t_mid = hn::MulAdd(splat(0.5f), len, front);
      const VF px = hn::MulAdd(t_mid, dx, ox), py = hn::MulAdd(t_mid, dy, oy),
               pz = hn::MulAdd(t_mid, dz, oz);
      // label_gradient in lanes: central differences of the label's indicator.
      VF gx, gy, gz;
      if (!cells_.interior_gradient(vis, px, py, pz, l_b, gx, gy, gz)) {
        const VF one = splat(1.0f), half = splat(0.5f);
        gx = hn::Mul(half, hn::Sub(cells_.indicator(hn::Add(px, one), py, pz, l_b),
                                   cells_.indicator(hn::Sub(px, one), py, pz, l_b)));
        gy = hn::Mul(half, hn::Sub(cells_.indicator(px, hn::Add(py, one), pz, l_b),
                                   cells_.indicator(px, hn::Sub(py, one), pz, l_b)));
        gz = hn::Mul(half, hn::Sub(cells_.indicator(px, py, hn::Add(pz, one), l_b),
                                   cells_.indicator(px, py, hn::Sub(pz, one), l_b)));
      }
      shade_gradient(vis, own_rays(), gx, gy, gz, r, g, b, a);
    }
    composite(vis, r, g, b, a);
    return lit | whole;
  }

  // winning_label at the lanes' points, for the lanes in m: the common label where all eight
  // voxels around a point agree (most points), else the scalar classifier.
  VI winners(VF px, VF py, VF pz, unsigned m) const {
    HWY_ALIGN int32_t out[kLanes] = {};
    unsigned mixed = m;
    if (!nearest_) {
      VI c[8];
      VF fx, fy, fz;
      cells_.cell(px, py, pz, c, fx, fy, fz);
      MI same = hn::Eq(c[1], c[0]);
      for (int k = 2; k < 8; ++k) same = hn::And(same, hn::Eq(c[k], c[0]));
      mixed &= ~bits_of(to_float(same));
      if (!mixed) return c[0];
      store(c[0], out);
    }
    HWY_ALIGN float x[kLanes], y[kLanes], z[kLanes];
    store(px, x), store(py, y), store(pz, z);
    for (; mixed; mixed &= mixed - 1) {
      const int l = __builtin_ctz(mixed);
      out[l] = winning_label(voxels_, glm::vec3(x[l], y[l], z[l]), nearest_);
    }
    return load(out);
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
  void composite(MF vis, VF cr, VF cg, VF cb, VF ca) {
    const VF ar = load(L_.r), ag = load(L_.g), ab = load(L_.b), aa = load(L_.a);
    const VF w = hn::Sub(splat(1.0f), aa);
    store(hn::IfThenElse(vis, hn::MulAdd(w, cr, ar), ar), L_.r);
    store(hn::IfThenElse(vis, hn::MulAdd(w, cg, ag), ag), L_.g);
    store(hn::IfThenElse(vis, hn::MulAdd(w, cb, ab), ab), L_.b);
    store(hn::IfThenElse(vis, hn::MulAdd(w, ca, aa), aa), L_.a);
  }

  // TfEmptiness::is_empty_between in lanes (NaN ends as there: a NaN front is never empty, a
  // NaN back counts as the front).
  MF empty_between(VF a, VF b) const {
    b = hn::IfThenElse(hn::Eq(b, b), b, a);
    const VF lo = hn::Min(a, b), hi = hn::Max(a, b);
    MF empty = hn::Not(all_lanes());
    for (int k = 0; k < TfEmptiness::kMaxRuns; ++k)
      empty = hn::Or(empty, hn::And(hn::Ge(lo, splat(run_lo_[k])), hn::Le(hi, splat(run_hi_[k]))));
    return hn::And(empty, hn::Eq(a, a));
  }

  // The table cell of (s_f, s_b) in a pre-integration table's layout: the entry of its lower
  // corner and the fractions toward the upper one (PreintegrationView::axis: max(x, 0) returns
  // 0 for a NaN x).
  void table_cell(VF s_f, VF s_b, int32_t* entry, float* wx, float* wy) const {
    const VF lo = splat(preint_.lo), inv = splat(preint_.inv_step);
    const VF last = splat(static_cast<float>(preint_.size - 1));
    const VI last_cell = splat(preint_.size - 2);
    const VF zero = hn::Zero(DF());
    const VF x = hn::Min(hn::Max(hn::Mul(hn::Sub(s_f, lo), inv), zero), last);
    const VF y = hn::Min(hn::Max(hn::Mul(hn::Sub(s_b, lo), inv), zero), last);
    const VI i = hn::Min(hn::ConvertTo(DI(), x), last_cell);
    const VI j = hn::Min(hn::ConvertTo(DI(), y), last_cell);
    store(hn::Add(hn::Mul(i, splat(preint_.size)), j), entry);
    store(hn::Sub(x, hn::ConvertTo(DF(), i)), wx);
    store(hn::Sub(y, hn::ConvertTo(DF(), j)), wy);
  }

  // PreintegrationView::lookup(s_f, s_b) in lanes: per lane, entries j and j + 1 of rows i and
  // i + 1, lerped across the rows and then between the entries.
  void lookup(VF s_f, VF s_b, VF& r, VF& g, VF& b, VF& a) const {
    HWY_ALIGN int32_t entry[kLanes];
    HWY_ALIGN float wx[kLanes], wy[kLanes];
    table_cell(s_f, s_b, entry, wx, wy);
    const float* table = reinterpret_cast<const float*>(preint_.data);
    const size_t row = 4 * static_cast<size_t>(preint_.size);
#if HWY_TARGET == HWY_SCALAR
    // One lane: the corners' components as vectors.
    const float* r0 = table + 4 * static_cast<size_t>(entry[0]);
    const VF fx = load(wx), fy = load(wy);
    VF out[4];
    for (int c = 0; c < 4; ++c) {
      const VF lo = lerp(splat(r0[c]), splat(r0[row + c]), fx);
      const VF hi = lerp(splat(r0[4 + c]), splat(r0[row + 4 + c]), fx);
      out[c] = lerp(lo, hi, fy);
    }
    r = out[0], g = out[1], b = out[2], a = out[3];
#else
    // Per lane one RGBA entry of four lanes, then a transpose.
    const hn::Full128<float> d4;
    HWY_ALIGN float e[4 * kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const float* r0 = table + 4 * static_cast<size_t>(entry[l]);
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
      // Entries j and j + 1 of a row in one 256-bit load.
      const hn::Full256<float> d8;
      const auto rows = lerp4(hn::LoadU(d8, r0), hn::LoadU(d8, r0 + row), hn::Set(d8, wx[l]));
      const auto lo = hn::LowerHalf(d4, rows), hi = hn::UpperHalf(d4, rows);
#else
      const auto fx = hn::Set(d4, wx[l]);
      const auto lo = lerp4(hn::LoadU(d4, r0), hn::LoadU(d4, r0 + row), fx);
      const auto hi = lerp4(hn::LoadU(d4, r0 + 4), hn::LoadU(d4, r0 + row + 4), fx);
#endif
      hn::Store(lerp4(lo, hi, hn::Set(d4, wy[l])), d4, e + 4 * l);
    }
    hn::LoadInterleaved4(DF(), e, r, g, b, a);
#endif
  }

  // PreintegrationView::light_of(a, the moments at (s_f, s_b)) in lanes: the centre and the
  // spread of where a piece's light comes from (0.5 and 0 where a is not positive).
  void light_of(VF s_f, VF s_b, VF a, VF& centre, VF& spread) const {
    HWY_ALIGN int32_t entry[kLanes];
    HWY_ALIGN float wx[kLanes], wy[kLanes];
    table_cell(s_f, s_b, entry, wx, wy);
    const float* table = reinterpret_cast<const float*>(preint_.moments);
    const size_t row = 2 * static_cast<size_t>(preint_.size);
    // Entries j and j + 1 of rows i and i + 1: the two moments of each, lerped across the rows,
    // then between the entries.
    VF m1, m2;
#if HWY_TARGET == HWY_SCALAR
    const float* r0 = table + 2 * static_cast<size_t>(entry[0]);
    const VF fx = load(wx), fy = load(wy);
    VF m[4];
    for (int c = 0; c < 4; ++c) m[c] = lerp(splat(r0[c]), splat(r0[row + c]), fx);
    m1 = lerp(m[0], m[2], fy);
    m2 = lerp(m[1], m[3], fy);
#else
    const hn::Full128<float> d4;
    HWY_ALIGN float e[4 * kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const float* r0 = table + 2 * static_cast<size_t>(entry[l]);
      const auto m = lerp4(hn::LoadU(d4, r0), hn::LoadU(d4, r0 + row), hn::Set(d4, wx[l]));
      hn::Store(lerp4(m, hn::ConcatUpperUpper(d4, m, m), hn::Set(d4, wy[l])), d4, e + 4 * l);
    }
    VF unused0, unused1;
    hn::LoadInterleaved4(DF(), e, m1, m2, unused0, unused1);
#endif
    sample_formulas::light_of<LaneOps>(a, m1, m2, centre, spread);
  }
  static constexpr float kMinSpread = 1.0f / 64.0f;  // VolumeMarcher::kMinSpread

  // The opacity correction of pieces shorter than the table's step (span ends only: rare).
  void correct_short(MF mask, VF len, VF& r, VF& g, VF& b, VF& a) const {
    HWY_ALIGN float lr[kLanes], lg[kLanes], lb[kLanes], la[kLanes], ll[kLanes];
    store(r, lr), store(g, lg), store(b, lb), store(a, la);
    store(len, ll);
    for (unsigned m = bits_of(mask); m; m &= m - 1) {
      int l = __builtin_ctz(m);
      const float k = correct_opacity(la[l], ll[l], step_) / la[l];
      lr[l] *= k, lg[l] *= k, lb[l] *= k, la[l] *= k;
    }
    r = load(lr), g = load(lg), b = load(lb), a = load(la);
  }

  // RayShading::apply with the gradient at index-space point p, in lanes.
  void shade(MF vis, const RayOf& from, VF px, VF py, VF pz, VF& r, VF& g, VF& b, VF a) const {
    VF gx, gy, gz;
    if (gradients_) {
      gradients_->sample(px, py, pz, gx, gy, gz);
    } else if constexpr (NoData) {
      gradient_of_data(px, py, pz, gx, gy, gz);
    } else {
      grid_.gradient(px, py, pz, gx, gy, gz);
    }
    shade_gradient(vis, from, gx, gy, gz, r, g, b, a);
  }

  // RayShading::apply with the index-space gradient g, in lanes (the eye and light directions
  // of the rays `from` names).
  void shade_gradient(MF vis, const RayOf& from, VF gx, VF gy, VF gz, VF& r, VF& g, VF& b,
                      VF a) const {
    const auto order = hn::IndicesFromVec(DF(), from.from);
    const auto ray_field = [&](const float* f) HWY_ATTR {
      return from.own ? load(f) : hn::TableLookupLanes(load(f), order);
    };
    const glm::mat3& m = v_.gradient_to_world;
    const LaneOps::V3 n = {dot3(splat(m[0][0]), splat(m[1][0]), splat(m[2][0]), gx, gy, gz),
                           dot3(splat(m[0][1]), splat(m[1][1]), splat(m[2][1]), gx, gy, gz),
                           dot3(splat(m[0][2]), splat(m[1][2]), splat(m[2][2]), gx, gy, gz)};
    // The lights as sample_formulas::blinn_phong reads them, each lane's from its ray.
    struct Lights {
      const PacketKernel& kernel;
      const decltype(ray_field)& field;
      HWY_INLINE void light(int k, LaneOps::V3& l, LaneOps::V3& h) const {
        const Lanes& L = kernel.L_;
        l = {field(L.lx[k]), field(L.ly[k]), field(L.lz[k])};
        h = {field(L.hx[k]), field(L.hy[k]), field(L.hz[k])};
      }
      const glm::vec3& colour(int k) const { return kernel.lights_[k].color; }
      HWY_INLINE VF specular(VF x) const { return kernel.specular(x); }
    };
    LaneOps::V3 rgb = {r, g, b};
    sample_formulas::blinn_phong<LaneOps>(v_.object->shading, n,
                                          {ray_field(L_.ex), ray_field(L_.ey), ray_field(L_.ez)},
                                          Lights{*this, ray_field}, light_count_, vis, rgb, a);
    r = rgb.x, g = rgb.y, b = rgb.z;
  }

  // VoxelGrid::gradient_of_data in lanes: one-sided against the centre where a side is no data,
  // 0 where that is not possible either.
  void gradient_of_data(VF px, VF py, VF pz, VF& gx, VF& gy, VF& gz) const {
    const VF one = splat(1.0f), half = splat(0.5f), zero = hn::Zero(DF());
    const VF c = grid_.sample(px, py, pz);
    const MF centre = hn::Not(no_data_lanes(c));
    auto axis = [&](VF up, VF down) HWY_ATTR {
      const MF has_up = hn::AndNot(no_data_lanes(up), centre);
      const MF has_down = hn::AndNot(no_data_lanes(down), centre);
      const MF both = hn::AndNot(no_data_lanes(up), hn::Not(no_data_lanes(down)));
      VF g = hn::IfThenElse(has_down, hn::Sub(c, down), zero);
      g = hn::IfThenElse(has_up, hn::Sub(up, c), g);
      return hn::IfThenElse(both, hn::Mul(half, hn::Sub(up, down)), g);
    };
    gx = axis(grid_.sample(hn::Add(px, one), py, pz), grid_.sample(hn::Sub(px, one), py, pz));
    gy = axis(grid_.sample(px, hn::Add(py, one), pz), grid_.sample(px, hn::Sub(py, one), pz));
    gz = axis(grid_.sample(px, py, hn::Add(pz, one)), grid_.sample(px, py, hn::Sub(pz, one)));
  }

  // SpecularTable::operator() in lanes: the same table, two fetches and a lerp.
  VF specular(VF x) const {
    const SpecularTable::View t = v_.specular.view();
    const VF zero = hn::Zero(DF());
    const VF last = splat(static_cast<float>(SpecularTable::kEntries - 1));
    VF u = hn::Mul(hn::Sub(x, splat(t.x_min)), splat(t.inv_step));
    const MF above = hn::Gt(u, zero);  // false for NaN
    u = hn::Min(hn::Max(u, zero), last);
    const VI i = hn::ConvertTo(DI(), u);
    const VF f = hn::Sub(u, hn::ConvertTo(DF(), i));
    const VF lo = gather_floats(t.values, i);
    const VF hi = gather_floats(t.values, hn::Add(i, splat(1)));
    return hn::IfThenElseZero(above, lerp(lo, hi, f));
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
  bool defer_ = false;     // shading waits in queue_ (not for label volumes)
  unsigned declined_ = 0;  // lanes whose ray the sink declined
  ShadeQueue queue_;
  Lanes L_{};  // zeros in lanes that never get a ray
};

}  // namespace

// The lanes' march of `rays` on this target: composites into `out`, or with a sink, its slabs.
void march_packets_lanes(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                         std::span<const ShadingLight> lights, float ert, std::span<glm::vec4> out,
                         SlabExtent extent, SlabSink* sink) {
  run_lane_kernel<PacketKernel>(v, rays, step, lights, ert, out, extent, sink);
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace imx {
namespace {

HWY_EXPORT(march_packets_lanes);

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

// dot3 of lanes-inl.hpp on one ray: a.b with the same two fused steps.
float dot3(float ax, float ay, float az, float bx, float by, float bz) {
  return std::fma(az, bz, std::fma(ay, by, ax * bx));
}

// _mm256_max_ps and _mm256_min_ps of the lanes this replaced: the second operand where either
// is NaN.
float max_ps(float a, float b) {
  return a > b ? a : b;
}
float min_ps(float a, float b) {
  return a < b ? a : b;
}

}  // namespace

bool packet_marching_supported(const PreparedVolume& v, std::span<const ShadingLight> lights) {
  if (v.colours.active()) return false;  // a colour volume's colours: VolumeMarcher, ray by ray
  const glm::ivec3 d = v.grid.dims;
  const bool labels = v.labels.active();  // classified by label, not by a table
  if ((!labels && !v.accel.preint) || d.x < 2 || d.y < 2 || d.z < 2) return false;
  if (labels && v.has_no_data) return false;
  // Fetches take int32 indices: voxels, and the byte offsets of int16 gradients.
  const double voxels = static_cast<double>(d.x) * d.y * d.z;
  const bool int16_gradients = v.accel.gradients && !v.accel.gradients->packed();
  if (voxels * (int16_gradients ? 6.0 : 1.0) + 4.0 >= 2147483647.0) return false;
  // LaneBricks computes brick indices in floats, exact below 2^24 bricks.
  if (v.accel.occupancy && v.accel.occupancy->grid().count() >= (size_t{1} << 24)) return false;
  const Shading& s = v.object->shading;
  if (!s.enabled) return true;
  return lights.size() <= static_cast<size_t>(RayShading::kMaxLights) && !v.specular.exact();
}

PacketCamera::PacketCamera(const CameraModel& camera)
    : at_(camera.pixel_basis().at),
      per_x_(camera.pixel_basis().per_x),
      per_y_(camera.pixel_basis().per_y),
      eye_(camera.eye()),
      forward_(camera.forward()),
      perspective_(camera.perspective()),
      wide_(wide_scalar_available()) {}

// One ray at a time with the arithmetic the AVX2 lanes had (fused where they fused, in the same
// order), so that the rays, and the images, stay as they were on every target.
void PacketCamera::block(int x, int y, PacketRay* out, glm::vec2 at) const {
  run_wide_scalar(wide_, [&] {
    const float x0 = static_cast<float>(x) + at.x, y0 = static_cast<float>(y) + at.y;
    for (int l = 0; l < 8; ++l) {
      const float px = x0 + static_cast<float>(l % 4), py = y0 + static_cast<float>(l / 4);
      float v[3];
      for (int a = 0; a < 3; ++a) v[a] = std::fma(py, per_y_[a], std::fma(px, per_x_[a], at_[a]));
      if (perspective_) {
        const float inv = 1.0f / std::sqrt(dot3(v[0], v[1], v[2], v[0], v[1], v[2]));
        out[l].ray = Ray{eye_, glm::vec3(v[0] * inv, v[1] * inv, v[2] * inv)};
      } else {
        out[l].ray = Ray{glm::vec3(v[0], v[1], v[2]), forward_};
      }
    }
  });
}

// Groups of eight rays with the arithmetic the AVX2 lanes had (as PacketCamera::block), the
// rest with PreparedVolume::intersect as before, so that every ray's interval stays as it was.
// Each step runs over the group's eight rays (structure of arrays, no branches), which the
// compiler vectorizes.
void intersect_packets(const PreparedVolume& v, std::span<PacketRay> rays) {
  run_wide_scalar(v.wide_scalar, [&] {
    constexpr int kGroup = 8;
    const size_t grouped = rays.size() - rays.size() % kGroup;
    const glm::mat4& m = v.world_to_index;
    const glm::vec3 hi = glm::vec3(v.grid.dims - 1);
    const float tiny = 1e-12f;
    for (size_t first = 0; first < grouped; first += kGroup) {
      float o[3][kGroup], d[3][kGroup], t0[kGroup], t1[kGroup];
      int outside[kGroup];
      for (int l = 0; l < kGroup; ++l) {
        const Ray& ray = rays[first + static_cast<size_t>(l)].ray;
        for (int a = 0; a < 3; ++a) o[a][l] = ray.origin[a], d[a][l] = ray.dir[a];
        t0[l] = 0.0f, t1[l] = INFINITY, outside[l] = 0;
      }
      for (int a = 0; a < 3; ++a) {
        const float m0 = m[0][a], m1 = m[1][a], m2 = m[2][a], m3 = m[3][a], last = hi[a];
        for (int l = 0; l < kGroup; ++l) {
          // Row a of the index map: the ray's origin and direction in index space.
          const float io = std::fma(m2, o[2][l], std::fma(m1, o[1][l], std::fma(m0, o[0][l], m3)));
          const float id = dot3(m0, m1, m2, d[0][l], d[1][l], d[2][l]);
          const bool parallel = std::abs(id) < tiny;
          outside[l] |= parallel & ((io < 0.0f) | (io > last));
          const float inv = 1.0f / id;
          const float ta = (0.0f - io) * inv;
          const float tb = (last - io) * inv;
          const bool swap = ta > tb;
          const float near = swap ? tb : ta, far = swap ? ta : tb;
          // As std::max(t0, near) and std::min(t1, far): a NaN bound leaves the interval alone.
          t0[l] = parallel ? t0[l] : max_ps(near, t0[l]);
          t1[l] = parallel ? t1[l] : min_ps(far, t1[l]);
        }
      }
      for (const ClipPlane& c : v.object->clip_planes) {
        const glm::vec3 n(c.normal), p(c.point);
        for (int l = 0; l < kGroup; ++l) {
          const float side = dot3(o[0][l] - p.x, o[1][l] - p.y, o[2][l] - p.z, n.x, n.y, n.z);
          const float rate = dot3(d[0][l], d[1][l], d[2][l], n.x, n.y, n.z);
          const bool parallel = std::abs(rate) < tiny;
          outside[l] |= parallel & (side < 0.0f);
          const float t = -side / rate;
          t0[l] = !parallel && rate > 0.0f ? max_ps(t, t0[l]) : t0[l];
          t1[l] = !parallel && rate <= 0.0f ? min_ps(t, t1[l]) : t1[l];
        }
      }
      for (int l = 0; l < kGroup; ++l) {
        PacketRay& r = rays[first + static_cast<size_t>(l)];
        r.t0 = outside[l] ? 0.0f : t0[l];
        r.t1 = outside[l] ? -1.0f : t1[l];
      }
    }
    for (size_t i = grouped; i < rays.size(); ++i) {
      const RayInterval span = v.intersect(rays[i].ray);
      rays[i].t0 = span.t0, rays[i].t1 = span.t1;
    }
  });
}

void composite_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                       std::span<const ShadingLight> lights, float ert, std::span<glm::vec4> out,
                       SlabExtent extent) {
  if (packet_marching_supported(v, lights)) {
    apply_simd_environment();
    HWY_DYNAMIC_DISPATCH(march_packets_lanes)(v, rays, step, lights, ert, out, extent, nullptr);
    return;
  }
  composite_each(v, rays, step, lights, ert, out, extent);
}

void march_slab_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                        std::span<const ShadingLight> lights, float ert, SlabSink& sink) {
  if (packet_marching_supported(v, lights) && !v.labels.active()) {
    apply_simd_environment();
    HWY_DYNAMIC_DISPATCH(march_packets_lanes)
    (v, rays, step, lights, ert, std::span<glm::vec4>(), SlabExtent::visible, &sink);
    return;
  }
  // One ray at a time (label maps, what the lanes do not take): the lanes' pieces, empty ones
  // left out as the lanes leave out the invisible.
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
#endif  // HWY_ONCE
