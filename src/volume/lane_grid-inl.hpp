// LaneGrid: trilinear voxel fetches for a packet of rays at once, as VoxelGrid<T>::sample, in
// every SIMD target's lanes (lanes-inl.hpp).
#if defined(IMX_VOLUME_LANE_GRID_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef IMX_VOLUME_LANE_GRID_INL_HPP_
#undef IMX_VOLUME_LANE_GRID_INL_HPP_
#else
#define IMX_VOLUME_LANE_GRID_INL_HPP_
#endif

#include <type_traits>

#include "volume/lanes-inl.hpp"
#include "volume/voxel_grid.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE::lanes {

// Where trilinear fetches read in a grid of `dims` voxels: the lower corner's voxel index and
// the fractions toward the upper one, clamped as VoxelGrid<T>::sample clamps.
class LaneLattice {
 public:
  explicit LaneLattice(glm::ivec3 dims)
      : hi_x_(static_cast<float>(dims.x - 1)),
        hi_y_(static_cast<float>(dims.y - 1)),
        hi_z_(static_cast<float>(dims.z - 1)),
        max_x_(dims.x - 2),
        max_y_(dims.y - 2),
        max_z_(dims.z - 2),
        sy_(dims.x),
        sz_(dims.x * dims.y) {}

  // Set where p lies at least a voxel inside the grid on every axis (p in [1, dims - 2)), so
  // that fetches one voxel either way of its cell are never clamped.
  MF interior(VF px, VF py, VF pz) const {
    const VF one = splat(1.0f);
    return hn::And(hn::And(hn::And(hn::Ge(px, one), hn::Lt(px, splat(hi_x_ - 1.0f))),
                           hn::And(hn::Ge(py, one), hn::Lt(py, splat(hi_y_ - 1.0f)))),
                   hn::And(hn::Ge(pz, one), hn::Lt(pz, splat(hi_z_ - 1.0f))));
  }
  // Voxel (1, 1, 1): a cell whose neighbourhood every interior fetch may read instead.
  int interior_base() const { return 1 + sy_ + sz_; }

  VI sy() const { return splat(sy_); }
  VI sz() const { return splat(sz_); }
  int stride_y() const { return sy_; }
  int stride_z() const { return sz_; }

  VI locate(VF px, VF py, VF pz, VF& fx, VF& fy, VF& fz) const {
    VI corner[3];
    return locate(px, py, pz, fx, fy, fz, corner);
  }
  // As locate(), and the lower corner's index along each axis.
  VI locate(VF px, VF py, VF pz, VF& fx, VF& fy, VF& fz, VI corner[3]) const {
    const VF zero = hn::Zero(DF());
    // max(p, 0) returns 0 for a NaN p on every target (hn::Max takes the second operand for a
    // NaN first), as the clamp must to stay inside the grid.
    px = hn::Min(hn::Max(px, zero), splat(hi_x_));
    py = hn::Min(hn::Max(py, zero), splat(hi_y_));
    pz = hn::Min(hn::Max(pz, zero), splat(hi_z_));
    const VI ix = hn::Min(hn::ConvertTo(DI(), px), splat(max_x_));
    const VI iy = hn::Min(hn::ConvertTo(DI(), py), splat(max_y_));
    const VI iz = hn::Min(hn::ConvertTo(DI(), pz), splat(max_z_));
    fx = hn::Sub(px, hn::ConvertTo(DF(), ix));
    fy = hn::Sub(py, hn::ConvertTo(DF(), iy));
    fz = hn::Sub(pz, hn::ConvertTo(DF(), iz));
    corner[0] = ix, corner[1] = iy, corner[2] = iz;
    return hn::Add(ix, hn::Add(hn::Mul(iy, sy()), hn::Mul(iz, sz())));
  }
  // The last lower corner along each axis (dims - 2).
  int last_corner(int axis) const { return axis == 0 ? max_x_ : axis == 1 ? max_y_ : max_z_; }

 private:
  float hi_x_, hi_y_, hi_z_;   // dims - 1: the clamp
  int max_x_, max_y_, max_z_;  // dims - 2: the last lower corner
  int sy_, sz_;                // strides in voxels
};

// sample_formulas::trilinear in lanes, as VoxelGrid<T>::sample interpolates.
HWY_INLINE VF trilinear(const VF c[8], VF fx, VF fy, VF fz) {
  return sample_formulas::trilinear<LaneOps>(c, fx, fy, fz);
}

// The low and high 16-bit halves of 32-bit words, sign- or zero-extended as T is.
template <class T>
HWY_INLINE VI low_half(VI w) {
  if constexpr (std::is_signed_v<T>) return hn::ShiftRight<16>(hn::ShiftLeft<16>(w));
  return hn::And(w, splat(0xffff));
}
template <class T>
HWY_INLINE VI high_half(VI w) {
  if constexpr (std::is_signed_v<T>) return hn::ShiftRight<16>(w);
  return hn::BitCast(DI(), hn::ShiftRight<16>(hn::BitCast(DU(), w)));
}

// VoxelGrid<T>::sample in lanes. 8- and 16-bit voxels are fetched as 32-bit words holding the
// x-neighbours (i, i + 1) together: four fetches instead of eight. A word read at the last
// u8 voxel pair would run past the voxels, so that one is read from at most N - 4 and shifted.
template <class T>
class LaneGrid {
 public:
  explicit LaneGrid(const VoxelGrid<T>& g)
      : data_(g.data), lattice_(g.dims), last_word_(g.dims.x * g.dims.y * g.dims.z - 4) {}

