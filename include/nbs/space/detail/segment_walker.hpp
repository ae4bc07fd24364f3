// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Exact integer 3D-DDA (Amanatides–Woo) in key space, without floating point in the loop.
///
/// The segment's end points are quantised to 1/2^kFractionBits voxel (fixed point, int64). The walker visits the
/// voxels the *quantised* segment crosses, in order, from the voxel containing the start to the one containing the
/// end. Crossing times t_a = N_a / A_a (N_a: distance to the next boundary along axis a, A_a = |Δ_a|) are compared
/// by cross-multiplication; the six products N_a·A_b are kept incrementally, so a step costs a few integer adds and
/// compares. Ties (the segment passes exactly through a voxel edge or corner) step the higher axis first. The number
/// of steps is exactly Σ_a |end_key_a − start_key_a|, so the loop always terminates.
/// Overflow: |coordinate| < 2^20 voxels ⇒ N_a < 2^32, A_b < 2^31 ⇒ products < 2^63.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "nbs/core/types.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs::detail {

/// Fixed-point precision of the DDA: end points are quantised to 1/2^kFractionBits voxel.
inline constexpr int kDdaFractionBits = 10;

/// A segment quantised for the DDA, per axis a: start key, direction sign, boundary crossings to the end voxel
/// (remaining), A_a = |Δ_a| and N_a = distance from the start to the first boundary crossed (fixed point).
struct SegmentSetup {
  static constexpr std::int64_t kOne = std::int64_t{1} << kDdaFractionBits;

  /// Fixed-point coordinate of a voxel-unit value v (world · 1/l_v). Precondition: |v| ≤ 2^20.
  [[nodiscard]] static std::int64_t to_fixed(double v) {
    const double x = v * static_cast<double>(kOne);  // |x| ≤ 2^30: the conversion is exact after truncation
    const auto t = static_cast<std::int64_t>(x);
    return t - (static_cast<double>(t) > x ? 1 : 0);  // floor without a libm call
  }
  /// Floor division of a fixed-point coordinate by one voxel (arithmetic shift = floor, also for f < 0).
  [[nodiscard]] static std::int32_t key_of_fixed(std::int64_t f) {
    return static_cast<std::int32_t>(f >> kDdaFractionBits);
  }

  /// Fixed-point coordinates of a point v in voxel units. v·2^F is exact (a power of two), so
  /// key_of_fixed(to_fixed(v_a)) = floor(v_a): the walk's voxel keys equal VoxelGrid::key_of of the same point.
  using Fixed = std::array<std::int64_t, 3>;
  [[nodiscard]] static Fixed to_fixed(const Vec3& v) { return {to_fixed(v.x()), to_fixed(v.y()), to_fixed(v.z())}; }
  /// Key of the voxel containing fixed-point coordinates f.
  [[nodiscard]] static VoxelKey key_of_fixed(const Fixed& f) {
    return {key_of_fixed(f[0]), key_of_fixed(f[1]), key_of_fixed(f[2])};
  }

