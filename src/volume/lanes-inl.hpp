// Lane helpers for the ray packets, one source for every SIMD target (Google Highway): up to
// sixteen floats per vector, one ray per lane. Included once per target inside
// HWY_BEFORE_NAMESPACE by the kernels' foreach_target files; the guard toggles per target.
#if defined(IMX_VOLUME_LANES_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef IMX_VOLUME_LANES_INL_HPP_
#undef IMX_VOLUME_LANES_INL_HPP_
#else
#define IMX_VOLUME_LANES_INL_HPP_
#endif

#include <cstddef>
#include <cstdint>
#include <cstring>

#include <hwy/highway.h>

#include "intermix/scene.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE::lanes {

namespace hn = hwy::HWY_NAMESPACE;

// Sixteen lanes at most, so that a set of lanes fits an unsigned's low bits.
using DF = hn::CappedTag<float, 16>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using VU = hn::Vec<DU>;
using MF = hn::Mask<DF>;
using MI = hn::Mask<DI>;

constexpr int kLanes = static_cast<int>(hn::MaxLanes(DF()));
constexpr unsigned kAllLanes = kLanes >= 32 ? ~0u : (1u << kLanes) - 1;
static_assert(kLanes <= 16, "lane sets are 16-bit");

HWY_INLINE VF splat(float x) {
  return hn::Set(DF(), x);
}
HWY_INLINE VI splat(int x) {
  return hn::Set(DI(), x);
}
HWY_INLINE VF load(const float* p) {
  return hn::Load(DF(), p);
}
HWY_INLINE VI load(const int32_t* p) {
  return hn::Load(DI(), p);
}
HWY_INLINE void store(VF v, float* p) {
  hn::Store(v, DF(), p);
}
HWY_INLINE void store(VI v, int32_t* p) {
  hn::Store(v, DI(), p);
}

// The lanes set in `m` as bits (lane l is bit l), and back.
HWY_INLINE unsigned bits_of(MF m) {
  uint8_t b[8] = {};
  hn::StoreMaskBits(DF(), m, b);
  return static_cast<unsigned>(b[0]) | static_cast<unsigned>(b[1]) << 8;
}
HWY_INLINE MF lane_mask(unsigned bits) {
  const uint8_t b[8] = {static_cast<uint8_t>(bits), static_cast<uint8_t>(bits >> 8)};
  return hn::LoadMaskBits(DF(), b);
}
HWY_INLINE MF all_lanes() {
  return hn::FirstN(DF(), kLanes);
}
HWY_INLINE MF to_float(MI m) {
  return hn::RebindMask(DF(), m);
}
HWY_INLINE MI to_int(MF m) {
  return hn::RebindMask(DI(), m);
}

// The per-sample formulas compiled for this target (sample_formulas.hpp).
#define IMX_FORMULA_ATTR HWY_ATTR
namespace sample_formulas {
#include "volume/sample_formulas.inc"  // NOLINT(bugprone-suspicious-include)
}  // namespace sample_formulas
#undef IMX_FORMULA_ATTR

// ScalarOps' vocabulary (sample_ops.hpp) on lanes, one ray per lane: what the formulas of
// sample_formulas.hpp are instantiated with here.
struct LaneOps {
  using V = VF;
  using M = MF;

  static HWY_INLINE V splat(float x) { return hn::Set(DF(), x); }
  static HWY_INLINE V sub(V a, V b) { return hn::Sub(a, b); }
  static HWY_INLINE V mul(V a, V b) { return hn::Mul(a, b); }
  static HWY_INLINE V div(V a, V b) { return hn::Div(a, b); }
  static HWY_INLINE V mul_add(V a, V b, V c) { return hn::MulAdd(a, b, c); }
  static HWY_INLINE V neg_mul_add(V a, V b, V c) { return hn::NegMulAdd(a, b, c); }
  static HWY_INLINE V min(V a, V b) { return hn::Min(a, b); }
  static HWY_INLINE V max(V a, V b) { return hn::Max(a, b); }
  static HWY_INLINE V sqrt(V a) { return hn::Sqrt(a); }

