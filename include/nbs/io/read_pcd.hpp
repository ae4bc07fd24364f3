// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict PCD point-cloud reader (PCL's Point Cloud Data format, DATA ascii, binary and binary_compressed):
/// fields x y z, with normal_x normal_y normal_z and rgb / rgba when present, and the VIEWPOINT as the cloud's
/// sensor pose. Other fields (curvature, intensity, padding `_`, ...) are checked and skipped. Binary data is read
/// as little-endian, which is what PCL writes on every machine it runs on.

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/lzf.hpp"
#include "nbs/io/detail/pcd_header.hpp"
#include "nbs/io/point_cloud.hpp"

namespace nbs {

/// Options of read_pcd.
struct PcdReadOptions {
  /// Organised clouds (HEIGHT > 1) mark pixels without a return by NaN coordinates. false (default): a non-finite
  /// coordinate or normal is an error naming the point. true: such points are dropped and counted in
  /// PointCloud::dropped (an error if no point is left).
  bool drop_non_finite = false;
};

namespace io_detail {

/// A little-endian value of field `f` at `p` as double (integers converted exactly up to 2^53).
[[nodiscard]] inline double pcd_binary_value(const PcdField& f, const char* p) {
  std::uint64_t u = 0;
  std::memcpy(&u, p, f.size);  // little-endian file on a little-endian host: the low bytes
  if constexpr (std::endian::native == std::endian::big) {
    std::uint64_t r = 0;
    for (std::size_t i = 0; i < f.size; ++i) r |= ((u >> (8 * (7 - i))) & 0xFFu) << (8 * i);
    u = r;
  }
  if (f.type == 'F') return f.size == 4 ? static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)))
                                        : std::bit_cast<double>(u);
  if (f.type == 'U') return static_cast<double>(u);
  const unsigned shift = static_cast<unsigned>(64 - 8 * f.size);  // sign-extend
  return static_cast<double>(static_cast<std::int64_t>(u << shift) >> shift);
}

/// An ascii token of field `f` as double; false if it is not a number of the field's type and range.
[[nodiscard]] inline bool pcd_ascii_value(const PcdField& f, std::string_view w, double& out) {
  const char* b = w.data();
  const char* e = w.data() + w.size();
  if (f.type == 'F') {
    const auto r = std::from_chars(b, e, out);
    return r.ec == std::errc() && r.ptr == e;
  }
  const unsigned bits = static_cast<unsigned>(8 * f.size);
  if (f.type == 'U') {
    std::uint64_t v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e || (bits < 64 && v >> bits != 0)) return false;
    out = static_cast<double>(v);
    return true;
  }
  std::int64_t v = 0;
  const auto r = std::from_chars(b, e, v);
  if (r.ec != std::errc() || r.ptr != e) return false;
  if (bits < 64 && (v < -(std::int64_t{1} << (bits - 1)) || v >= (std::int64_t{1} << (bits - 1)))) return false;
  out = static_cast<double>(v);
  return true;
}

/// A packed rgb/rgba ascii token: the 32-bit value as an unsigned integer (what PCL writes), or a float whose bits
/// are the packed value (older writers). False if neither.
[[nodiscard]] inline bool pcd_ascii_rgb(std::string_view w, std::uint32_t& out) {
  std::uint64_t v = 0;
  auto r = std::from_chars(w.data(), w.data() + w.size(), v);
  if (r.ec == std::errc() && r.ptr == w.data() + w.size() && v <= 0xFFFFFFFFu) {
    out = static_cast<std::uint32_t>(v);
    return true;
  }
  float f = 0.0f;
  r = std::from_chars(w.data(), w.data() + w.size(), f);
  if (r.ec != std::errc() || r.ptr != w.data() + w.size()) return false;
  out = std::bit_cast<std::uint32_t>(f);
  return true;
}

}  // namespace io_detail