  /// Segment from `start` to `end`, both in voxel units (world metres · 1/l_v), each coordinate in
  /// [−2^20, 2^20) — the caller checks (VoxelGrid::key_of succeeds for both).
  SegmentSetup(const Vec3& start, const Vec3& end) : SegmentSetup(to_fixed(start), to_fixed(end)) {}
  /// Segment between fixed-point coordinates (see to_fixed).
  SegmentSetup(const Fixed& start, const Fixed& end) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t s = start[a];
      const std::int64_t e = end[a];
      key[a] = key_of_fixed(s);
      const std::int32_t end_key = key_of_fixed(e);
      const std::int64_t d = e - s;
      sign[a] = d > 0 ? 1 : (d < 0 ? -1 : 0);
      abs[a] = d >= 0 ? d : -d;
      remaining[a] = end_key >= key[a] ? end_key - key[a] : key[a] - end_key;
      const std::int64_t cell = static_cast<std::int64_t>(key[a]) * kOne;
      next[a] = d > 0 ? cell + kOne - s : (d < 0 ? s - cell : 0);
    }
  }
  /// Key of the end voxel.
  [[nodiscard]] VoxelKey end_key() const {
    return {key.x + sign[0] * remaining[0], key.y + sign[1] * remaining[1], key.z + sign[2] * remaining[2]};
  }
  /// Steps of the whole walk: Σ_a remaining_a.
  [[nodiscard]] std::int64_t steps() const {
    return static_cast<std::int64_t>(remaining[0]) + remaining[1] + remaining[2];
  }

  VoxelKey key;
  int sign[3] = {0, 0, 0};
  std::int32_t remaining[3] = {0, 0, 0};
  std::int64_t abs[3] = {0, 0, 0};
  std::int64_t next[3] = {0, 0, 0};
};

/// The rest of a walk after one of its boundary crossings: `rest` walks exactly the voxels q's walk visits from that
/// crossing on, in order (same end point, same A_a; key, N_a and remaining_a advanced), and `done` is the number of
/// steps q's walk takes up to and including the crossing.
struct SegmentRest {
  SegmentSetup rest;
  std::int64_t done;
};

/// The rest of q's walk after its j-th crossing along `axis` (1 ≤ j ≤ q.remaining[axis]). Exact: the crossing counts
/// of the other axes follow from the crossing times t_a,k = (N_a + (k − 1)·2^F) / A_a compared by cross-multiplication
/// (128-bit), with the tie rule of SegmentWalker::step (at equal times the later axis steps first). Since the DDA
/// compares crossing times only, a walker built from `rest` takes the steps q's walker takes after that crossing.
[[nodiscard]] inline SegmentRest after_crossing(const SegmentSetup& q, int axis, std::int32_t j) {
  using Wide = __int128;
  SegmentRest r{q, 0};
  const Wide t_num = Wide{q.next[axis]} + Wide{j - 1} * SegmentSetup::kOne;  // crossing time · A_axis
  const Wide unit = Wide{SegmentSetup::kOne} * q.abs[axis];
  for (int b = 0; b < 3; ++b) {
    std::int64_t c = j;
    if (b != axis) {
      c = 0;
      if (q.remaining[b] > 0) {
        // Crossing k of b comes first iff (N_b + (k − 1)·2^F)·A_axis < t_num·A_b, or = and b > axis.
        const Wide d = t_num * q.abs[b] - Wide{q.next[b]} * q.abs[axis];
        const Wide n = b > axis ? (d < 0 ? 0 : d / unit + 1) : (d <= 0 ? 0 : (d - 1) / unit + 1);
        c = static_cast<std::int64_t>(std::min<Wide>(n, q.remaining[b]));
      }
    }
    r.rest.key[b] += static_cast<std::int32_t>(q.sign[b] * c);
    r.rest.remaining[b] -= static_cast<std::int32_t>(c);
    r.rest.next[b] += c * SegmentSetup::kOne;
    r.done += c;
  }
  return r;
}

class SegmentWalker {
public:
  static constexpr int kFractionBits = kDdaFractionBits;
  static constexpr std::int64_t kOne = SegmentSetup::kOne;

  /// See SegmentSetup.
  [[nodiscard]] static std::int64_t to_fixed(double v) { return SegmentSetup::to_fixed(v); }
  /// See SegmentSetup.
  [[nodiscard]] static std::int32_t key_of_fixed(std::int64_t f) { return SegmentSetup::key_of_fixed(f); }

