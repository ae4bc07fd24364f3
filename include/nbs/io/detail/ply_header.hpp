// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// PLY header: formats, property types, elements; strict parser (every keyword, type and count checked).

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/words.hpp"

namespace nbs {

/// Body encoding of a PLY file.
enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// Scalar type of a PLY property (int8 … float64; the header spells them char uchar short ushort int uint float
/// double).
enum class PlyType : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

namespace io_detail {

/// The classic header name of `t` ("uchar", "double", ...), as the writers spell it.
[[nodiscard]] inline std::string_view ply_type_name(PlyType t) {
  constexpr std::string_view names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return names[static_cast<int>(t)];
}

[[nodiscard]] inline std::size_t ply_type_size(PlyType t) {
  constexpr std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return sizes[static_cast<int>(t)];
}
[[nodiscard]] inline bool ply_type_is_integer(PlyType t) { return t != PlyType::f32 && t != PlyType::f64; }

/// Parses a PLY type name (both the classic and the sized spellings). False if unknown.
[[nodiscard]] inline bool parse_ply_type(std::string_view s, PlyType& t) {
  struct Name { std::string_view a, b; PlyType t; };
  constexpr Name names[] = {{"char", "int8", PlyType::i8},     {"uchar", "uint8", PlyType::u8},
                            {"short", "int16", PlyType::i16},  {"ushort", "uint16", PlyType::u16},
                            {"int", "int32", PlyType::i32},    {"uint", "uint32", PlyType::u32},
                            {"float", "float32", PlyType::f32}, {"double", "float64", PlyType::f64}};
  for (const auto& n : names)
    if (s == n.a || s == n.b) {
      t = n.t;
      return true;
    }
  return false;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType type = PlyType::f32;        ///< scalar type, or item type of a list
  PlyType count_type = PlyType::u8;   ///< list length type (lists only)
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t header_line = 0;

  /// Index of the property called `name`, or -1.
  [[nodiscard]] int find(std::string_view prop) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == prop) return static_cast<int>(i);
    return -1;
  }
  /// Fewest bytes one record can take in binary (lists counted as empty).
  [[nodiscard]] std::size_t min_binary_size() const {
    std::size_t s = 0;
    for (const auto& p : properties) s += ply_type_size(p.is_list ? p.count_type : p.type);
    return s;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  ///< byte offset of the first body byte
  std::size_t body_line = 0;    ///< 1-based line number of the first body line (ascii)
};

/// Parses the header of a PLY file held in `bytes`. Throws FileError "<path>: line N: <problem>".
[[nodiscard]] inline PlyHeader parse_ply_header(const std::string& path, std::string_view bytes) {
  PlyHeader h;
  std::size_t pos = 0, line_no = 0;
  bool have_format = false;
  auto fail = [&](const auto&... msg) { throw FileError(detail::concat(path, ": line ", line_no, ": ", msg...)); };
  while (true) {
    ++line_no;
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string_view::npos) fail("header is not terminated by 'end_header' (file truncated?)");
    std::string_view line = bytes.substr(pos, nl - pos);
    pos = nl + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto w = split_words(line);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply") fail("not a PLY file: first line must be 'ply'");
      continue;
    }
    if (w.empty()) continue;
    const std::string_view key = w[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") break;
    if (key == "format") {
      if (have_format) fail("second 'format' line");
      if (w.size() != 3 || w[2] != "1.0") fail("expected 'format <encoding> 1.0'");
      if (w[1] == "ascii") h.format = PlyFormat::ascii;
      else if (w[1] == "binary_little_endian") h.format = PlyFormat::binary_little_endian;
      else if (w[1] == "binary_big_endian") h.format = PlyFormat::binary_big_endian;
      else fail("unknown format '", w[1], "'");
      have_format = true;
    } else if (key == "element") {
      if (w.size() != 3) fail("expected 'element <name> <count>'");
      PlyElement e;
      e.name = std::string(w[1]);
      e.header_line = line_no;
      const auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size())
        fail("element '", e.name, "' has an invalid count '", w[2], "'");
      for (const auto& other : h.elements)
        if (other.name == e.name) fail("element '", e.name, "' declared twice");
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) fail("'property' before any 'element'");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.is_list = true;
        if (!parse_ply_type(w[2], p.count_type)) fail("unknown list count type '", w[2], "'");
        if (!ply_type_is_integer(p.count_type)) fail("list count type must be an integer type, got '", w[2], "'");
        if (!parse_ply_type(w[3], p.type)) fail("unknown list item type '", w[3], "'");
        p.name = std::string(w[4]);
      } else if (w.size() == 3 && w[1] != "list") {
        if (!parse_ply_type(w[1], p.type)) fail("unknown property type '", w[1], "'");
        p.name = std::string(w[2]);
      } else {
        fail("expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      auto& e = h.elements.back();
      if (e.find(p.name) >= 0) fail("property '", p.name, "' declared twice in element '", e.name, "'");
      e.properties.push_back(std::move(p));
    } else {
      fail("unknown header keyword '", key, "'");
    }
  }
  if (!have_format) throw FileError(detail::concat(path, ": header has no 'format' line"));
  // A record without properties takes no bytes, so its count would not be bounded by the file size.
  for (const auto& e : h.elements)
    if (e.properties.empty() && e.count > 0)
      throw FileError(detail::concat(path, ": line ", e.header_line, ": element '", e.name, "' has ", e.count,
                                     " records but no properties"));
  h.body_offset = pos;
  h.body_line = line_no + 1;
  return h;
}

}  // namespace io_detail
}  // namespace nbs
