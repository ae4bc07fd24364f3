// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict check of the `v` and `f` lines of an OBJ text before tinyobjloader reads it: tinyobjloader turns
/// `v nan 0 0` and `v abc 0 0` into (0, 0, 0) and wraps face indices beyond the int range.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/words.hpp"

namespace nbs::io_detail {

/// Throws FileError "<path>: line L: <problem>" unless every `v` line starts with three finite numbers and every
/// `f` line has ≥ 3 vertex references whose vertex index is a non-zero integer referring to an existing vertex
/// (1-based, or negative = relative to the vertices read so far). Other lines are not looked at.
inline void check_obj_text(const std::string& path, std::string_view text) {
  std::size_t pos = 0, line_no = 0;
  std::uint64_t vertices = 0, max_index = 0, max_index_line = 0;
  auto fail = [&](const auto&... msg) { throw FileError(detail::concat(path, ": line ", line_no, ": ", msg...)); };
  while (pos < text.size()) {
    ++line_no;
    std::string_view line = next_line(text, pos);
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const auto w = split_words(line);
    if (w.empty()) continue;
    if (w[0] == "v") {
      if (w.size() < 4) fail("a vertex needs 3 coordinates, got ", w.size() - 1);
      for (std::size_t a = 1; a <= 3; ++a) {
        double x = 0.0;
        const auto r = std::from_chars(w[a].data(), w[a].data() + w[a].size(), x);
        if (r.ec != std::errc() || r.ptr != w[a].data() + w[a].size()) fail("'", w[a], "' is not a number");
        if (!std::isfinite(x)) fail("vertex coordinate '", w[a], "' is not finite");
      }
      ++vertices;
    } else if (w[0] == "f") {
      if (w.size() < 4) fail("a face needs at least 3 vertices, got ", w.size() - 1);
      for (std::size_t k = 1; k < w.size(); ++k) {
        const std::string_view ref = w[k].substr(0, w[k].find('/'));
        std::int64_t idx = 0;
        const auto r = std::from_chars(ref.data(), ref.data() + ref.size(), idx);
        if (r.ec != std::errc() || r.ptr != ref.data() + ref.size() || idx == 0)
          fail("'", w[k], "' is not a vertex reference (a non-zero integer index)");
        const std::uint64_t mag = idx < 0 ? 0 - static_cast<std::uint64_t>(idx) : static_cast<std::uint64_t>(idx);
        if (mag > 0x7fffffffu) fail("vertex index ", idx, " is out of range");
        if (idx < 0 && mag > vertices) fail("relative vertex index ", idx, " but only ", vertices, " vertices precede it");
        if (idx > 0 && mag > max_index) {
          max_index = mag;
          max_index_line = line_no;
        }
      }
    }
  }
  if (max_index > vertices) {
    line_no = max_index_line;
    fail("vertex index ", max_index, " but the file has ", vertices, " vertices");
  }
}

}  // namespace nbs::io_detail