  /// Segment from `start` to `end`, both in voxel units (world metres · 1/l_v), each coordinate in
  /// [−2^20, 2^20) — the caller checks (VoxelGrid::key_of succeeds for both).
  SegmentWalker(const Vec3& start, const Vec3& end) : SegmentWalker(SegmentSetup(start, end)) {}
  /// The walk of a quantised segment.
  explicit SegmentWalker(const SegmentSetup& q) : key_(q.key) {
    for (int a = 0; a < 3; ++a) {
      sign_[a] = q.sign[a];
      remaining_[a] = q.remaining[a];
    }
    total_ = q.steps();
    const std::int64_t* A = q.abs;
    const std::int64_t* N = q.next;
    // p_ab = N_a·A_b; i_ab = 2^F·A_b is added to p_ab when axis a steps.
    p01_ = N[0] * A[1], p02_ = N[0] * A[2];
    p10_ = N[1] * A[0], p12_ = N[1] * A[2];
    p20_ = N[2] * A[0], p21_ = N[2] * A[1];
    i01_ = kOne * A[1], i02_ = kOne * A[2];
    i10_ = kOne * A[0], i12_ = kOne * A[2];
    i20_ = kOne * A[0], i21_ = kOne * A[1];
    for (int a = 0; a < 3; ++a)
      if (remaining_[a] == 0) exhaust(a);
  }

  /// Current voxel.
  [[nodiscard]] const VoxelKey& key() const { return key_; }
  /// Steps left until the end voxel.
  [[nodiscard]] std::int64_t remaining() const { return total_; }
  /// Direction of travel along `axis`: −1, 0 or +1.
  [[nodiscard]] int sign(int axis) const { return sign_[axis]; }

  /// Moves to the next voxel and returns the axis crossed. Precondition: remaining() > 0.
  int step() {
    // t_a < t_b ⇔ N_a·A_b < N_b·A_a; ties go to the later axis. Exhausted axes never win (see exhaust()).
    // Named members (no variable indexing) so that an inlined walk keeps them in registers.
    int best;
    if (p01_ < p10_) {
      best = p20_ <= p02_ ? 2 : 0;
    } else {
      best = p21_ <= p12_ ? 2 : 1;
    }
    --total_;
    switch (best) {
      case 0:
        key_.x += sign_[0];
        p01_ += i01_;
        p02_ += i02_;
        if (--remaining_[0] == 0) exhaust(0);
        break;
      case 1:
        key_.y += sign_[1];
        p10_ += i10_;
        p12_ += i12_;
        if (--remaining_[1] == 0) exhaust(1);
        break;
      default:
        key_.z += sign_[2];
        p20_ += i20_;
        p21_ += i21_;
        if (--remaining_[2] == 0) exhaust(2);
        break;
    }
    return best;
  }

private:
  static constexpr std::int64_t kNever = std::int64_t{1} << 62;
  // Axis a has no crossing left: make every comparison against it lose (its products +2^62, the others' −2^62;
  // real products and their growth stay below 2^62 in magnitude, so the order is kept).
  void exhaust(int a) {
    if (a == 0) {
      p01_ = p02_ = kNever;
      p10_ = p20_ = -kNever;
      i10_ = i20_ = 0;
    } else if (a == 1) {
      p10_ = p12_ = kNever;
      p01_ = p21_ = -kNever;
      i01_ = i21_ = 0;
    } else {
      p20_ = p21_ = kNever;
      p02_ = p12_ = -kNever;
      i02_ = i12_ = 0;
    }
  }

  VoxelKey key_;
  int sign_[3] = {0, 0, 0};
  std::int32_t remaining_[3] = {0, 0, 0};
  std::int64_t total_ = 0;
  std::int64_t p01_ = 0, p02_ = 0, p10_ = 0, p12_ = 0, p20_ = 0, p21_ = 0;
  std::int64_t i01_ = 0, i02_ = 0, i10_ = 0, i12_ = 0, i20_ = 0, i21_ = 0;
};

