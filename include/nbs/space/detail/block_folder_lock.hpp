// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Ownership of a HashedBlockBackend flush folder `nbs-blocks-<n>`, so that the folders a killed process leaves
/// behind are removed at the next start: the owner holds an exclusive flock(2) on `<folder>/owner.lock` for as long
/// as the backend lives (the kernel releases it when the process dies, however it dies). The lock file is created
/// as `owner.lock.tmp`, locked, then renamed, so an `owner.lock` that exists was locked when it appeared.
/// `remove_stale_block_folders` removes the sibling folders whose `owner.lock` it can lock itself (their owner is
/// dead); folders without `owner.lock` (being created, or not ours) are left alone, as is every folder whose owner
/// is alive, in this process or another. POSIX only: elsewhere the lock is a no-op and nothing is removed.
///
/// Thread-safety: distinct objects may be used concurrently; flock is per open file, so two backends of one
/// process exclude each other like two processes do.

#include <cstddef>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>
#define NBS_HAS_FLOCK 1
#else
#define NBS_HAS_FLOCK 0
#endif

namespace nbs::detail {

inline constexpr const char* kBlockFolderPrefix = "nbs-blocks-";
inline constexpr const char* kBlockFolderLockName = "owner.lock";

/// An exclusive lock on a block folder's owner.lock; released (file descriptor closed) on destruction. Move-only.
class BlockFolderLock {
 public:
  BlockFolderLock() = default;
  BlockFolderLock(BlockFolderLock&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  BlockFolderLock& operator=(BlockFolderLock&& o) noexcept {
    if (this != &o) {
      release();
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  BlockFolderLock(const BlockFolderLock&) = delete;
  BlockFolderLock& operator=(const BlockFolderLock&) = delete;
  ~BlockFolderLock() { release(); }

  /// Creates and locks `<folder>/owner.lock` (through owner.lock.tmp). Returns false (nothing held) on failure.
  [[nodiscard]] bool acquire_new(const std::filesystem::path& folder) {
    release();
#if NBS_HAS_FLOCK
    const std::filesystem::path tmp = folder / (std::string(kBlockFolderLockName) + ".tmp");
    const int fd = ::open(tmp.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (fd < 0) return false;
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);
      return false;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, folder / kBlockFolderLockName, ec);
    if (ec) {
      ::close(fd);
      return false;
    }
    fd_ = fd;
#else
    (void)folder;
#endif
    return true;
  }

  /// Locks an existing `<folder>/owner.lock` without waiting. True if this object now holds it (its owner is gone).
  [[nodiscard]] bool try_take_over(const std::filesystem::path& folder) {
    release();
#if NBS_HAS_FLOCK
    const std::filesystem::path file = folder / kBlockFolderLockName;
    const int fd = ::open(file.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) return false;
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);
      return false;
    }
    fd_ = fd;
    return true;
#else
    (void)folder;
    return false;
#endif
  }

  [[nodiscard]] bool held() const { return fd_ >= 0; }

  void release() {
#if NBS_HAS_FLOCK
    if (fd_ >= 0) ::close(fd_);
#endif
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

/// Removes the folders `nbs-blocks-*` in `parent` that have an owner.lock no live owner holds, and returns how many
/// it removed. Never throws; a folder it cannot remove is left (and not counted).
[[nodiscard]] inline std::size_t remove_stale_block_folders(const std::filesystem::path& parent) {
  std::vector<std::filesystem::path> folders;  // collected first: the directory is not changed while iterated
  std::error_code ec;
  std::filesystem::directory_iterator it(parent, ec), end;
  if (ec) return 0;
  for (; it != end; it.increment(ec)) {
    if (ec) break;
    if (it->path().filename().string().rfind(kBlockFolderPrefix, 0) == 0 && it->is_directory(ec))
      folders.push_back(it->path());
  }
  std::size_t removed = 0;
  for (const std::filesystem::path& p : folders) {
    BlockFolderLock lock;
    if (!lock.try_take_over(p)) continue;  // alive, being created, or not a locked folder
    std::error_code rm;
    std::filesystem::remove_all(p, rm);  // the lock's file is removed too; the descriptor stays valid until release
    removed += rm ? 0 : 1;
  }
  return removed;
}

}  // namespace nbs::detail
