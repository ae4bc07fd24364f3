// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A whole file as a string (bytes as stored; "" if it cannot be opened) — what the tests compare outputs with.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace nbs_test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace nbs_test
