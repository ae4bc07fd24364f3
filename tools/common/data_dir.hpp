// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Where a tool finds nbs's bundled data (the demo mesh): an installed tool looks in `<prefix>/share/nbs`, found
/// from its own path (`/proc/self/exe`, then NBS_DATA_FROM_BIN, the install's bin → data path, e.g.
/// `../share/nbs`), so a moved prefix still works; a tool in a build tree uses the source tree's `data/`
/// (NBS_DATA_DIR). Linux (`/proc`); elsewhere only the source tree's copy is found.

#include <filesystem>
#include <string>
#include <system_error>

namespace nbs::tools {

/// The path of the bundled file `relative` (e.g. "meshes/stanford-bunny.obj"): the installed copy next to this
/// executable if there is one, else the source tree's. Returns the source tree's path (which may not exist) when
/// neither is found, so that the loader's error names a path.
[[nodiscard]] inline std::string bundled_data(const std::string& relative) {
  namespace fs = std::filesystem;
#ifdef NBS_DATA_FROM_BIN
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path() / NBS_DATA_FROM_BIN / relative;
    if (fs::is_regular_file(installed, ec)) return installed.lexically_normal().string();
  }
#endif
#ifdef NBS_DATA_DIR
  return (fs::path(NBS_DATA_DIR) / relative).string();
#else
  return relative;
#endif
}

}  // namespace nbs::tools
