// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Reading a whole file into memory with FileError on failure.

#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace nbs::io_detail
