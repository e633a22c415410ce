// LaneBricks: the empty-space brick walk of BrickDda for a packet of rays at once, in every SIMD
// target's lanes (lanes-inl.hpp).
#if defined(IMX_VOLUME_LANE_BRICKS_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef IMX_VOLUME_LANE_BRICKS_INL_HPP_
#undef IMX_VOLUME_LANE_BRICKS_INL_HPP_
#else
#define IMX_VOLUME_LANE_BRICKS_INL_HPP_
#endif

#include <cmath>

#include "volume/brick_occupancy.hpp"
#include "volume/lanes-inl.hpp"
#include "volume/volume_acceleration.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE::lanes {

// The brick walk of BrickDda in lanes. From each lane's position it finds the first occupied
// brick ahead, jumping over the cube of empty bricks ahead that a brick's distance toward the
// ray's octant vouches for (one brick at a time with SkipMode::bricks), and lands in the brick
// BrickDda::skip lands in: the exit axis steps past the cube's far face, the others take the
// brick at the exit point.
class LaneBricks {
 public:
  LaneBricks(const BrickOccupancy& occ, SkipMode mode)
      : distances_(occ.padded_distances()), by_distance_(mode == SkipMode::distance) {
    const glm::ivec3 d = occ.grid().dims;
    for (int a = 0; a < 3; ++a) inv_size_[a] = 1.0f / static_cast<float>(occ.grid().size[a]);
    stride_y_ = static_cast<float>(d.x);
    stride_z_ = static_cast<float>(d.x) * static_cast<float>(d.y);
    last_[0] = static_cast<float>(d.x - 1);
    last_[1] = static_cast<float>(d.y - 1);
    last_[2] = static_cast<float>(d.z - 1);
  }

  // One ray per lane, in brick units (index space / brick size, same parameter t as the
  // marcher). Axes the ray runs parallel to (|dir| < 1e-12 voxels, as BrickDda) never cross a
  // brick boundary: their inverse direction is infinite and their shift positive.
  struct Rays {
    HWY_ALIGN float origin[3][kLanes], dir[3][kLanes];
    HWY_ALIGN float inv_dir[3][kLanes];  // 1 / dir
    HWY_ALIGN float shift[3][kLanes];    // crossing brick j's far face at t = (j + shift) * inv_dir
    HWY_ALIGN float toward[3][kLanes];   // +1, -1 or 0: where the next brick along that axis is
    HWY_ALIGN int32_t backward[3][kLanes];  // all ones where the ray moves down that axis
    HWY_ALIGN float edge[3][kLanes];   // the brick after which the ray leaves the grid (-1: never)
    HWY_ALIGN int32_t octant[kLanes];  // BrickDda::octant(): which of a brick's distances applies
  };

  // The rays of a packet's origins and directions in index space (structure of arrays, aligned
  // as HWY_ALIGN).
  void rays(const float* const origin[3], const float* const dir[3], Rays& r) const {
    const VF zero = hn::Zero(DF()), one = splat(1.0f);
    VI octant = hn::Zero(DI());
    for (int a = 0; a < 3; ++a) {
      const VF o = hn::Mul(load(origin[a]), splat(inv_size_[a]));
      const VF d = load(dir[a]);
      const MF crosses = hn::Ge(hn::Abs(d), splat(1e-12f));
      const MF forward = hn::And(crosses, hn::Gt(d, zero));
      const MF backward = hn::AndNot(forward, crosses);
      const VF dir_bricks = hn::Mul(d, splat(inv_size_[a]));
      store(o, r.origin[a]);
      store(dir_bricks, r.dir[a]);
      store(hn::VecFromMask(DI(), to_int(backward)), r.backward[a]);
      store(hn::IfThenElse(crosses, hn::Div(one, dir_bricks), splat(INFINITY)), r.inv_dir[a]);
      store(hn::IfThenElse(crosses, hn::Sub(hn::IfThenElseZero(forward, one), o), one), r.shift[a]);
      store(hn::Or(hn::IfThenElseZero(forward, one), hn::IfThenElseZero(backward, splat(-1.0f))),
            r.toward[a]);
      store(hn::IfThenElse(crosses, hn::IfThenElseZero(forward, splat(last_[a])), splat(-1.0f)),
            r.edge[a]);
      octant = hn::Or(octant, hn::IfThenElseZero(to_int(backward), splat(1 << a)));
    }
    store(octant, r.octant);
  }

  // Every occupied brick counts (first_occupied's default).
  struct AnyOccupied {
    HWY_INLINE MF operator()(VI) const { return all_lanes(); }
  };