/// Reads the points of a PCD file (`bytes` the whole file, `path` naming it in the messages). Normals are read when
/// the file has all of normal_x normal_y normal_z, colours when it has `rgb` or `rgba` (4 bytes, 0x00RRGGBB packed,
/// as PCL stores them); PointCloud::viewpoint is the VIEWPOINT when the header has one. Throws FileError naming the
/// file and the line or point and the value for: a malformed header (see parse_pcd_header), a missing or repeated
/// x/y/z, only some of the normal fields, a COUNT ≠ 1 for x y z, normals or colour, a colour field not of 4 bytes,
/// truncated or surplus data, a token that is not a number of its field's type, a malformed compressed block, a
/// non-finite coordinate or normal (unless dropped, see PcdReadOptions), no points. Nothing is returned on failure.
[[nodiscard]] inline PointCloud read_pcd_bytes(const std::string& path, const std::string& bytes,
                                               const PcdReadOptions& options = {}) {
  using namespace io_detail;
  const PcdHeader h = parse_pcd_header(path, bytes);
  const auto field = [&](std::string_view name, bool required) {
    const int i = h.find(name);
    if (i < 0 && required) throw FileError(detail::concat(path, ": no field '", name, "'"));
    for (std::size_t j = static_cast<std::size_t>(i < 0 ? 0 : i + 1); i >= 0 && j < h.fields.size(); ++j)
      if (h.fields[j].name == name) throw FileError(detail::concat(path, ": field '", name, "' appears twice"));
    if (i >= 0 && h.fields[static_cast<std::size_t>(i)].count != 1)
      throw FileError(detail::concat(path, ": field '", name, "' has COUNT ",
                                     h.fields[static_cast<std::size_t>(i)].count, ", not 1"));
    return i;
  };
  const int xyz[3] = {field("x", true), field("y", true), field("z", true)};
  const int nrm[3] = {field("normal_x", false), field("normal_y", false), field("normal_z", false)};
  const int n_normals = (nrm[0] >= 0) + (nrm[1] >= 0) + (nrm[2] >= 0);
  if (n_normals != 0 && n_normals != 3)
    throw FileError(detail::concat(path, ": only some of the fields normal_x normal_y normal_z"));
  int rgb = field("rgb", false);
  const int rgba = field("rgba", false);
  if (rgb >= 0 && rgba >= 0) throw FileError(detail::concat(path, ": both 'rgb' and 'rgba' fields"));
  if (rgb < 0) rgb = rgba;
  if (rgb >= 0 && h.fields[static_cast<std::size_t>(rgb)].size != 4)
    throw FileError(detail::concat(path, ": colour field '", h.fields[static_cast<std::size_t>(rgb)].name, "' has SIZE ",
                                   h.fields[static_cast<std::size_t>(rgb)].size, ", not 4"));
  if (h.points == 0) throw FileError(detail::concat(path, ": the point cloud has no points"));

  const std::string_view body = std::string_view(bytes).substr(h.body_offset);
  std::string unpacked;  // binary_compressed: the decompressed, field-major data
  if (h.data == PcdData::binary_compressed) {
    if (body.size() < 8) throw FileError(detail::concat(path, ": compressed data ends before its two sizes"));
    std::uint32_t sizes[2];
    std::memcpy(sizes, body.data(), 8);
    if constexpr (std::endian::native == std::endian::big)
      for (auto& s : sizes) s = (s >> 24) | ((s >> 8) & 0xFF00u) | ((s << 8) & 0xFF0000u) | (s << 24);
    const std::uint64_t expected = h.points * h.point_size;  // ≤ 2^32 checked below before it can overflow
    if (h.points > std::numeric_limits<std::uint32_t>::max() / h.point_size || sizes[1] != expected)
      throw FileError(detail::concat(path, ": compressed data declares ", sizes[1], " bytes uncompressed, but ",
                                     h.points, " points of ", h.point_size, " bytes need ", expected));
    if (sizes[0] != body.size() - 8)
      throw FileError(detail::concat(path, ": compressed data declares ", sizes[0], " bytes but ", body.size() - 8,
                                     " follow"));
    // LZF expands at most 264 / 2 bytes per byte of input: a larger claim is a malformed file, not an allocation.
    if (sizes[1] > 132ull * sizes[0] + 32)
      throw FileError(detail::concat(path, ": compressed data of ", sizes[0], " bytes cannot decompress to ", sizes[1]));
    if (const auto err = lzf_decompress(body.substr(8), sizes[1], unpacked))
      throw FileError(detail::concat(path, ": compressed data: ", *err));
  } else if (h.data == PcdData::binary) {
    if (h.points > body.size() / h.point_size)
      throw FileError(detail::concat(path, ": binary data has ", body.size(), " bytes, fewer than ", h.points,
                                     " points of ", h.point_size, " bytes need (truncated?)"));
    if (h.points * h.point_size != body.size())
      throw FileError(detail::concat(path, ": ", body.size() - h.points * h.point_size, " unexpected byte(s) after the ",
                                     h.points, " points of binary data"));
  } else if (h.points > (body.size() + 1) / (2 * h.values)) {  // a line holds ≥ values tokens and separators
    throw FileError(detail::concat(path, ": ", h.points, " points of ", h.values, " values cannot fit in the ",
                                   body.size(), " bytes that follow (truncated?)"));
  }

  PointCloud cloud;
  if (h.has_viewpoint) cloud.viewpoint = h.viewpoint;
  const std::size_t n = static_cast<std::size_t>(h.points);
  cloud.points.reserve(n);
  if (n_normals == 3) cloud.normals.reserve(n);
  if (rgb >= 0) cloud.colors.reserve(n);

  std::vector<double> value(h.fields.size(), 0.0);  // the count-1 fields' values of the current point
  std::uint32_t packed = 0;
  std::size_t pos = 0, line = h.body_line - 1;
  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < n; ++i) {
    std::string where;  // filled only on failure
    const auto fail = [&](const auto&... msg) {
      if (h.data == PcdData::ascii) where = detail::concat("line ", line, ", ");
      throw FileError(detail::concat(path, ": ", where, "point ", i, ": ", msg...));
    };
    if (h.data == PcdData::ascii) {
      words.clear();
      while (words.empty()) {
        if (pos >= body.size()) fail("file ends early (truncated?)");
        ++line;
        std::size_t nl = body.find('\n', pos);
        if (nl == std::string_view::npos) nl = body.size();
        std::string_view text = body.substr(pos, nl - pos);
        if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
        words = split_words(text);
        pos = nl + 1;
      }
      if (words.size() != h.values) fail(words.size(), " values on the line, the fields need ", h.values);
      std::size_t k = 0;
      for (std::size_t f = 0; f < h.fields.size(); ++f) {
        const PcdField& fd = h.fields[f];
        for (std::size_t c = 0; c < fd.count; ++c, ++k) {
          if (static_cast<int>(f) == rgb) {
            if (!pcd_ascii_rgb(words[k], packed)) fail(fd.name, ": '", words[k], "' is not a packed colour");
          } else if (!pcd_ascii_value(fd, words[k], value[f])) {
            fail(fd.name, ": '", words[k], "' is not a number of type ", fd.type, fd.size);
          }
        }
      }
    } else {
      for (int f : {xyz[0], xyz[1], xyz[2], nrm[0], nrm[1], nrm[2], rgb}) {
        if (f < 0) continue;
        const PcdField& fd = h.fields[static_cast<std::size_t>(f)];
        const char* p = h.data == PcdData::binary ? body.data() + i * h.point_size + fd.offset
                                                  : unpacked.data() + n * fd.offset + i * fd.size;
        if (f == rgb) {
          std::memcpy(&packed, p, 4);
          if constexpr (std::endian::native == std::endian::big)
            packed = (packed >> 24) | ((packed >> 8) & 0xFF00u) | ((packed << 8) & 0xFF0000u) | (packed << 24);
        } else {
          value[static_cast<std::size_t>(f)] = pcd_binary_value(fd, p);
        }
      }
    }
    const auto at = [&](int f) { return value[static_cast<std::size_t>(f)]; };
    const Vec3 p(at(xyz[0]), at(xyz[1]), at(xyz[2]));
    const Vec3 nv = n_normals == 3 ? Vec3(at(nrm[0]), at(nrm[1]), at(nrm[2])) : Vec3::Zero();
    if (!p.allFinite() || !nv.allFinite()) {
      if (!options.drop_non_finite)
        fail(!p.allFinite() ? "non-finite coordinate (" : "non-finite normal (",
             (!p.allFinite() ? p : nv).transpose(), ")");
      ++cloud.dropped;
      continue;
    }
    cloud.points.push_back(p);
    if (n_normals == 3) cloud.normals.push_back(nv);
    if (rgb >= 0)
      cloud.colors.push_back({static_cast<std::uint8_t>(packed >> 16), static_cast<std::uint8_t>(packed >> 8),
                              static_cast<std::uint8_t>(packed)});
  }
  if (h.data == PcdData::ascii && body.substr(std::min(pos, body.size())).find_first_not_of(" \t\r\n") !=
                                      std::string_view::npos)
    throw FileError(detail::concat(path, ": unexpected data after the last of the ", n, " points"));
  if (cloud.points.empty())
    throw FileError(detail::concat(path, ": all ", n, " points have non-finite coordinates or normals"));
  return cloud;
}

/// read_pcd_bytes of the file at `path` (FileError if it cannot be read).
[[nodiscard]] inline PointCloud read_pcd(const std::string& path, const PcdReadOptions& options = {}) {
  return read_pcd_bytes(path, io_detail::read_file_bytes(path), options);
}

}  // namespace nbs
