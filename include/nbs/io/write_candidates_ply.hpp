// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The scan candidates of one planning step as PLY line segments (Fig. 4.16), for viewers such as MeshLab or
/// CloudCompare: a vertex at each path end (double x y z, uchar red green blue), one `edge` per path (int vertex1
/// vertex2, its colour, double utility). Colour by utility_color of the min/max-normalised utilities: red = lowest
/// of the step, green = highest.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/io/color.hpp"
#include "nbs/io/ply_writer.hpp"

namespace nbs {

/// Writes `paths` with their `utility` (one value per path) to `path` as ascii PLY: vertices 2i (start) and 2i + 1
/// (end) of path i with 9 significant digits, edge i with the utility as nlohmann-json prints it (the shortest form
/// that parses back exactly; `null` if not finite, as in report.json). The file appears complete or not at all
/// (PlyWriter). Throws InvalidArgument if the sizes differ, FileError if the file cannot be written.
inline void write_candidates_ply(const std::string& path, std::span<const LinearScanPath> paths,
                                 std::span<const double> utility) {
  detail::require(utility.size() == paths.size(), "write_candidates_ply: ", utility.size(), " utilities for ",
                  paths.size(), " paths");
  const std::vector<double> u01 = normalize_utilities(utility);
  PlyWriter w(path, PlyFormat::ascii, 9);
  w.comment("nbs scan candidates of one planning step, coloured by utility (red low, green high)");
  w.element("vertex", 2 * paths.size());
  for (const char* name : {"x", "y", "z"}) w.property(PlyType::f64, name);
  for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.element("edge", paths.size());
  for (const char* name : {"vertex1", "vertex2"}) w.property(PlyType::i32, name);
  for (const char* name : {"red", "green", "blue"}) w.property(PlyType::u8, name);
  w.property(PlyType::f64, "utility");
  w.end_header();
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const Rgb c = utility_color(u01[i]);
    for (const Vec3& p : {paths[i].start().position(), paths[i].end_position()}) {
      for (int k = 0; k < 3; ++k) w.value(p[k]);
      for (std::uint8_t v : c) w.value(v);
      w.end_record();
    }
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const Rgb c = utility_color(u01[i]);
    w.value(static_cast<std::int32_t>(2 * i));
    w.value(static_cast<std::int32_t>(2 * i + 1));
    for (std::uint8_t v : c) w.value(v);
    w.ascii_token(nlohmann::json(utility[i]).dump());  // shortest exact form; null if not finite
    w.end_record();
  }
  w.finish();
}

}  // namespace nbs