  static HWY_INLINE M gt(V a, V b) { return hn::Gt(a, b); }
  static HWY_INLINE M lt(V a, V b) { return hn::Lt(a, b); }
  static HWY_INLINE M both(M a, M b) { return hn::And(a, b); }
  static HWY_INLINE M either(M a, M b) { return hn::Or(a, b); }
  static HWY_INLINE M not_(M a) { return hn::Not(a); }
  static HWY_INLINE bool none(M a) { return hn::AllFalse(DF(), a); }
  static HWY_INLINE V select(M m, V a, V b) { return hn::IfThenElse(m, a, b); }
  static HWY_INLINE V zero_unless(M m, V a) { return hn::IfThenElseZero(m, a); }

  using I = VI;
  using MI = hn::Mask<DI>;
  static HWY_INLINE I isplat(int x) { return hn::Set(DI(), x); }
  static HWY_INLINE I iadd(I a, I b) { return hn::Add(a, b); }
  static HWY_INLINE I ineg(I a) { return hn::Neg(a); }
  static HWY_INLINE MI igt(I a, I b) { return hn::Gt(a, b); }
  static HWY_INLINE MI ilt(I a, I b) { return hn::Lt(a, b); }
  static HWY_INLINE MI ieq(I a, I b) { return hn::Eq(a, b); }
  static HWY_INLINE I iselect(MI m, I a, I b) { return hn::IfThenElse(m, a, b); }
  static HWY_INLINE I izero_unless(MI m, I a) { return hn::IfThenElseZero(m, a); }
  static HWY_INLINE M float_mask(MI m) { return hn::RebindMask(DF(), m); }

  // Three-vectors, one per lane: structure of arrays.
  struct V3 {
    V x, y, z;
  };
  static HWY_INLINE V3 splat3(const glm::vec3& v) { return {splat(v.x), splat(v.y), splat(v.z)}; }
  static HWY_INLINE V dot(V3 a, V3 b) {
    return hn::MulAdd(a.z, b.z, hn::MulAdd(a.y, b.y, hn::Mul(a.x, b.x)));
  }
  static HWY_INLINE V3 scale(V k, V3 a) {
    return {hn::Mul(k, a.x), hn::Mul(k, a.y), hn::Mul(k, a.z)};
  }
  static HWY_INLINE V3 add(V3 a, V3 b) {
    return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
  }
  static HWY_INLINE V3 mul(V3 a, V3 b) {
    return {hn::Mul(a.x, b.x), hn::Mul(a.y, b.y), hn::Mul(a.z, b.z)};
  }
  static HWY_INLINE V3 mul_add(V3 a, V3 b, V3 c) {
    return {hn::MulAdd(a.x, b.x, c.x), hn::MulAdd(a.y, b.y, c.y), hn::MulAdd(a.z, b.z, c.z)};
  }
  static HWY_INLINE V3 zero_unless(M m, V3 a) {
    return {hn::IfThenElseZero(m, a.x), hn::IfThenElseZero(m, a.y), hn::IfThenElseZero(m, a.z)};
  }
  static HWY_INLINE V3 negate_if(M m, V3 a) {
    const V sign = hn::IfThenElseZero(m, splat(-0.0f));
    return {hn::Xor(a.x, sign), hn::Xor(a.y, sign), hn::Xor(a.z, sign)};
  }
};

HWY_INLINE VF dot3(VF ax, VF ay, VF az, VF bx, VF by, VF bz) {
  return sample_formulas::dot3<LaneOps>(ax, ay, az, bx, by, bz);
}

// a + f * (b - a), the interpolation step of every trilinear and bilinear fetch.
HWY_INLINE VF lerp(VF a, VF b, VF f) {
  return sample_formulas::lerp<LaneOps>(a, b, f);
}

// Whether the target gathers in hardware (x86 AVX2 and AVX-512). On this project's Intel machine
// the gather instructions beat one scalar load per lane: a MIP of the Philips CT at 16 lanes took
// 109 ms against 155 ms, at 8 lanes 137 against 158 ms. Other targets load lane by lane.
constexpr bool kHardwareGather = HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2;

// The 32-bit words at byte offsets index * Scale (unaligned).
template <int Scale>
HWY_INLINE VI gather_words(const void* base, VI index) {
  const auto* words = static_cast<const int32_t*>(base);
  if constexpr (kHardwareGather) {
    if constexpr (Scale == 4) return hn::GatherIndex(DI(), words, index);
    return hn::GatherOffset(DI(), words, Scale == 1 ? index : hn::ShiftLeft<1>(index));
  }
  HWY_ALIGN int32_t at[kLanes];
  HWY_ALIGN int32_t word[kLanes];
  store(index, at);
  const char* bytes = static_cast<const char*>(base);
  for (int l = 0; l < kLanes; ++l)
    std::memcpy(&word[l], bytes + static_cast<ptrdiff_t>(at[l]) * Scale, sizeof(int32_t));
  return load(word);
}

