// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// CachedBlockReader: HashedBlockBackend's read-only block lookups for one thread's walks (the backend's
/// BasicReader<CacheBits> / Reader), find_block behind a direct-mapped cache of 2^CacheBits recent ids.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace nbs::detail {

/// Read-only block lookups for one thread's walks: find_block behind a direct-mapped cache of 2^CacheBits recent
/// ids (resident blocks and ids without a block; a flushed block read into the reader's scratch is not cached).
/// Valid while the backend is not modified. Not thread-safe: one reader per thread; several may read one backend
/// concurrently. Reader (256 slots, 4 KiB) serves many rays; a single ray, which seldom revisits a block, takes
/// BasicReader<0>.
template <class BackendT, int CacheBits>
class CachedBlockReader {
  using Block = typename BackendT::Block;

public:
  using Backend = BackendT;
  explicit CachedBlockReader(const Backend& be) : be_(&be) {}
  /// find_block(id): the block, or nullptr if it was never allocated. A flushed block stays valid until the next
  /// find of another flushed block. Throws FileError if a flushed block cannot be read.
  [[nodiscard]] const Block* find(std::uint64_t id) {
    Slot& s = slots_[kBits == 0 ? 0 : (id * 0x9E3779B97F4A7C15ull) >> ((64 - kBits) & 63)];
    if (s.id == id) return s.block;
    return find_slow(id, s);
  }

private:
  static constexpr int kBits = CacheBits;
  static_assert(kBits >= 0 && kBits <= 16);
  struct Slot {
    std::uint64_t id = ~std::uint64_t{0};  // never a packed key (those use 63 bits)
    const Block* block = nullptr;
  };
  const Block* find_slow(std::uint64_t id, Slot& s) {
    const Block* b = be_->find_block(id, scratch_);
    if (b == nullptr || b != scratch_.get()) s = {id, b};
    return b;
  }
  const Backend* be_;
  std::array<Slot, std::size_t{1} << kBits> slots_{};
  std::unique_ptr<Block> scratch_;
};

}  // namespace nbs::detail
