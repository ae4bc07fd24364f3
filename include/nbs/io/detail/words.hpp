// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Splitting a text into lines and a line into words (the ascii PLY, OBJ and STL readers).

#include <string_view>
#include <vector>

namespace nbs::io_detail {

/// The line of `text` starting at `pos` (without its '\n' and a trailing '\r'); advances `pos` past it.
/// Precondition: pos < text.size().
[[nodiscard]] inline std::string_view next_line(std::string_view text, std::size_t& pos) {
  std::size_t nl = text.find('\n', pos);
  if (nl == std::string_view::npos) nl = text.size();
  std::string_view line = text.substr(pos, nl - pos);
  pos = nl + 1;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

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