  // Where the lanes in `walk` meet their first occupied brick at or after `t`, before `t1`, that
  // `counts` (set lanes for the brick indices it is given) takes: `enter` gets the time the ray
  // enters it (t itself when it is already in one), `leave` the time it leaves it. An occupied
  // brick it refuses is walked past, one brick at a time. Returns the lanes that meet none.
  template <class Counts = AnyOccupied>
  unsigned first_occupied(const Rays& ray, unsigned walk, VF t, VF t1, VF& enter, VF& leave,
                          Counts counts = {}) const {
    VF origin[3], dir[3], toward[3];
    MF backward[3];
    VF cell[3];
    for (int a = 0; a < 3; ++a) {
      origin[a] = load(ray.origin[a]), dir[a] = load(ray.dir[a]), toward[a] = load(ray.toward[a]);
      backward[a] = to_float(hn::MaskFromVec(load(ray.backward[a])));
      // As BrickDda's constructor: a start on a boundary belongs to the brick the ray moves into.
      const VF x = hn::MulAdd(t, dir[a], origin[a]);
      const VF c = hn::IfThenElse(backward[a], hn::Sub(hn::Ceil(x), splat(1.0f)), hn::Floor(x));
      cell[a] = clamp_cell(a, c);
    }
    const VI octant = load(ray.octant);
    unsigned none = 0;
    for (unsigned pending = walk; pending;) {
      // Exact in floats: callers keep grids below 2^24 bricks (packet_marching_supported), so
      // the entry index stays below 2^27.
      const VI brick = hn::ConvertTo(
          DI(),
          hn::MulAdd(cell[2], splat(stride_z_), hn::MulAdd(cell[1], splat(stride_y_), cell[0])));
      const VI index = hn::Or(hn::ShiftLeft<3>(brick), octant);
      const VI d = hn::And(gather_words<1>(distances_, index), splat(0xff));
      const MF occupied = hn::And(to_float(hn::Eq(d, hn::Zero(DI()))), counts(brick));
      // The cube of empty bricks reaches `reach` bricks ahead of this one (with SkipMode::bricks,
      // or for an occupied brick, it is the brick alone).
      VF reach = hn::Zero(DF());
      if (by_distance_) reach = hn::ConvertTo(DF(), hn::Max(hn::Sub(d, splat(1)), hn::Zero(DI())));
      VF far[3], exit_t[3];
      for (int a = 0; a < 3; ++a) {
        far[a] = clamp_cell(a, hn::MulAdd(reach, toward[a], cell[a]));
        exit_t[a] = crossing(ray, a, far[a]);
      }
      const VF exit = hn::Min(hn::Min(exit_t[0], exit_t[1]), exit_t[2]);
      const MF here = lane_mask(pending);
      const MF found = hn::And(here, occupied);
      enter = hn::IfThenElse(found, t, enter);
      leave = hn::IfThenElse(found, exit, leave);
      // NaN times end the walk too.
      const MF moving = hn::AndNot(occupied, here);
      const MF gone = hn::AndNot(hn::Lt(exit, t1), moving);
      none |= bits_of(gone);
      const MF go = hn::AndNot(gone, moving);
      pending = bits_of(go);
      if (!pending) break;
      // Into the brick beyond the cube: past the far face on the exit axis (ties go to the lowest
      // axis, as in BrickDda), the brick at the exit point (within the cube) on the others.
      MF taken = hn::Not(all_lanes());
      for (int a = 0; a < 3; ++a) {
        const MF is_exit = hn::AndNot(taken, hn::Eq(exit_t[a], exit));
        taken = hn::Or(taken, is_exit);
        const VF past = hn::Add(far[a], toward[a]);
        const VF at = hn::Floor(hn::MulAdd(exit, dir[a], origin[a]));
        const VF inside = hn::Min(hn::Max(at, hn::Min(cell[a], far[a])), hn::Max(cell[a], far[a]));
        cell[a] = hn::IfThenElse(go, hn::IfThenElse(is_exit, past, inside), cell[a]);
      }
      t = hn::IfThenElse(go, exit, t);
    }
    return none;
  }

 private:
  // Brick c of axis a clamped to the grid (NaN goes to 0, as in BrickDda).
  VF clamp_cell(int a, VF c) const { return hn::Min(hn::Max(c, hn::Zero(DF())), splat(last_[a])); }

  // BrickDda::crossing in lanes: when the ray leaves brick j of axis a, infinity where it never
  // does or where the next brick is outside the grid.
  VF crossing(const Rays& ray, int a, VF j) const {
    const VF t = hn::Mul(hn::Add(j, load(ray.shift[a])), load(ray.inv_dir[a]));
    return hn::IfThenElse(hn::Eq(j, load(ray.edge[a])), splat(INFINITY), t);
  }

  const uint8_t* distances_;
  bool by_distance_;
  float inv_size_[3];          // 1 / cells per brick, per axis
  float stride_y_, stride_z_;  // brick index strides, as floats
  float last_[3];              // dims - 1, as floats
};

}  // namespace imx::HWY_NAMESPACE::lanes
HWY_AFTER_NAMESPACE();

#endif  // IMX_VOLUME_LANE_BRICKS_INL_HPP_
