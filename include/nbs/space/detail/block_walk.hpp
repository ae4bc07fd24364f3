#pragma once
/// \file
/// Segment walks over a HashedBlockBackend that look a block up only when the walk enters a new block.

#include <memory>
#include <type_traits>

#include "nbs/core/types.hpp"
#include "nbs/space/detail/segment_walker.hpp"
#include "nbs/space/hashed_block_backend.hpp"

namespace nbs::detail {

template <class B>
inline constexpr bool is_hashed_block_backend_v = false;
template <class S>
inline constexpr bool is_hashed_block_backend_v<HashedBlockBackend<S>> = true;

/// Writing walk from a to b (voxel units, valid keys): visit(Block&, index, key, is_end_voxel) for each voxel,
/// allocating blocks as needed; the end voxel is skipped unless include_end. Inside a block the voxel index is
/// stepped directly; the block is looked up only when the walk leaves it.
template <class S, class Visit>
void walk_blocks(HashedBlockBackend<S>& be, const Vec3& a, const Vec3& b, bool include_end, Visit&& visit) {
  using BE = HashedBlockBackend<S>;
  constexpr int kMask = BE::kEdge - 1;
  SegmentWalker w(a, b);
  auto* blk = &be.block(BE::block_id(w.key()));
  int i = BE::local_index(w.key());
  const int sx = w.sign(0), sy = w.sign(1), sz = w.sign(2);
  int lx = w.key().x & kMask, ly = w.key().y & kMask, lz = w.key().z & kMask;  // position inside the block
  for (;;) {
    const bool last = w.remaining() == 0;
    if (last && !include_end) return;
    visit(*blk, i, w.key(), last);
    if (last) return;
    bool leaves;
    switch (w.step()) {
      case 0:
        lx += sx;
        leaves = static_cast<unsigned>(lx) > static_cast<unsigned>(kMask);
        i += sx;
        break;
      case 1:
        ly += sy;
        leaves = static_cast<unsigned>(ly) > static_cast<unsigned>(kMask);
        i += sy * BE::kEdge;
        break;
      default:
        lz += sz;
        leaves = static_cast<unsigned>(lz) > static_cast<unsigned>(kMask);
        i += sz * BE::kEdge * BE::kEdge;
        break;
    }
    if (leaves) {
      blk = &be.block(BE::block_id(w.key()));
      i = BE::local_index(w.key());
      lx &= kMask;
      ly &= kMask;
      lz &= kMask;
    }
  }
}

/// Read-only walk from a to b (voxel units, valid keys): visit(const Block* or nullptr, index, key) for each
/// voxel, end voxel included; stops early when visit returns false. Flushed blocks are read into a scratch block
/// owned by the walk. Returns the number of voxels visited.
template <class S, class Visit>
std::uint32_t walk_blocks_const(const HashedBlockBackend<S>& be, const Vec3& a, const Vec3& b, Visit&& visit) {
  using BE = HashedBlockBackend<S>;
  SegmentWalker w(a, b);
  VoxelKey k = w.key();
  std::unique_ptr<typename BE::Block> scratch;
  const typename BE::Block* blk = be.find_block(BE::block_id(k), scratch);
  std::uint32_t n = 0;
  for (;;) {
    ++n;
    if (!visit(blk, BE::local_index(k), k)) return n;
    if (w.remaining() == 0) return n;
    const int axis = w.step();
    k = w.key();
    if ((k[axis] & (BE::kEdge - 1)) == (w.sign(axis) > 0 ? 0 : BE::kEdge - 1))
      blk = be.find_block(BE::block_id(k), scratch);
  }
}

/// Clips the segment a → b to the closed box (Liang–Barsky). Returns false if they do not meet; otherwise sets
/// [t0, t1] ⊆ [0, 1].
inline bool clip_segment(const Vec3& a, const Vec3& b, const Aabb& box, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double d = b[i] - a[i];
    if (d == 0.0) {
      if (a[i] < box.min[i] || a[i] > box.max[i]) return false;
      continue;
    }
    double ta = (box.min[i] - a[i]) / d;
    double tb = (box.max[i] - a[i]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

/// a + t·(b − a), clamped into the box (guards against round-off past the faces).
inline Vec3 point_in_box(const Vec3& a, const Vec3& b, double t, const Aabb& box) {
  return (a + t * (b - a)).cwiseMax(box.min).cwiseMin(box.max);
}

}  // namespace nbs::detail
