// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Segment walks over a BlockBackend (space/concepts.hpp) that look a block up only when the walk enters a new block.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "nbs/core/types.hpp"
#include "nbs/space/detail/segment_clip.hpp"
#include "nbs/space/detail/segment_walker.hpp"
#include "nbs/space/concepts.hpp"

namespace nbs::detail {

/// ReaderOf<B, Bits>::type is B::BasicReader<Bits> (lazily, so that std::conditional_t can name it for any backend).
template <class B, int Bits>
struct ReaderOf {
  using type = typename B::template BasicReader<Bits>;
};

/// Key of voxel `i` of the block with block key `bk` (= voxel key >> kEdgeBits per axis) of a BlockBackend BE.
template <class BE>
[[nodiscard]] VoxelKey voxel_key_in_block(const VoxelKey& bk, int i) {
  constexpr int m = BE::kEdge - 1, e = BE::kEdgeBits;
  return {(bk.x << e) | (i & m), (bk.y << e) | ((i >> e) & m), (bk.z << e) | (i >> (2 * e))};
}

/// The loop of walk_untouched over any stepper whose step() returns the axis crossed (SegmentWalker or
/// CommonDenominatorStepper): the voxel index is stepped inside a block; the block is looked up on leaving it. Fresh
/// voxels (rare) are collected and handed to visit in batches, so that the loop itself makes no calls but the block
/// lookups. Stepper and signs are taken by value so that the loop keeps them in registers. After `steps` steps the
/// voxel reached is visited if include_last, with is_end = last_is_end.
template <class BE, class Stepper, class Visit>
void walk_untouched_steps(BE& be, Stepper st, const VoxelKey start, const int sx, const int sy, const int sz,
                          std::int64_t steps, const bool include_last, const bool last_is_end, Visit& visit) {
  using Block = typename BE::Block;
  constexpr int e = BE::kEdgeBits, m = BE::kEdge - 1;
  struct Fresh {  // no member initialisers: the batch is not zeroed on every call
    Block* block;
    std::int32_t bx, by, bz, index;
  };
  constexpr int kBatch = 16;
  Fresh fresh[kBatch];
  int n_fresh = 0;
  const auto flush = [&] {
    for (int f = 0; f < n_fresh; ++f)
      visit(*fresh[f].block, fresh[f].index, VoxelKey{fresh[f].bx, fresh[f].by, fresh[f].bz}, false);
    n_fresh = 0;
  };
  VoxelKey bk{start.x >> e, start.y >> e, start.z >> e};
  Block* blk = &be.block(bk.pack());
  int i = BE::local_index(start);
  for (std::int64_t n = steps; n > 0; --n) {
    if (!blk->is_touched(i)) {  // test first: the store happens only for the rare fresh voxel
      (void)blk->touch(i);
      fresh[n_fresh++] = {blk, bk.x, bk.y, bk.z, i};
      if (n_fresh == kBatch) flush();
    }
    const int axis = st.step();
    int s, local;  // local: new position along `axis` inside the block; outside [0, m]: the walk left the block
    switch (axis) {
      case 0:
        s = sx;
        local = (i & m) + s;
        i += s;
        break;
      case 1:
        s = sy;
        local = ((i >> e) & m) + s;
        i += s * BE::kEdge;
        break;
      default:
        s = sz;
        local = (i >> (2 * e)) + s;
        i += s * BE::kEdge * BE::kEdge;
        break;
    }
    if (static_cast<unsigned>(local) > static_cast<unsigned>(m)) {
      bk[axis] += s;
      i -= s * (BE::kEdge << (e * axis));  // wrap to the opposite face of the next block
      blk = &be.block(bk.pack());
    }
  }
  flush();
  if (include_last && blk->touch(i)) visit(*blk, i, bk, last_is_end);
}

/// walk_untouched_steps over the walk of q (or of the rest of a walk, after_crossing) for `steps` steps.
template <class BE, class Visit>
void walk_untouched_run(BE& be, const SegmentSetup& q, std::int64_t steps, bool include_last, bool last_is_end,
                        Visit& visit) {
  if (const auto fast = CommonDenominatorStepper::make(q)) {
    walk_untouched_steps(be, *fast, q.key, q.sign[0], q.sign[1], q.sign[2], steps, include_last, last_is_end, visit);
  } else {
    walk_untouched_steps(be, SegmentWalker(q), q.key, q.sign[0], q.sign[1], q.sign[2], steps, include_last,
                         last_is_end, visit);
  }
}

/// Writing walk of the quantised segment q (valid keys) that updates each voxel at most once per scan: for every voxel
/// of the walk (the end voxel only if include_end) whose "updated in this scan" bit is clear, sets the bit and calls
/// visit(Block&, index, block_key, is_end_voxel) (block_key: see voxel_key_in_block), allocating blocks as needed.
/// Voxels already updated in this scan cost one DDA step and one bit test. Returns the number of voxels of the walk
/// (visited or skipped).
/// `be` is a BlockBackend or a writer with the same `block(id)`, `local_index`, `kEdge`, `kEdgeBits` and `Block`
/// (a ConcurrentWriter).
template <class BE, class Visit>
std::int64_t walk_untouched(BE& be, const SegmentSetup& q, bool include_end, Visit&& visit) {
  walk_untouched_run(be, q, q.steps(), include_end, true, visit);
  return q.steps() + (include_end ? 1 : 0);
}

/// walk_untouched restricted to the voxels of q's walk whose key along `axis` lies in [lo, hi): since a walk is
/// monotone along every axis they are one run of it, which is walked alone (started by after_crossing, stopped on its
/// last voxel). Calls visit for the same voxels, in the same order, as walk_untouched would for them; looks up only
/// blocks holding such voxels (with lo, hi multiples of kEdge: only blocks of the slab — what lets threads that own
/// disjoint slabs of blocks walk concurrently). Returns the number of voxels of the walk in the slab (the end voxel
/// counted only if include_end).
template <class BE, class Visit>
std::int64_t walk_untouched_slab(BE& be, const SegmentSetup& q, int axis, std::int32_t lo, std::int32_t hi,
                                 bool include_end, Visit&& visit) {
  const std::int32_t k0 = q.key[axis];
  const int s = q.sign[axis];
  if (s == 0) return k0 >= lo && k0 < hi ? walk_untouched(be, q, include_end, visit) : 0;
  const std::int32_t k1 = k0 + s * q.remaining[axis];  // end key along axis
  // a, z: the first and last key along axis of the run inside [lo, hi), in walk order.
  const std::int32_t a = s > 0 ? std::max(k0, lo) : std::min(k0, hi - 1);
  const std::int32_t z = s > 0 ? std::min(k1, hi - 1) : std::max(k1, lo);
  if (s > 0 ? a > z : a < z) return 0;
  const std::int32_t j_in = s > 0 ? a - k0 : k0 - a;  // crossings along axis before the run
  const SegmentRest from = j_in > 0 ? after_crossing(q, axis, j_in) : SegmentRest{q, 0};
  if (z == k1) {  // the run ends with the walk
    const std::int64_t steps = q.steps() - from.done;
    walk_untouched_run(be, from.rest, steps, include_end, true, visit);
    return steps + (include_end ? 1 : 0);
  }
  // The run ends before the crossing out of it: n voxels, the last one visited after n − 1 steps.
  const std::int64_t n = after_crossing(q, axis, (s > 0 ? z - k0 : k0 - z) + 1).done - from.done;
  walk_untouched_run(be, from.rest, n - 1, true, false, visit);
  return n;
}

/// The loop of walk_blocks_const over a stepper (SegmentWalker or CommonDenominatorStepper), in the manner of
/// walk_untouched_steps: the voxel index and key follow the returned axes; the block is looked up on leaving one.
template <class Reader, class Stepper, class Visit>
std::uint32_t walk_blocks_const_steps(Reader& rd, Stepper st, const SegmentSetup& q, Visit& visit) {
  using BE = typename Reader::Backend;
  constexpr int e = BE::kEdgeBits, m = BE::kEdge - 1;
  VoxelKey k = q.key;
  const typename BE::Block* blk = rd.find(BE::block_id(k));
  int i = BE::local_index(k);
  std::uint32_t n = 0;
  for (std::int64_t left = q.steps();; --left) {
    ++n;
    if (!visit(blk, i, k)) return n;
    if (left == 0) return n;
    const int axis = st.step();
    const int s = q.sign[axis];
    k[axis] += s;
    const int shift = e * axis;
    const int local = ((i >> shift) & m) + s;  // new position along `axis` inside the block
    i += s * (1 << shift);
    if (static_cast<unsigned>(local) > static_cast<unsigned>(m)) {
      i -= s * (BE::kEdge << shift);  // wrap to the opposite face of the next block
      blk = rd.find(BE::block_id(k));
    }
  }
}

/// Read-only walk from a to b (voxel units, valid keys), the voxels of SegmentWalker(a, b) in order:
/// visit(const Block* or nullptr, index, key) for each voxel, end voxel included; stops early when visit returns
/// false. Blocks are looked up through `rd` (see HashedBlockBackend::Reader). Returns the number of voxels visited.
template <class Reader, class Visit>
std::uint32_t walk_blocks_const(Reader& rd, const Vec3& a, const Vec3& b, Visit&& visit) {
  const SegmentSetup q(a, b);
  if (const auto fast = CommonDenominatorStepper::make(q)) return walk_blocks_const_steps(rd, *fast, q, visit);
  return walk_blocks_const_steps(rd, SegmentWalker(q), q, visit);
}

}  // namespace nbs::detail
