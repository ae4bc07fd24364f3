// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Pose files: one rigid transform per line as the 12 numbers of its upper 3×4 block, row-major
/// (r00 r01 r02 t0 r10 r11 r12 t1 r20 r21 r22 t2), the layout of the KITTI odometry pose files. Blank lines and lines
/// starting with `#` are skipped. Written with 17 significant digits, so a double pose reads back bit for bit.

#include <charconv>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/words.hpp"

namespace nbs {

/// Parses the poses in `text` (the contents of the file `path`, named in the messages). Translations are multiplied
/// by `translation_scale` (1e-3 for a file in millimetres). Throws FileError naming the file, the line and the value
/// for a line without exactly 12 numbers, a token that is not a finite number, and a pose that is not rigid
/// (pose_problem: |RᵀR − I|∞ or |det R − 1| above kOrthonormalTolerance).
[[nodiscard]] inline std::vector<Pose> parse_poses(const std::string& path, std::string_view text,
                                                   double translation_scale = 1.0) {
  std::vector<Pose> poses;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::vector<std::string_view> w = io_detail::split_words(line);
    if (w.empty() || w[0].starts_with('#')) continue;
    if (w.size() != 12)
      throw FileError(detail::concat(path, ":", line_no, ": a pose needs 12 numbers (3×4 row-major), got ", w.size()));
    Pose T = Pose::Identity();
    for (int k = 0; k < 12; ++k) {
      const std::string_view s = w[static_cast<std::size_t>(k)];
      double v = 0.0;
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
        throw FileError(detail::concat(path, ":", line_no, ": number ", k + 1, " '", s, "' is not a finite number"));
      T.matrix()(k / 4, k % 4) = (k % 4 == 3) ? v * translation_scale : v;
    }
    if (std::string why = pose_problem(T); !why.empty())
      throw FileError(detail::concat(path, ":", line_no, ": pose ", poses.size(), " is not rigid: ", why));
    poses.push_back(T);
  }
  return poses;
}

/// parse_poses of the file at `path` (FileError if it cannot be read).
[[nodiscard]] inline std::vector<Pose> read_pose_file(const std::string& path, double translation_scale = 1.0) {
  return parse_poses(path, io_detail::read_file_bytes(path), translation_scale);
}

/// The text of a pose file: an optional `# comment` line, then one line per pose (17 significant digits).
[[nodiscard]] inline std::string format_poses(std::span<const Pose> poses, std::string_view comment = {}) {
  std::string out;
  if (!comment.empty()) (out += "# ") += std::string(comment) + "\n";
  char buf[32];
  for (const Pose& T : poses) {
    for (int k = 0; k < 12; ++k) {
      const int n = std::snprintf(buf, sizeof buf, "%.17g", T.matrix()(k / 4, k % 4));
      out.append(buf, static_cast<std::size_t>(n));
      out += k == 11 ? '\n' : ' ';
    }
  }
  return out;
}

/// Writes `poses` to `path` atomically (the file is complete or left as it was). Throws InvalidArgument, naming the
/// index, for a pose that is not rigid (nothing is written), FileError if the file cannot be written.
inline void write_pose_file(const std::string& path, std::span<const Pose> poses, std::string_view comment = {}) {
  for (std::size_t i = 0; i < poses.size(); ++i)
    if (std::string why = pose_problem(poses[i]); !why.empty())
      throw InvalidArgument(detail::concat(path, ": pose ", i, " ", why));
  io_detail::write_file_atomic(path, format_poses(poses, comment));
}

}  // namespace nbs
