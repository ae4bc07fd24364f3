// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// HashedBlockBackend's flushing and reloading members, defined out of the class (hashed_block_backend.hpp, which
/// includes this file at its end; see its file comment for the policy): allocating a block or reloading a flushed one
/// (find_or_make), the choice of blocks to flush (by predicate, or least recently written until under a memory
/// budget), writing one block (a failure is counted in flush_stats() and thrown as FileError, the block staying
/// resident), and reading a flushed block. Exclusive access, except read_block, which const calls use.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/space/detail/block_files.hpp"
#include "nbs/space/hashed_block_backend.hpp"

namespace nbs {

template <class StateT>
auto HashedBlockBackend<StateT>::find_or_make(std::uint64_t id) -> Block* {
  auto it = blocks_.find(id);
  if (it != blocks_.end()) return it->second.get();
  auto b = std::make_unique<Block>();
  const bool flushed = !flushed_.empty() && flushed_.contains(id);
  if (flushed) read_block(id, *b);  // may throw: nothing changed yet
  Block* raw = b.get();
  blocks_.emplace(id, std::move(b));
  if (flushed) {
    flushed_.erase(id);
    std::error_code ec;
    std::filesystem::remove(block_path(id), ec);  // a stale file is harmless: it is overwritten by the next flush
    ++stats_.blocks_reloaded;
  }
  return raw;
}

template <class StateT>
template <class Pred>
std::size_t HashedBlockBackend<StateT>::flush_where(Pred&& pred) {
  std::vector<std::pair<std::uint32_t, std::uint64_t>> order;
  for (const auto& [id, b] : blocks_)
    if (pred(*b)) order.push_back({b->last_written, id});
  std::sort(order.begin(), order.end());
  return flush_ids(order, [](std::size_t) { return true; });
}

template <class StateT>
void HashedBlockBackend<StateT>::flush_to_budget(std::size_t budget) {
  std::size_t bytes = memory_bytes();
  if (bytes <= budget) return;
  std::vector<std::pair<std::uint32_t, std::uint64_t>> order;
  for (const auto& [id, b] : blocks_) order.push_back({b->last_written, id});
  std::sort(order.begin(), order.end());
  (void)flush_ids(order, [&](std::size_t freed) {
    if (bytes <= budget) return false;
    bytes -= std::min(bytes, freed);
    return true;
  });
}

template <class StateT>
template <class More>
std::size_t HashedBlockBackend<StateT>::flush_ids(const std::vector<std::pair<std::uint32_t, std::uint64_t>>& order,
                                                More&& more) {
  std::size_t n = 0, freed = 0;
  cache_.fill(CacheEntry{});
  for (const auto& [last, id] : order) {
    if (!more(freed)) break;
    const auto it = blocks_.find(id);
    write_block(id, *it->second);  // throws FileError: this block stays resident
    freed = sizeof(Block) + it->second->states.heap_bytes();
    blocks_.erase(it);
    flushed_.insert(id);
    ++stats_.blocks_written;
    ++n;
  }
  return n;
}

template <class StateT>
void HashedBlockBackend<StateT>::write_block(std::uint64_t id, const Block& b) {
  try {
    ensure_folder();
  } catch (const FileError& e) {
    fail(e.what());
  }
  detail::write_block_file(block_path(id), id, b, [this](const std::string& message) { fail(message); });
}

template <class StateT>
void HashedBlockBackend<StateT>::read_block(std::uint64_t id, Block& b) const {
  const std::filesystem::path path = block_path(id);
  if (!detail::read_block_file(path, id, b))
    throw FileError(detail::concat("HashedBlockBackend: cannot read flushed block '", path.string(), "'"));
  b.touched.fill(0);
  b.scan = 0;
  b.last_written = epoch_;
}

}  // namespace nbs
