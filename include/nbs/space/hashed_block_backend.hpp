#pragma once
/// \file
/// The native voxel backend: a hash map of 8³ blocks, each a flat array of states (after Bonxai / Dymodda).
///
/// The space grows in any direction (a block is allocated when one of its voxels is first written, the role of the
/// multiple octrees of Dymodda, Fig. 3.11). Each block also carries one 8-bit stamp per voxel, used by
/// ProbabilisticVoxelSpace to update a voxel at most once per scan (beam independence, Sec. 3.3.2), and a bit mask
/// of observed voxels. Thread-safety: concurrent const calls are safe; writes need exclusive access.

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>

#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Hashed 8³-block storage of `StateT` per voxel. Models VoxelBackend.
template <class StateT>
class HashedBlockBackend {
public:
  using State = StateT;
  static constexpr int kEdgeBits = 3;                 ///< block edge = 2^3 voxels
  static constexpr int kEdge = 1 << kEdgeBits;        ///< 8
  static constexpr int kVoxels = kEdge * kEdge * kEdge;  ///< 512 voxels per block

  /// One 8³ block; voxel (lx, ly, lz) ∈ [0, 8)³ is at index lx + 8·ly + 64·lz.
  struct Block {
    std::array<State, kVoxels> state{};                    ///< State{} = unknown
    std::array<std::uint8_t, kVoxels> stamp{};             ///< scan epoch of the last update (0 = none)
    std::array<std::uint64_t, kVoxels / 64> observed{};    ///< bit i set once voxel i was written

    [[nodiscard]] bool is_observed(int i) const { return (observed[i >> 6] >> (i & 63)) & 1u; }
    /// Sets the observed bit; returns true if it was not set before.
    bool observe(int i) {
      const std::uint64_t bit = std::uint64_t{1} << (i & 63);
      const bool fresh = (observed[i >> 6] & bit) == 0;
      observed[i >> 6] |= bit;
      return fresh;
    }
  };

  /// Throws InvalidArgument unless resolution_m is finite and > 0.
  explicit HashedBlockBackend(double resolution_m) : grid_(resolution_m) {}
  /// Move-only; the moved-from backend is empty.
  HashedBlockBackend(HashedBlockBackend&& o) noexcept
      : grid_(o.grid_), cache_(o.cache_), blocks_(std::move(o.blocks_)), observed_(o.observed_), epoch_(o.epoch_) {
    o.reset_after_move();
  }
  HashedBlockBackend& operator=(HashedBlockBackend&& o) noexcept {
    if (this != &o) {
      grid_ = o.grid_;
      cache_ = o.cache_;
      blocks_ = std::move(o.blocks_);
      observed_ = o.observed_;
      epoch_ = o.epoch_;
      o.reset_after_move();
    }
    return *this;
  }
  HashedBlockBackend(const HashedBlockBackend&) = delete;
  HashedBlockBackend& operator=(const HashedBlockBackend&) = delete;
  ~HashedBlockBackend() = default;

  // ---- VoxelBackend members --------------------------------------------------------------------------------------
  [[nodiscard]] double resolution_m() const { return grid_.resolution_m(); }
  [[nodiscard]] const VoxelGrid& grid() const { return grid_; }

  [[nodiscard]] State get(const VoxelKey& k) const {
    if (!k.valid()) return State{};
    const Block* b = find_block(block_id(k));
    return b ? b->state[local_index(k)] : State{};
  }
  [[nodiscard]] bool observed(const VoxelKey& k) const {
    if (!k.valid()) return false;
    const Block* b = find_block(block_id(k));
    return b != nullptr && b->is_observed(local_index(k));
  }
  /// Throws InvalidArgument if k is not valid().
  void set(const VoxelKey& k, const State& s) {
    detail::require(k.valid(), "HashedBlockBackend::set: key (", k.x, ", ", k.y, ", ", k.z, ") out of range");
    Block& b = block(block_id(k));
    const int i = local_index(k);
    b.state[i] = s;
    note_observed(b, i);
  }
  template <class F>
  void for_each(F&& f) const {
    for (const auto& [id, b] : blocks_) {
      const VoxelKey base = block_origin(id);
      for (int w = 0; w < kVoxels / 64; ++w) {
        for (std::uint64_t m = b->observed[w]; m != 0; m &= m - 1) {
          const int i = w * 64 + std::countr_zero(m);
          f(VoxelKey{base.x + (i & 7), base.y + ((i >> 3) & 7), base.z + (i >> 6)}, b->state[i]);
        }
      }
    }
  }
  [[nodiscard]] std::size_t size() const { return observed_; }
  [[nodiscard]] std::size_t memory_bytes() const {
    // blocks + per-entry node of std::unordered_map (key, pointer, next, cached hash) + bucket array
    constexpr std::size_t node = sizeof(std::uint64_t) + sizeof(void*) * 3;
    return blocks_.size() * (sizeof(Block) + node) + blocks_.bucket_count() * sizeof(void*) + sizeof(*this);  // incl. cache
  }
  [[nodiscard]] KeyBox observed_key_bounds() const {
    KeyBox box;
    for_each([&box](const VoxelKey& k, const State&) { box.extend(k); });
    return box;
  }

