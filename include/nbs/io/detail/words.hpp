// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Splitting a text line into words (the ascii PLY and OBJ readers).

#include <string_view>
#include <vector>

namespace nbs::io_detail {

/// Splits `line` at spaces/tabs.
[[nodiscard]] inline std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> w;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > b) w.push_back(line.substr(b, i - b));
  }
  return w;
}

}  // namespace nbs::io_detail