  // The eight voxels around each lane's point (c000, c100, c010, c110, c001, c101, c011, c111)
  // as integers (floats truncated) and the fractions toward the upper corner.
  void corners(VF px, VF py, VF pz, VI c[8], VF& fx, VF& fy, VF& fz) const {
    const VI base = lattice_.locate(px, py, pz, fx, fy, fz);
    const VI sy = lattice_.sy(), sz = lattice_.sz();
    const VI o01 = hn::Add(base, sy), o10 = hn::Add(base, sz);
    const VI offs[4] = {base, o01, o10, hn::Add(o01, sz)};
    if constexpr (std::is_same_v<T, float>) {
      for (int k = 0; k < 4; ++k) {
        c[2 * k] = hn::ConvertTo(DI(), gather_floats(data_, offs[k]));
        c[2 * k + 1] = hn::ConvertTo(DI(), gather_floats(data_, hn::Add(offs[k], splat(1))));
      }
    } else {
      for (int k = 0; k < 4; ++k) {
        const VI w = word(offs[k], k == 3);
        if constexpr (sizeof(T) == 1) {
          c[2 * k] = hn::And(w, splat(0xff));
          c[2 * k + 1] = hn::And(hn::ShiftRight<8>(w), splat(0xff));
        } else {
          c[2 * k] = low_half<T>(w);
          c[2 * k + 1] = high_half<T>(w);
        }
      }
    }
  }

  const LaneLattice& lattice() const { return lattice_; }

  VF sample(VF px, VF py, VF pz) const {
    VF fx, fy, fz;
    const VI base = lattice_.locate(px, py, pz, fx, fy, fz);
    const VI sy = lattice_.sy(), sz = lattice_.sz();
    const VI o01 = hn::Add(base, sy), o10 = hn::Add(base, sz);
    const VI offs[4] = {base, o01, o10, hn::Add(o01, sz)};
    VF c[8];  // c000, c100, c010, c110, c001, c101, c011, c111
    for (int k = 0; k < 4; ++k) pair(offs[k], k == 3, c[2 * k], c[2 * k + 1]);
    return trilinear(c, fx, fy, fz);
  }

  // VoxelGrid<T>::gradient (central differences of sample() one voxel each way) in every lane,
  // the six samples read from p's own lattice point and fractions: the 32 voxels around p once,
  // in 12 to 16 word fetches instead of 24 for 8- and 16-bit voxels. Rows and columns past the
  // grid's faces are clamped to them, which gives the values of the clamped sample positions
  // wherever p lies inside the grid; a result may differ from six sample() calls by the rounding
  // of p +- 1, and where p lies in the half voxel outside the centres (p is clamped first).
  // Every lane alike, so that a lane's bytes do not depend on the packet it is in.
  void gradient(VF px, VF py, VF pz, VF& gx, VF& gy, VF& gz) const {
    VF fx, fy, fz;
    VI corner[3];
    const VI base = lattice_.locate(px, py, pz, fx, fy, fz, corner);
    const int last[3] = {lattice_.last_corner(0), lattice_.last_corner(1), lattice_.last_corner(2)};
    // The pairs as the formula reads them.
    struct Rows {
      const LaneGrid& grid;
      HWY_INLINE void pair(VI at, bool last_row, VF& a, VF& b) const {
        grid.pair(at, last_row, a, b);
      }
    };
    LaneOps::V3 g;
    sample_formulas::clamped_gradient<LaneOps>(Rows{*this}, base, corner, fx, fy, fz, last,
                                               lattice_.sy(), lattice_.sz(), g);
    gx = g.x, gy = g.y, gz = g.z;
  }

 private:
  // Voxels i and i + 1 as floats (`last_row`: as word()).
  void pair(VI i, bool last_row, VF& a, VF& b) const {
    if constexpr (std::is_same_v<T, float>) {
      a = gather_floats(data_, i);
      b = gather_floats(data_, hn::Add(i, splat(1)));
    } else {
      const VI w = word(i, last_row);
      if constexpr (sizeof(T) == 1) {
        a = hn::ConvertTo(DF(), hn::And(w, splat(0xff)));
        b = hn::ConvertTo(DF(), hn::And(hn::ShiftRight<8>(w), splat(0xff)));
      } else {
        a = hn::ConvertTo(DF(), low_half<T>(w));
        b = hn::ConvertTo(DF(), high_half<T>(w));
      }
    }
  }

  // The 32-bit word holding voxels (i, i + 1) for 8- and 16-bit T. For 16-bit voxels element
  // i + 1 is at most the last voxel, so no word runs past the end; for 8-bit ones only the last
  // pair (`last_row`: the upper y and z row) can lie within the last 3 bytes, every stride
  // being at least 2.
  VI word(VI at, bool last_row) const {
    if constexpr (sizeof(T) == 2) {
      (void)last_row;
      return gather_words<2>(data_, at);
    } else {
      if (!last_row) return gather_words<1>(data_, at);
      const VI safe = hn::Min(at, splat(last_word_));
      const VU shift = hn::BitCast(DU(), hn::ShiftLeft<3>(hn::Sub(at, safe)));
      return hn::BitCast(DI(), hn::Shr(hn::BitCast(DU(), gather_words<1>(data_, safe)), shift));
    }
  }

  const T* data_;
  LaneLattice lattice_;
  int last_word_;  // the last voxel a 32-bit word may start at
};

}  // namespace imx::HWY_NAMESPACE::lanes
HWY_AFTER_NAMESPACE();

#endif  // IMX_VOLUME_LANE_GRID_INL_HPP_