  /// Every valid key (21 bits per axis).
  [[nodiscard]] static KeyBox key_range() {
    return {{VoxelKey::kMinIndex, VoxelKey::kMinIndex, VoxelKey::kMinIndex},
            {VoxelKey::kMaxIndex, VoxelKey::kMaxIndex, VoxelKey::kMaxIndex}};
  }

  // ---- Block-level access (fast paths of ProbabilisticVoxelSpace) ------------------------------------------------
  /// Packed id of the block containing key k.
  [[nodiscard]] static std::uint64_t block_id(const VoxelKey& k) {
    return VoxelKey{k.x >> kEdgeBits, k.y >> kEdgeBits, k.z >> kEdgeBits}.pack();
  }
  /// Index of key k inside its block.
  [[nodiscard]] static int local_index(const VoxelKey& k) {
    return (k.x & (kEdge - 1)) | ((k.y & (kEdge - 1)) << kEdgeBits) | ((k.z & (kEdge - 1)) << (2 * kEdgeBits));
  }
  /// Key of voxel (0, 0, 0) of block `id`.
  [[nodiscard]] static VoxelKey block_origin(std::uint64_t id) {
    const VoxelKey b = VoxelKey::unpack(id);
    return {b.x * kEdge, b.y * kEdge, b.z * kEdge};
  }
  /// The block with id `id`, or nullptr if it was never allocated.
  [[nodiscard]] const Block* find_block(std::uint64_t id) const {
    const auto it = blocks_.find(id);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  [[nodiscard]] Block* find_block(std::uint64_t id) {
    const auto it = blocks_.find(id);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  /// The block with id `id`, allocated (all voxels unknown) if absent. A direct-mapped cache of recently used
  /// blocks sits in front of the hash map (blocks are never freed, so cached pointers stay valid).
  [[nodiscard]] Block& block(std::uint64_t id) {
    CacheEntry& c = cache_[(id * 0x9E3779B97F4A7C15ull) >> (64 - kCacheBits)];
    if (c.id == id) return *c.block;
    auto& slot = blocks_[id];
    if (!slot) slot = std::make_unique<Block>();
    c = {id, slot.get()};
    return *slot;
  }
  /// Marks voxel i of b observed and keeps the observed count.
  void note_observed(Block& b, int i) { observed_ += b.observe(i) ? 1u : 0u; }
  [[nodiscard]] std::size_t block_count() const { return blocks_.size(); }

  /// Starts a new update epoch and returns its stamp (1..255). On wrap-around all stamps are cleared first, so a
  /// stamp equal to the returned value always means "updated in this epoch".
  [[nodiscard]] std::uint8_t next_epoch() {
    if (epoch_ == 255) {
      for (auto& [id, b] : blocks_) b->stamp.fill(0);
      epoch_ = 0;
    }
    return ++epoch_;
  }

private:
  void reset_after_move() {
    cache_.fill(CacheEntry{});
    blocks_.clear();
    observed_ = 0;
    epoch_ = 0;
  }

  static constexpr int kCacheBits = 10;
  struct CacheEntry {
    std::uint64_t id = ~std::uint64_t{0};  // never a packed key (those use 63 bits)
    Block* block = nullptr;
  };

  VoxelGrid grid_;
  std::array<CacheEntry, std::size_t{1} << kCacheBits> cache_{};
  std::unordered_map<std::uint64_t, std::unique_ptr<Block>> blocks_;
  std::size_t observed_ = 0;
  std::uint8_t epoch_ = 0;
};

}  // namespace nbs
