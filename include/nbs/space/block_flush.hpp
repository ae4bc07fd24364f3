// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The flush policy and flush counters of HashedBlockBackend (hashed_block_backend.hpp), which writes cold blocks to
/// disk and reloads them transparently; see that file for when blocks are flushed and what a failure does.

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "nbs/core/error.hpp"

namespace nbs {

/// When HashedBlockBackend writes cold blocks to disk. Flushing is on when `directory` is set and idle_scans > 0 or
/// memory_budget_bytes > 0.
struct BlockFlushSetting {
  /// Parent folder; the backend creates its own sub-folder `nbs-blocks-<n>` there at the first flush and deletes it
  /// when destroyed. It holds a lock on the folder while alive; the first flush also removes the sibling folders
  /// whose owner died without deleting them.
  std::filesystem::path directory;
  std::uint32_t idle_scans = 0;           ///< flush blocks not written during the last idle_scans scans (0 = off)
  std::size_t memory_budget_bytes = 0;    ///< then flush LRU blocks until memory_bytes() ≤ this (0 = off)

  /// True if this setting flushes anything (a directory and a rule).
  [[nodiscard]] bool enabled() const { return !directory.empty() && (idle_scans > 0 || memory_budget_bytes > 0); }
  /// Throws InvalidArgument, prefixed with `who`, if a rule is set without a directory.
  void validate(std::string_view who) const {
    detail::require(!directory.empty() || (idle_scans == 0 && memory_budget_bytes == 0), who,
                    ": idle_scans = ", idle_scans, " and memory_budget_bytes = ", memory_budget_bytes,
                    " need a directory");
  }
};

/// What flushing has done so far.
struct BlockFlushStats {
  std::uint64_t blocks_written = 0;   ///< blocks flushed to disk
  std::uint64_t blocks_reloaded = 0;  ///< flushed blocks brought back by a write access
  std::uint64_t failed_writes = 0;    ///< flushes that failed (the block stayed in memory)
  /// `nbs-blocks-*` folders of dead owners (e.g. a killed process) removed from the directory at this backend's
  /// first flush (detail/block_folder_lock.hpp).
  std::uint64_t stale_folders_removed = 0;
  std::string last_error;             ///< message of the last failed flush ("" if none)
};

/// A voxel backend that can flush cold blocks to disk (the capability NbsPlanner needs for PlannerSetting::flush):
/// `set_flush_policy(BlockFlushSetting)` (throws InvalidArgument for a rule without a directory) and
/// `flush_stats()`. HashedBlockBackend models it.
template <class B>
concept FlushableBackend = requires(B& b, const B& cb, BlockFlushSetting s) {
  b.set_flush_policy(s);
  { cb.flush_stats() } -> std::convertible_to<const BlockFlushStats&>;
};

}  // namespace nbs
