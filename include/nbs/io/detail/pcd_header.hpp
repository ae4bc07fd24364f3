// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict parsing of a PCD header (PCL's Point Cloud Data format, v0.5–0.7): FIELDS SIZE TYPE COUNT WIDTH HEIGHT
/// VIEWPOINT POINTS DATA, comments (#) and blank lines allowed, DATA last.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"
#include "nbs/io/detail/words.hpp"

namespace nbs::io_detail {

enum class PcdData { ascii, binary, binary_compressed };

/// One field: name, type letter (I signed, U unsigned, F float), size in bytes, count of values.
struct PcdField {
  std::string name;
  char type = 'F';
  std::size_t size = 4;
  std::size_t count = 1;
  std::size_t offset = 0;  ///< byte offset in a binary point record
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0, height = 1, points = 0;
  std::size_t point_size = 0;  ///< bytes per point in a binary record
  std::size_t values = 0;      ///< values per point (Σ count)
  Pose viewpoint = Pose::Identity();
  bool has_viewpoint = false;
  PcdData data = PcdData::ascii;
  std::size_t body_offset = 0;  ///< first byte after the DATA line
  std::size_t body_line = 0;    ///< 1-based line number of the first ascii data line

  /// Index of the field called `name`, or −1.
  [[nodiscard]] int find(std::string_view name) const {
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (fields[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

/// Parses the header of `bytes` (a whole PCD file named `path` in messages). Throws FileError naming the line and
/// the value for an unknown or repeated keyword, a missing FIELDS/SIZE/TYPE/WIDTH/DATA, list lengths that differ
/// from FIELDS, a type letter or size PCD does not have (I/U: 1 2 4 8 bytes, F: 4 8), a zero COUNT, WIDTH × HEIGHT
/// ≠ POINTS, a non-finite VIEWPOINT or one whose quaternion is not of unit norm (±1e-3; it is then normalised).
[[nodiscard]] inline PcdHeader parse_pcd_header(const std::string& path, std::string_view bytes) {
  PcdHeader h;
  std::size_t pos = 0, line = 0;
  bool seen_size = false, seen_type = false, seen_count = false, seen_width = false, seen_height = false,
       seen_points = false, seen_version = false, seen_fields = false;
  std::vector<std::string_view> sizes, types, counts;
  std::size_t fields_line = 0;
  const auto fail = [&](const auto&... msg) -> void {
    throw FileError(detail::concat(path, ": line ", line, ": ", msg...));
  };
  const auto to_u64 = [&](std::string_view key, std::string_view w) {
    std::uint64_t v = 0;
    const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
    if (r.ec != std::errc() || r.ptr != w.data() + w.size()) fail(key, ": '", w, "' is not a non-negative integer");
    return v;
  };
  const auto once = [&](bool& seen, std::string_view key) {
    if (seen) fail("repeated ", key);
    seen = true;
  };
  for (;;) {
    if (pos >= bytes.size()) throw FileError(detail::concat(path, ": the header ends without a DATA line"));
    ++line;
    std::size_t nl = bytes.find('\n', pos);
    const bool last = nl == std::string_view::npos;
    if (last) nl = bytes.size();
    std::string_view text = bytes.substr(pos, nl - pos);
    pos = last ? bytes.size() : nl + 1;
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    const std::vector<std::string_view> w = split_words(text);
    if (w.empty() || w[0].front() == '#') continue;
    const std::string_view key = w[0];
    const std::size_t n = w.size() - 1;
    if (key == "VERSION") {
      once(seen_version, key);
    } else if (key == "FIELDS") {
      once(seen_fields, key);
      if (n == 0) fail("FIELDS lists no field");
      fields_line = line;
      for (std::size_t i = 1; i < w.size(); ++i) {
        PcdField f;
        f.name = std::string(w[i]);
        h.fields.push_back(f);
      }
    } else if (key == "SIZE") {
      once(seen_size, key);
      sizes.assign(w.begin() + 1, w.end());
    } else if (key == "TYPE") {
      once(seen_type, key);
      types.assign(w.begin() + 1, w.end());
    } else if (key == "COUNT") {
      once(seen_count, key);
      counts.assign(w.begin() + 1, w.end());
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      once(key == "WIDTH" ? seen_width : key == "HEIGHT" ? seen_height : seen_points, key);
      if (n != 1) fail(key, " needs one value, got ", n);
      (key == "WIDTH" ? h.width : key == "HEIGHT" ? h.height : h.points) = to_u64(key, w[1]);
    } else if (key == "VIEWPOINT") {
      once(h.has_viewpoint, key);
      if (n != 7) fail("VIEWPOINT needs 7 values (tx ty tz qw qx qy qz), got ", n);
      double v[7];
      for (int i = 0; i < 7; ++i) {
        const std::string_view s = w[static_cast<std::size_t>(i) + 1];
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v[i]);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v[i]))
          fail("VIEWPOINT value ", i + 1, " '", s, "' is not a finite number");
      }
      Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
      if (std::abs(q.norm() - 1.0) > 1e-3) fail("VIEWPOINT quaternion (", v[3], " ", v[4], " ", v[5], " ", v[6],
                                                ") has norm ", q.norm(), ", not 1");
      q.normalize();
      h.viewpoint = Pose::Identity();
      h.viewpoint.linear() = q.toRotationMatrix();
      h.viewpoint.translation() = Vec3(v[0], v[1], v[2]);
    } else if (key == "DATA") {
      if (n != 1) fail("DATA needs one value (ascii, binary or binary_compressed), got ", n);
      if (w[1] == "ascii") h.data = PcdData::ascii;
      else if (w[1] == "binary") h.data = PcdData::binary;
      else if (w[1] == "binary_compressed") h.data = PcdData::binary_compressed;
      else fail("DATA '", w[1], "' is not ascii, binary or binary_compressed");
      h.body_offset = pos;
      h.body_line = line + 1;
      break;
    } else {
      fail("unknown header keyword '", key, "'");
    }
  }
  if (!seen_fields) fail("no FIELDS line before DATA");
  if (!seen_size) fail("no SIZE line before DATA");
  if (!seen_type) fail("no TYPE line before DATA");
  if (!seen_width) fail("no WIDTH line before DATA");
  const std::size_t nf = h.fields.size();
  const auto same_length = [&](const std::vector<std::string_view>& v, std::string_view key) {
    if (v.size() != nf)
      throw FileError(detail::concat(path, ": ", key, " has ", v.size(), " values for ", nf, " FIELDS (line ",
                                     fields_line, ")"));
  };
  same_length(sizes, "SIZE");
  same_length(types, "TYPE");
  if (seen_count) same_length(counts, "COUNT");
  for (std::size_t i = 0; i < nf; ++i) {
    PcdField& f = h.fields[i];
    if (types[i].size() != 1 || (types[i][0] != 'I' && types[i][0] != 'U' && types[i][0] != 'F'))
      throw FileError(detail::concat(path, ": field '", f.name, "': TYPE '", types[i], "' is not I, U or F"));
    f.type = types[i][0];
    f.size = static_cast<std::size_t>(to_u64("SIZE", sizes[i]));
    const bool ok = f.type == 'F' ? (f.size == 4 || f.size == 8) : (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8);
    if (!ok) throw FileError(detail::concat(path, ": field '", f.name, "': SIZE ", f.size, " is not valid for TYPE ", f.type));
    f.count = seen_count ? static_cast<std::size_t>(to_u64("COUNT", counts[i])) : 1;
    if (f.count == 0 || f.count > (1u << 20))
      throw FileError(detail::concat(path, ": field '", f.name, "': COUNT ", f.count, " is not in [1, 2^20]"));
    f.offset = h.point_size;
    h.point_size += f.size * f.count;
    h.values += f.count;
  }
  if (h.height == 0 || (h.width != 0 && h.height > std::numeric_limits<std::uint64_t>::max() / h.width))
    throw FileError(detail::concat(path, ": WIDTH ", h.width, " x HEIGHT ", h.height, " is not a valid point count"));
  if (!seen_points) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    throw FileError(detail::concat(path, ": POINTS ", h.points, " is not WIDTH x HEIGHT = ", h.width, " x ", h.height));
  return h;
}

}  // namespace nbs::io_detail
