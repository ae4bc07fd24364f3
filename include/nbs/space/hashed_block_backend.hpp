// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The native voxel backend: a hash map of 8³ blocks (after Bonxai / Dymodda), with optional flushing of cold blocks
/// to disk and transparent reload.
///
/// The space grows in any direction (a block is allocated when one of its voxels is first written, the role of the
/// multiple octrees of Dymodda, Fig. 3.11). A block holds the voxel states in the layout of `BlockStates<State>`
/// (block_states.hpp), a bit mask of observed voxels, and a bit mask of the voxels updated in the current scan, used
/// by ProbabilisticVoxelSpace to update a voxel at most once per scan (beam independence, Sec. 3.3.2).
///
/// Flushing (off by default, `set_flush_policy`): after each scan (`end_scan`, called by ProbabilisticVoxelSpace)
/// blocks not written for `idle_scans` scans, then least recently written blocks while memory_bytes() exceeds
/// `memory_budget_bytes`, are written to a per-space folder (temporary file, then std::filesystem::rename into
/// place) and dropped from memory. A failed write loses nothing: the block stays in memory, the error is counted and
/// kept in flush_stats() (the explicit `flush_*` calls throw FileError instead). A write access to a flushed block
/// reloads it (and deletes its file); a const access reads the file into a temporary without caching, so const
/// calls stay free of shared mutable state.
///
/// Thread-safety: concurrent const calls are safe (also on flushed blocks: they only read files); writes, end_scan and
/// the flush calls need exclusive access, except writes to disjoint blocks through one ConcurrentWriter per thread.
/// Const calls on a flushed block throw FileError if its file cannot be read.
///
/// The flush setting and counters are in block_flush.hpp, the block files in detail/block_files.hpp, the flushing
/// and reloading members in detail/hashed_block_flush.hpp (included at the end), the cached read-only lookups
/// (Reader) in detail/block_reader.hpp, the writer of one thread of a parallel scan (ConcurrentWriter) in
/// detail/block_writer.hpp.

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/space/block_flush.hpp"
#include "nbs/space/block_states.hpp"
#include "nbs/space/detail/block_files.hpp"
#include "nbs/space/detail/block_folder_lock.hpp"
#include "nbs/space/detail/block_reader.hpp"
#include "nbs/space/detail/block_writer.hpp"
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
  static_assert(kVoxels == kBlockVoxels);

  /// One 8³ block; voxel (lx, ly, lz) ∈ [0, 8)³ is at index lx + 8·ly + 64·lz.
  struct Block {
    BlockStates<State> states;                             ///< State{} = unknown
    std::array<std::uint64_t, kVoxels / 64> observed{};    ///< bit i set once voxel i was written
    std::array<std::uint64_t, kVoxels / 64> touched{};     ///< bit i: voxel i updated in scan `scan`
    std::uint32_t scan = 0;                                ///< epoch the touched mask belongs to
    std::uint32_t last_written = 0;                        ///< epoch of the last write access (LRU)

    [[nodiscard]] State get(int i) const { return states.load(i); }
    void put(int i, const State& s) { states.store(i, s); }
    [[nodiscard]] bool is_observed(int i) const { return (observed[i >> 6] >> (i & 63)) & 1u; }
    /// Sets the observed bit; returns true if it was not set before.
    bool observe(int i) {
      const std::uint64_t bit = std::uint64_t{1} << (i & 63);
      const bool fresh = (observed[i >> 6] & bit) == 0;
      observed[i >> 6] |= bit;
      return fresh;
    }
    /// True if voxel i was marked updated in the current scan (valid for a block of the current epoch).
    [[nodiscard]] bool is_touched(int i) const { return (touched[i >> 6] >> (i & 63)) & 1u; }
    /// Marks voxel i updated in the current scan; returns false if it already was.
    bool touch(int i) {
      const std::uint64_t bit = std::uint64_t{1} << (i & 63);
      const bool fresh = (touched[i >> 6] & bit) == 0;
      touched[i >> 6] |= bit;
      return fresh;
    }
  };

  /// Throws InvalidArgument unless resolution_m is finite and > 0.
  explicit HashedBlockBackend(double resolution_m) : grid_(resolution_m) {}
  /// Move-only; the moved-from backend is empty (and owns no flush folder).
  HashedBlockBackend(HashedBlockBackend&& o) noexcept { take(o); }
  HashedBlockBackend& operator=(HashedBlockBackend&& o) noexcept {
    if (this != &o) {
      remove_folder();
      take(o);
    }
    return *this;
  }
  HashedBlockBackend(const HashedBlockBackend&) = delete;
  HashedBlockBackend& operator=(const HashedBlockBackend&) = delete;
  ~HashedBlockBackend() { remove_folder(); }

  // ---- VoxelBackend members --------------------------------------------------------------------------------------
  [[nodiscard]] double resolution_m() const { return grid_.resolution_m(); }
  [[nodiscard]] const VoxelGrid& grid() const { return grid_; }

  [[nodiscard]] State get(const VoxelKey& k) const {
    if (!k.valid()) return State{};
    std::unique_ptr<Block> scratch;
    const Block* b = find_block(block_id(k), scratch);
    return b ? b->get(local_index(k)) : State{};
  }
  [[nodiscard]] bool observed(const VoxelKey& k) const {
    if (!k.valid()) return false;
    std::unique_ptr<Block> scratch;
    const Block* b = find_block(block_id(k), scratch);
    return b != nullptr && b->is_observed(local_index(k));
  }
  /// Throws InvalidArgument if k is not valid().
  void set(const VoxelKey& k, const State& s) {
    detail::require(k.valid(), "HashedBlockBackend::set: key (", k.x, ", ", k.y, ", ", k.z, ") out of range");
    Block& b = block(block_id(k));
    const int i = local_index(k);
    b.put(i, s);
    note_observed(b, i);
  }
  /// f(key, state) for every observed voxel, resident blocks in block-id order, then flushed blocks (read from disk,
  /// not reloaded) in block-id order: the order depends on the states only, not on the order the blocks were
  /// allocated in (which a parallel integrate leaves to the threads).
  template <class F>
  void for_each(F&& f) const {
    std::vector<std::pair<std::uint64_t, const Block*>> resident;
    resident.reserve(blocks_.size());
    for (const auto& [id, b] : blocks_) resident.emplace_back(id, b.get());
    std::sort(resident.begin(), resident.end());
    for (const auto& [id, b] : resident) for_each_in(id, *b, f);
    if (flushed_.empty()) return;
    std::vector<std::uint64_t> ids(flushed_.begin(), flushed_.end());
    std::sort(ids.begin(), ids.end());
    Block tmp;
    for (const std::uint64_t id : ids) {
      read_block(id, tmp);
      for_each_in(id, tmp, f);
    }
  }
  [[nodiscard]] std::size_t size() const { return observed_; }
  /// Bytes held in memory: resident blocks (with their heap side-cars), the hash maps' nodes and buckets, the
  /// block cache and the set of flushed block ids. Flushed blocks count only as an id.
  [[nodiscard]] std::size_t memory_bytes() const {
    constexpr std::size_t node = sizeof(std::uint64_t) + sizeof(void*) * 3;  // key, value, next, cached hash
    std::size_t heap = 0;
    for (const auto& [id, b] : blocks_) heap += b->states.heap_bytes();
    return blocks_.size() * (sizeof(Block) + node) + blocks_.bucket_count() * sizeof(void*) + heap +
           flushed_.size() * (sizeof(std::uint64_t) + 2 * sizeof(void*)) + flushed_.bucket_count() * sizeof(void*) +
           sizeof(*this);
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
  /// The resident block with id `id`, or nullptr if it is not in memory (never allocated, or flushed).
  [[nodiscard]] const Block* find_resident_block(std::uint64_t id) const {
    const auto it = blocks_.find(id);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  /// The block with id `id` for reading: the resident block, a flushed block read into `scratch` (valid until
  /// scratch is reused), or nullptr if it was never allocated. Throws FileError if a flushed block cannot be read.
  [[nodiscard]] const Block* find_block(std::uint64_t id, std::unique_ptr<Block>& scratch) const {
    const auto it = blocks_.find(id);
    if (it != blocks_.end()) return it->second.get();
    if (flushed_.empty() || !flushed_.contains(id)) return nullptr;
    if (!scratch) scratch = std::make_unique<Block>();
    read_block(id, *scratch);
    return scratch.get();
  }
  /// Read-only block lookups for one thread's walks, behind a direct-mapped cache of 2^CacheBits recent ids (see
  /// detail/block_reader.hpp). Not thread-safe: one reader per thread. Reader (256 slots) serves many rays; a single
  /// ray takes BasicReader<0>.
  template <int CacheBits>
  using BasicReader = detail::CachedBlockReader<HashedBlockBackend, CacheBits>;
  using Reader = BasicReader<8>;
  /// The block with id `id` for writing, allocated (all voxels unknown) if absent and reloaded if flushed. Its
  /// touched mask belongs to the current epoch. A direct-mapped cache of recently used blocks sits in front of the
  /// hash map; it is cleared by next_epoch() and by every flush, so the first access to a block in a scan always
  /// takes block_slow. Throws FileError if a flushed block cannot be read back.
  [[nodiscard]] Block& block(std::uint64_t id) {
    CacheEntry& c = cache_[cache_slot(id)];
    if (c.id == id) return *c.block;
    return block_slow(id, c);
  }
  /// Write access for one of several threads that write disjoint sets of blocks concurrently, one writer per thread
  /// over one shared mutex (ConcurrentBlockBackend, space/concepts.hpp; detail/block_writer.hpp).
  using ConcurrentWriter = detail::ConcurrentBlockWriter<HashedBlockBackend>;
  /// block(id) without the cache, which it leaves unchanged: not thread-safe; ConcurrentWriter calls it under its
  /// mutex (the block itself is then written by one thread only).
  [[nodiscard]] Block& block_uncached(std::uint64_t id) {
    Block* b = find_or_make(id);
    if (b->scan != epoch_) {
      b->scan = epoch_;
      b->touched.fill(0);
    }
    b->last_written = epoch_;
    return *b;
  }
  /// Adds n voxels written for the first time through a ConcurrentWriter to size().
  void add_observed(std::size_t n) { observed_ += n; }
  /// True if every voxel of the key box with corners a and b (any order, at most 64 voxels, else false) was marked
  /// updated in the current epoch (Block::touch after next_epoch()). Reads only: no block is allocated or reloaded.
  [[nodiscard]] bool all_touched(const VoxelKey& a, const VoxelKey& b) const {
    const VoxelKey lo{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
    const VoxelKey hi{std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
    if ((std::int64_t{hi.x} - lo.x + 1) * (std::int64_t{hi.y} - lo.y + 1) * (std::int64_t{hi.z} - lo.z + 1) > 64)
      return false;
    // The box split at block faces; each part is tested against its block's touched mask, word z of which holds the
    // 8×8 voxels of slab z (bit x + 8·y).
    constexpr int m = kEdge - 1;
    for (std::int32_t bz = lo.z >> kEdgeBits; bz <= hi.z >> kEdgeBits; ++bz)
      for (std::int32_t by = lo.y >> kEdgeBits; by <= hi.y >> kEdgeBits; ++by)
        for (std::int32_t bx = lo.x >> kEdgeBits; bx <= hi.x >> kEdgeBits; ++bx) {
          const Block* blk = epoch_block(VoxelKey{bx, by, bz}.pack());
          if (blk == nullptr) return false;
          const auto part = [](std::int32_t lo_k, std::int32_t hi_k, std::int32_t bk, int& first, int& last) {
            first = std::max(lo_k, bk * kEdge) & m;
            last = std::min(hi_k, bk * kEdge + m) & m;
          };
          int x0, x1, y0, y1, z0, z1;
          part(lo.x, hi.x, bx, x0, x1);
          part(lo.y, hi.y, by, y0, y1);
          part(lo.z, hi.z, bz, z0, z1);
          const std::uint64_t row = ((std::uint64_t{1} << (x1 - x0 + 1)) - 1) << x0;  // bits x0 .. x1 of one y row
          std::uint64_t mask = 0;
          for (int y = y0; y <= y1; ++y) mask |= row << (kEdge * y);
          for (int z = z0; z <= z1; ++z)
            if ((touched_word(*blk, z) & mask) != mask) return false;
        }
    return true;
  }
  /// The resident block `id` if it was accessed for writing in the current epoch (its touched mask is current).
  [[nodiscard]] const Block* epoch_block(std::uint64_t id) const {
    const CacheEntry& c = cache_[cache_slot(id)];
    const Block* b = c.id == id ? c.block : find_resident_block(id);
    return b != nullptr && b->scan == epoch_ ? b : nullptr;
  }
  /// Word w of b's touched mask: bits 64·w … 64·w + 63, i.e. the voxels of slab z = w (x + 8·y within the word).
  [[nodiscard]] static std::uint64_t touched_word(const Block& b, int w) { return b.touched[static_cast<std::size_t>(w)]; }
  /// Marks voxel i of b observed and keeps the observed count.
  void note_observed(Block& b, int i) { observed_ += b.observe(i) ? 1u : 0u; }
  /// Blocks allocated so far, resident or flushed.
  [[nodiscard]] std::size_t block_count() const { return blocks_.size() + flushed_.size(); }
  /// Blocks in memory.
  [[nodiscard]] std::size_t resident_block_count() const { return blocks_.size(); }
  /// Blocks on disk.
  [[nodiscard]] std::size_t flushed_block_count() const { return flushed_.size(); }
  /// Whether block `id` (block_id()) is on disk.
  [[nodiscard]] bool is_flushed(std::uint64_t id) const { return !flushed_.empty() && flushed_.contains(id); }

  /// Starts a new update epoch (one per scan) and returns it; a voxel whose block's touched bit is set was updated
  /// in this epoch. Epochs are 32-bit and start at 1.
  [[nodiscard]] std::uint32_t next_epoch() {
    cache_.fill(CacheEntry{});
    return ++epoch_;
  }
  /// Applies the flush policy after a scan (see file comment). Never throws for I/O errors: failures are counted in
  /// flush_stats() and the blocks stay in memory.
  void end_scan() {
    if (!flush_enabled()) return;
    try {
      if (setting_.idle_scans > 0) flush_where([&](const Block& b) { return epoch_ - b.last_written >= setting_.idle_scans; });
      if (setting_.memory_budget_bytes > 0) flush_to_budget(setting_.memory_budget_bytes);
    } catch (const FileError&) {
      // already recorded in stats_
    }
  }

  // ---- Flushing to disk -------------------------------------------------------------------------------------------
  /// Sets the automatic flush policy (applied by end_scan()). Throws InvalidArgument if a policy is set without a
  /// directory.
  void set_flush_policy(BlockFlushSetting s) {
    s.validate("HashedBlockBackend flush policy");
    if (!folder_.empty() && s.directory != setting_.directory) {
      reload_all();
      remove_folder();
    }
    setting_ = std::move(s);
  }
  [[nodiscard]] const BlockFlushSetting& flush_policy() const { return setting_; }
  [[nodiscard]] const BlockFlushStats& flush_stats() const { return stats_; }
  /// The per-space folder holding flushed blocks (empty before the first flush).
  [[nodiscard]] const std::filesystem::path& flush_folder() const { return folder_; }

  /// Flushes every resident block not written during the last `idle_scans` epochs (0: every block) to
  /// flush_policy().directory. Returns the number of blocks written. Throws FileError at the first failed write: that
  /// block and the ones not yet tried stay in memory (the voxel states are unchanged either way); InvalidArgument if
  /// no directory is set.
  std::size_t flush_idle_blocks(std::uint32_t idle_scans) {
    detail::require(!setting_.directory.empty(), "HashedBlockBackend::flush_idle_blocks: no directory set");
    return flush_where([&](const Block& b) { return epoch_ - b.last_written >= idle_scans; });
  }
  /// Flushes every resident block.
  std::size_t flush_all() { return flush_idle_blocks(0); }
  /// Reloads the flushed blocks among `ids` (others are ignored) all or nothing: every file is read into memory
  /// first; if one cannot be read, FileError is thrown and nothing changed (the blocks stay flushed, no counter
  /// moves). Used by ProbabilisticVoxelSpace::integrate to stage a scan before any voxel changes.
  void reload_blocks(const std::vector<std::uint64_t>& ids) {
    if (flushed_.empty()) return;
    std::vector<std::pair<std::uint64_t, std::unique_ptr<Block>>> staged;
    for (const std::uint64_t id : ids) {
      if (!flushed_.contains(id)) continue;
      auto b = std::make_unique<Block>();
      read_block(id, *b);  // may throw: nothing changed yet
      staged.emplace_back(id, std::move(b));
    }
    blocks_.reserve(blocks_.size() + staged.size());
    for (auto& [id, b] : staged) {
      blocks_.emplace(id, std::move(b));
      flushed_.erase(id);
      std::error_code ec;
      std::filesystem::remove(block_path(id), ec);
      ++stats_.blocks_reloaded;
    }
  }
  /// Reloads every flushed block into memory. Throws FileError if one cannot be read.
  void reload_all() {
    std::vector<std::uint64_t> ids(flushed_.begin(), flushed_.end());
    for (const std::uint64_t id : ids) (void)find_or_make(id);
  }

private:
  template <class F>
  static void for_each_in(std::uint64_t id, const Block& b, F& f) {
    const VoxelKey base = block_origin(id);
    for (int w = 0; w < kVoxels / 64; ++w) {
      for (std::uint64_t m = b.observed[w]; m != 0; m &= m - 1) {
        const int i = w * 64 + std::countr_zero(m);
        f(VoxelKey{base.x + (i & 7), base.y + ((i >> 3) & 7), base.z + (i >> 6)}, b.get(i));
      }
    }
  }

  [[nodiscard]] bool flush_enabled() const {
    return !setting_.directory.empty() && (setting_.idle_scans > 0 || setting_.memory_budget_bytes > 0);
  }

  // Allocation, flushing and reloading (defined in detail/hashed_block_flush.hpp).
  Block* find_or_make(std::uint64_t id);

  // Flushes the resident blocks with pred(block), in (last_written, id) order; see flush_idle_blocks.
  template <class Pred>
  std::size_t flush_where(Pred&& pred);
  void flush_to_budget(std::size_t budget);
  // Writes the blocks in `order` while more(bytes freed by the previous block) holds.
  template <class More>
  std::size_t flush_ids(const std::vector<std::pair<std::uint32_t, std::uint64_t>>& order, More&& more);

  [[nodiscard]] std::filesystem::path block_path(std::uint64_t id) const {
    return detail::block_file_path(folder_, id);
  }

  // Creates the per-space folder on first use, after removing the folders of dead owners beside it, and locks it
  // (detail/block_folder_lock.hpp; a folder that cannot be locked still works, it is only not cleaned up if killed).
  void ensure_folder() {
    if (!folder_.empty()) return;
    stats_.stale_folders_removed += detail::remove_stale_block_folders(setting_.directory);
    folder_ = detail::create_block_folder<HashedBlockBackend>(setting_.directory);
    (void)folder_lock_.acquire_new(folder_);
  }

  void fail(const std::string& message) {
    ++stats_.failed_writes;
    stats_.last_error = message;
    throw FileError(message);
  }

  void write_block(std::uint64_t id, const Block& b);  // detail/hashed_block_flush.hpp
  void read_block(std::uint64_t id, Block& b) const;    // detail/hashed_block_flush.hpp

  void remove_folder() {
    if (folder_.empty()) return;
    std::error_code ec;
    std::filesystem::remove_all(folder_, ec);
    folder_.clear();
    folder_lock_.release();
  }

  void take(HashedBlockBackend& o) {
    grid_ = o.grid_;
    cache_ = o.cache_;
    blocks_ = std::move(o.blocks_);
    flushed_ = std::move(o.flushed_);
    observed_ = o.observed_;
    epoch_ = o.epoch_;
    setting_ = std::move(o.setting_);
    stats_ = std::move(o.stats_);
    folder_ = std::move(o.folder_);
    folder_lock_ = std::move(o.folder_lock_);
    o.cache_.fill(CacheEntry{});
    o.blocks_.clear();
    o.flushed_.clear();
    o.observed_ = 0;
    o.epoch_ = 0;
    o.setting_ = {};
    o.stats_ = {};
    o.folder_.clear();
  }

  static constexpr int kCacheBits = 10;
  [[nodiscard]] static std::size_t cache_slot(std::uint64_t id) { return (id * 0x9E3779B97F4A7C15ull) >> (64 - kCacheBits); }
  struct CacheEntry {
    std::uint64_t id = ~std::uint64_t{0};  // never a packed key (those use 63 bits)
    Block* block = nullptr;
  };

  // block() after a cache miss: hash map (allocation, reload), epoch of the touched mask, cache entry c.
  [[gnu::noinline]] Block& block_slow(std::uint64_t id, CacheEntry& c) {
    Block& b = block_uncached(id);
    c = {id, &b};
    return b;
  }

  VoxelGrid grid_{1.0};
  std::array<CacheEntry, std::size_t{1} << kCacheBits> cache_{};
  std::unordered_map<std::uint64_t, std::unique_ptr<Block>> blocks_;
  std::unordered_set<std::uint64_t> flushed_;  ///< ids of blocks on disk (never also in blocks_)
  std::size_t observed_ = 0;
  std::uint32_t epoch_ = 0;
  BlockFlushSetting setting_;
  BlockFlushStats stats_;
  std::filesystem::path folder_;
  detail::BlockFolderLock folder_lock_;  // held while folder_ exists
};

}  // namespace nbs

#include "nbs/space/detail/hashed_block_flush.hpp"
