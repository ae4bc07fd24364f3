// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A fresh directory under the system's temporary directory, removed with everything in it when the object dies
// (the flush tests' scratch space).
#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace nbs_test {

struct TempDir {
  std::filesystem::path path;
  /// `prefix` + two random numbers, created at once.
  explicit TempDir(const std::string& prefix) {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / (prefix + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

}  // namespace nbs_test