// base[index] per lane.
HWY_INLINE VF gather_floats(const float* base, VI index) {
  if constexpr (kHardwareGather) return hn::GatherIndex(DF(), base, index);
  HWY_ALIGN int32_t at[kLanes];
  HWY_ALIGN float value[kLanes];
  store(index, at);
  for (int l = 0; l < kLanes; ++l) value[l] = base[at[l]];
  return load(value);
}

// lerp() on one lane's entries (128- or 256-bit vectors, whatever the target's lanes).
template <class V>
HWY_INLINE V lerp4(V a, V b, V f) {
  return hn::MulAdd(f, hn::Sub(b, a), a);
}

// Per-lane 128-bit vectors: not for the one-lane target nor the scalable ones (SVE, disabled),
// whose vectors cannot be kept in arrays.
#define IMX_LANE_QUADS (HWY_TARGET != HWY_SCALAR && !HWY_HAVE_SCALABLE)
#if IMX_LANE_QUADS
// One lane's four floats (an RGBA entry, a pair of moments) in a 128-bit vector.
using D4 = hn::Full128<float>;
using V4 = hn::Vec<D4>;

// Table entries i and i + 1 of four floats each (8 adjacent floats at `entry`), lerped at f.
HWY_INLINE V4 lerp_entries(const float* entry, float f) {
  const D4 d4;
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  const hn::Full256<float> d8;  // both entries in one load
  const auto both = hn::LoadU(d8, entry);
  return lerp4(hn::LowerHalf(d4, both), hn::UpperHalf(d4, both), hn::Set(d4, f));
#else
  return lerp4(hn::LoadU(d4, entry), hn::LoadU(d4, entry + 4), hn::Set(d4, f));
#endif
}

// The vector whose 128-bit block k is q[4k + first].
HWY_INLINE VF every_fourth(const V4* q, int first) {
#if HWY_MAX_BYTES >= 64
  const hn::Full256<float> d8;
  return hn::Combine(DF(), hn::Combine(d8, q[12 + first], q[8 + first]),
                     hn::Combine(d8, q[4 + first], q[first]));
#elif HWY_MAX_BYTES == 32
  return hn::Combine(DF(), q[4 + first], q[first]);
#else
  return q[first];
#endif
}

// Lane l's four floats q[l] = (x, y, z, w) as four vectors of lanes: a transpose in registers.
HWY_INLINE void transpose_quads(const V4* q, VF& x, VF& y, VF& z, VF& w) {
  static_assert(kLanes % 4 == 0, "whole blocks of four lanes");
  const VF a = every_fourth(q, 0), b = every_fourth(q, 1);
  const VF c = every_fourth(q, 2), d = every_fourth(q, 3);
  // Per block: (a.x, b.x, a.y, b.y), (c.x, d.x, c.y, d.y), then the z and w halves.
  const VF ab_xy = hn::InterleaveLower(DF(), a, b), cd_xy = hn::InterleaveLower(DF(), c, d);
  const VF ab_zw = hn::InterleaveUpper(DF(), a, b), cd_zw = hn::InterleaveUpper(DF(), c, d);
  const hn::Repartition<uint64_t, DF> d64;
  const auto low = [&](VF p, VF q2) HWY_ATTR {
    return hn::BitCast(DF(), hn::InterleaveLower(d64, hn::BitCast(d64, p), hn::BitCast(d64, q2)));
  };
  const auto high = [&](VF p, VF q2) HWY_ATTR {
    return hn::BitCast(DF(), hn::InterleaveUpper(d64, hn::BitCast(d64, p), hn::BitCast(d64, q2)));
  };
  x = low(ab_xy, cd_xy), y = high(ab_xy, cd_xy);
  z = low(ab_zw, cd_zw), w = high(ab_zw, cd_zw);
}
#endif

// no_data() in lanes: set where s is NaN or infinite.
HWY_INLINE MF no_data_lanes(VF s) {
  return hn::Not(hn::IsFinite(s));
}

}  // namespace imx::HWY_NAMESPACE::lanes
HWY_AFTER_NAMESPACE();

#endif  // IMX_VOLUME_LANES_INL_HPP_
