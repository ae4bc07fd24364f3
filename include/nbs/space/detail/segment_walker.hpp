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

#include <cmath>
#include <cstdint>

#include "nbs/core/types.hpp"
#include "nbs/space/voxel_key.hpp"

namespace nbs::detail {

class SegmentWalker {
public:
  static constexpr int kFractionBits = 10;
  static constexpr std::int64_t kOne = std::int64_t{1} << kFractionBits;

  /// Fixed-point coordinate of a voxel-unit value v (world · 1/l_v). Precondition: |v| ≤ 2^20.
  [[nodiscard]] static std::int64_t to_fixed(double v) {
    const double x = v * static_cast<double>(kOne);  // |x| ≤ 2^30: the conversion is exact after truncation
    const auto t = static_cast<std::int64_t>(x);
    return t - (static_cast<double>(t) > x ? 1 : 0);  // floor without a libm call
  }
  /// Floor division of a fixed-point coordinate by one voxel.
  [[nodiscard]] static std::int32_t key_of_fixed(std::int64_t f) {
    return static_cast<std::int32_t>(f >= 0 ? f / kOne : -((-f + kOne - 1) / kOne));
  }

  /// Segment from `start` to `end`, both in voxel units (world metres · 1/l_v), each coordinate in
  /// [−2^20, 2^20) — the caller checks (VoxelGrid::key_of succeeds for both).
  SegmentWalker(const Vec3& start, const Vec3& end) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t s = to_fixed(start[a]);
      const std::int64_t e = to_fixed(end[a]);
      key_[a] = key_of_fixed(s);
      const std::int32_t end_key = key_of_fixed(e);
      const std::int64_t d = e - s;
      sign_[a] = d > 0 ? 1 : (d < 0 ? -1 : 0);
      abs_[a] = d >= 0 ? d : -d;
      remaining_[a] = end_key >= key_[a] ? end_key - key_[a] : key_[a] - end_key;
      const std::int64_t cell = static_cast<std::int64_t>(key_[a]) * kOne;
      next_[a] = d > 0 ? cell + kOne - s : (d < 0 ? s - cell : 0);
    }
    total_ = static_cast<std::int64_t>(remaining_[0]) + remaining_[1] + remaining_[2];
    // p_ab = N_a·A_b; i_ab = 2^F·A_b is added to p_ab when axis a steps.
    p01_ = next_[0] * abs_[1], p02_ = next_[0] * abs_[2];
    p10_ = next_[1] * abs_[0], p12_ = next_[1] * abs_[2];
    p20_ = next_[2] * abs_[0], p21_ = next_[2] * abs_[1];
    i01_ = kOne * abs_[1], i02_ = kOne * abs_[2];
    i10_ = kOne * abs_[0], i12_ = kOne * abs_[2];
    i20_ = kOne * abs_[0], i21_ = kOne * abs_[1];
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
  std::int64_t abs_[3] = {0, 0, 0};
  std::int64_t next_[3] = {0, 0, 0};
  std::int64_t p01_ = 0, p02_ = 0, p10_ = 0, p12_ = 0, p20_ = 0, p21_ = 0;
  std::int64_t i01_ = 0, i02_ = 0, i10_ = 0, i12_ = 0, i20_ = 0, i21_ = 0;
};

}  // namespace nbs::detail