/// The step rule of SegmentWalker with three numbers instead of six. Over the axes that cross a voxel boundary
/// (remaining > 0, hence A > 0) let M = Π A_b; the crossing time t_a = N_a / A_a is scaled to the exact integer
/// T_a = t_a·M = N_a·Π_{b≠a} A_b, so t_a < t_b ⇔ T_a < T_b. A step along a adds D_a = 2^F·Π_{b≠a} A_b to T_a; an axis
/// that never crosses has T_a = +∞. Same tie rule as SegmentWalker::step (the later axis wins), so the voxel sequence
/// is identical (tests/space/test_dda.cpp compares them). It does not track the key: the caller follows the returned
/// axes from SegmentSetup::key, for exactly SegmentSetup::steps() steps.
/// No per-axis countdown is needed: every crossing of the walk has t ≤ 1 and the first crossing past an axis' last
/// one has t > 1 — except for an axis moving down whose end lies exactly on a voxel face: its extra crossing has
/// t = 1 and loses to every real crossing (t < 1) but could win a tie against a real crossing at t = 1, which only an
/// axis moving up to an end exactly on a face has; make() leaves segments with both to SegmentWalker.
class CommonDenominatorStepper {
public:
  /// The stepper of segment q, or nullopt if |Δ| ≥ 1024 voxels on some axis (its products could then exceed 2^61)
  /// or one axis moves down and another up to ends exactly on voxel faces; then use SegmentWalker.
  [[nodiscard]] static std::optional<CommonDenominatorStepper> make(const SegmentSetup& q) {
    // (N_a + remaining_a·2^F)·m_a ≤ (A_a + 2^(F+1))·A_b·A_c < 2^61 when every A < 2^20 (1024 voxels): then no T_a
    // nor T_a + D_a overflows.
    if ((q.abs[0] | q.abs[1] | q.abs[2]) >= (std::int64_t{1} << 20)) return std::nullopt;
    // End coordinate modulo 2^F: moving down start − A = key·2^F + N − A, moving up start + A = (key + 1)·2^F − N + A.
    bool down_to_face = false, up_to_face = false;
    for (int a = 0; a < 3; ++a) {
      if (q.remaining[a] == 0) continue;
      if (q.sign[a] < 0 && ((q.next[a] - q.abs[a]) & (SegmentSetup::kOne - 1)) == 0) down_to_face = true;
      if (q.sign[a] > 0 && ((q.abs[a] - q.next[a]) & (SegmentSetup::kOne - 1)) == 0) up_to_face = true;
    }
    if (down_to_face && up_to_face) return std::nullopt;
    const std::int64_t a0 = q.remaining[0] > 0 ? q.abs[0] : 1, a1 = q.remaining[1] > 0 ? q.abs[1] : 1,
                       a2 = q.remaining[2] > 0 ? q.abs[2] : 1;
    const std::int64_t m[3] = {a1 * a2, a0 * a2, a0 * a1};
    std::int64_t t[3], d[3];
    for (int a = 0; a < 3; ++a) {
      t[a] = q.remaining[a] > 0 ? q.next[a] * m[a] : kInf;
      d[a] = q.remaining[a] > 0 ? SegmentSetup::kOne * m[a] : 0;
    }
    CommonDenominatorStepper s;
    s.t0_ = t[0], s.t1_ = t[1], s.t2_ = t[2];
    s.d0_ = d[0], s.d1_ = d[1], s.d2_ = d[2];
    return s;
  }

  /// Moves to the next voxel and returns the axis crossed (0, 1, 2). Precondition: a step is left.
  int step() {
    if (t0_ < t1_) {
      if (t2_ <= t0_) return t2_ += d2_, 2;
      return t0_ += d0_, 0;
    }
    if (t2_ <= t1_) return t2_ += d2_, 2;
    return t1_ += d1_, 1;
  }

private:
  static constexpr std::int64_t kInf = std::int64_t{1} << 62;
  std::int64_t t0_ = kInf, t1_ = kInf, t2_ = kInf, d0_ = 0, d1_ = 0, d2_ = 0;
};

}  // namespace nbs::detail
