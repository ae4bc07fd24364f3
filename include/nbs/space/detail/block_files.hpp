// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The files of HashedBlockBackend's flushed blocks: one file `<block id, 16 hex digits>.blk` per block in a folder
/// `nbs-blocks-<n>` of the space's own. A file holds the magic "NBSB" and the format version (two uint32), the block
/// id (uint64), the observed mask, then `BlockStates::save`, all in native byte order: the files are the scratch
/// space of one backend (it deletes the folder when destroyed), not an exchange format. A block is written to
/// `<name>.tmp` and renamed into place, so a file that exists is complete.
///
/// Thread-safety: reading different files, or one file that no one writes, concurrently is safe.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "nbs/core/error.hpp"

namespace nbs::detail {

inline constexpr std::uint32_t kBlockFileMagic = 0x4253424Eu;  // "NBSB"
inline constexpr std::uint32_t kBlockFileVersion = 1;

/// The file of block `id` in `folder`.
[[nodiscard]] inline std::filesystem::path block_file_path(const std::filesystem::path& folder, std::uint64_t id) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.blk", static_cast<unsigned long long>(id));
  return folder / name;
}

/// Creates `parent` if needed and a new folder `nbs-blocks-<n>` in it, and returns the new folder. <n> comes from
/// the clock and a counter, one per `Owner` type. Throws FileError if no folder can be created.
template <class Owner>
[[nodiscard]] std::filesystem::path create_block_folder(const std::filesystem::path& parent) {
  static std::atomic<std::uint64_t> counter{0};
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  const auto seed = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  for (int attempt = 0; attempt < 64; ++attempt) {
    const std::filesystem::path p =
        parent / ("nbs-blocks-" + std::to_string((seed + counter.fetch_add(1)) % 1000000007ull));
    ec.clear();
    if (std::filesystem::create_directory(p, ec)) return p;
    if (ec) break;
  }
  throw FileError(detail::concat("HashedBlockBackend: cannot create a block folder in '", parent.string(), "'",
                                 ec ? ": " + ec.message() : std::string()));
}

/// Writes block `b` (id, observed mask, states) to `path` through `path` + ".tmp". On an error calls
/// fail(message), which must throw; the temporary file is removed first once it was opened.
template <class Block, class Fail>
void write_block_file(const std::filesystem::path& path, std::uint64_t id, const Block& b, Fail&& fail) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(detail::concat("HashedBlockBackend: cannot open '", tmp.string(), "' for writing"));
    const auto write = [&out](const void* p, std::size_t n) {
      out.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    };
    const std::uint32_t header[2] = {kBlockFileMagic, kBlockFileVersion};
    write(header, sizeof header);
    write(&id, sizeof id);
    write(b.observed.data(), sizeof(b.observed));
    b.states.save(write);
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      fail(detail::concat("HashedBlockBackend: writing '", tmp.string(), "' failed"));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    fail(detail::concat("HashedBlockBackend: cannot rename '", tmp.string(), "' to '", path.string(),
                        "': ", ec.message()));
  }
}

/// Reads the observed mask and the states of block `id` from `path` into `b`. False if the file cannot be opened,
/// is short, or is not block id's in this format; `b`'s mask and states may then be partly overwritten.
template <class Block>
[[nodiscard]] bool read_block_file(const std::filesystem::path& path, std::uint64_t id, Block& b) {
  std::ifstream in(path, std::ios::binary);
  const auto read = [&in](void* p, std::size_t n) {
    in.read(static_cast<char*>(p), static_cast<std::streamsize>(n));
    return static_cast<bool>(in);
  };
  std::uint32_t header[2] = {0, 0};
  std::uint64_t file_id = 0;
  const bool ok = in && read(header, sizeof header) && header[0] == kBlockFileMagic &&
                  header[1] == kBlockFileVersion && read(&file_id, sizeof file_id) && file_id == id &&
                  read(b.observed.data(), sizeof(b.observed)) && b.states.restore(read);
  return ok;
}

}  // namespace nbs::detail
