// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Reading a whole file into memory, and writing one atomically, with FileError on failure.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

#include "nbs/core/error.hpp"

namespace nbs::io_detail {

/// Contents of `path` (binary). Throws FileError naming the file if it cannot be opened or read.
[[nodiscard]] inline std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(detail::concat(path, ": cannot open file"));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw FileError(detail::concat(path, ": read error"));
  return std::move(ss).str();
}

/// Writes `bytes` to `<path>.tmp` and renames it to `path`: `path` is either left as it was or holds all of `bytes`.
/// Throws FileError naming the file if it cannot be written (the temporary file is then removed).
inline void write_file_atomic(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(detail::concat(path, ": cannot open file for writing (", tmp, ")"));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw FileError(detail::concat(path, ": write failed"));
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw FileError(detail::concat(path, ": cannot rename ", tmp, " into place: ", ec.message()));
  }
}

}  // namespace nbs::io_detail
