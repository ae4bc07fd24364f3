// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The one PLY writer behind every `write_*_ply`: declare the elements and their properties, then write the body
/// value by value, record by record, as ascii or binary (little or big endian). The file is written as
/// `<path>.tmp` and renamed into place by `finish()`, so `path` is never left half-written; a writer destroyed
/// without `finish()` (an exception on the way) removes its temporary file and leaves `path` as it was.
///
///   PlyWriter w(path, PlyFormat::ascii);
///   w.element("vertex", points.size());
///   w.property(PlyType::f64, "x"); ...
///   w.end_header();
///   for (const Vec3& p : points) { w.value(p.x()); ...; w.end_record(); }
///   w.finish();
///
/// The C++ type of each `value` gives its binary size (`std::uint8_t` for uchar, `double` for double, ...); the
/// caller passes the types it declared, in declaration order. Not thread-safe.

#include <bit>
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/ply_header.hpp"

namespace nbs {

/// A C++ type that is one PLY scalar: (u)int8/16/32, float, double.
template <class T>
concept PlyScalar = std::same_as<T, std::int8_t> || std::same_as<T, std::uint8_t> || std::same_as<T, std::int16_t> ||
                    std::same_as<T, std::uint16_t> || std::same_as<T, std::int32_t> ||
                    std::same_as<T, std::uint32_t> || std::same_as<T, float> || std::same_as<T, double>;

class PlyWriter {
public:
  /// Opens `<path>.tmp` and writes the `ply` and `format` lines. Ascii values of type float/double are written with
  /// `ascii_precision` significant digits (as printf %.Ng; 17 round-trips a double). Throws FileError if the
  /// temporary file cannot be opened.
  explicit PlyWriter(std::filesystem::path path, PlyFormat format = PlyFormat::binary_little_endian,
                     int ascii_precision = 17)
      : path_(std::move(path)), tmp_(path_), format_(format) {
    tmp_ += ".tmp";
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw FileError(detail::concat(path_.string(), ": cannot open file for writing (", tmp_.string(), ")"));
    out_.precision(ascii_precision);
    out_ << "ply\nformat "
         << (format == PlyFormat::ascii                  ? "ascii"
             : format == PlyFormat::binary_little_endian ? "binary_little_endian"
                                                         : "binary_big_endian")
         << " 1.0\n";
  }
  PlyWriter(const PlyWriter&) = delete;
  PlyWriter& operator=(const PlyWriter&) = delete;
  ~PlyWriter() {
    if (finished_) return;
    out_.close();
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
  }

  // --- header: comments, then each element followed by its properties, then end_header() ---
  /// `comment <text>` (one line; `text` must not contain a newline).
  void comment(std::string_view text) { out_ << "comment " << text << '\n'; }
  /// `element <name> <count>`: `count` records follow in the body.
  void element(std::string_view name, std::uint64_t count) {
    out_ << "element " << name << ' ' << count << '\n';
    declared_records_ += count;
  }
  /// `property <type> <name>` of the last element.
  void property(PlyType type, std::string_view name) {
    out_ << "property " << io_detail::ply_type_name(type) << ' ' << name << '\n';
  }
  /// `property list <count type> <item type> <name>`: per record the count, then that many items.
  void list_property(PlyType count_type, PlyType item_type, std::string_view name) {
    out_ << "property list " << io_detail::ply_type_name(count_type) << ' ' << io_detail::ply_type_name(item_type)
         << ' ' << name << '\n';
  }
  void end_header() { out_ << "end_header\n"; }

  // --- body ---
  /// One value of the current record.
  template <PlyScalar T>
  void value(T v) {
    if (format_ == PlyFormat::ascii) {
      separate();
      if constexpr (sizeof(T) == 1) out_ << static_cast<int>(v);  // a number, not a character
      else out_ << v;
      return;
    }
    using Bits = std::conditional_t<sizeof(T) == 1, std::uint8_t,
                                    std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                                       std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    const auto bits = std::bit_cast<Bits>(v);
    const bool little = format_ == PlyFormat::binary_little_endian;
    char b[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      const std::size_t shift = 8 * (little ? i : sizeof(T) - 1 - i);
      b[i] = static_cast<char>((bits >> shift) & 0xFFu);
    }
    out_.write(b, sizeof(T));
  }
  /// A value already formatted as ascii text (e.g. a number in a fixed notation). Ascii only: throws
  /// InvalidArgument for a binary writer.
  void ascii_token(std::string_view text) {
    detail::require(format_ == PlyFormat::ascii, "PlyWriter::ascii_token: ", path_.string(), " is binary");
    separate();
    out_ << text;
  }
  /// Ends the current record (a newline in ascii).
  void end_record() {
    if (format_ == PlyFormat::ascii) out_ << '\n';
    first_ = true;
    ++written_records_;
  }

  /// Closes the temporary file and renames it to `path`. Throws FileError if writing failed, if the number of
  /// records differs from the element counts declared (the temporary file is then removed, `path` untouched) or if
  /// the rename fails.
  void finish() {
    out_.close();
    std::error_code ec;
    if (!out_) {
      std::filesystem::remove(tmp_, ec);
      throw FileError(detail::concat(path_.string(), ": write failed"));
    }
    if (written_records_ != declared_records_) {
      std::filesystem::remove(tmp_, ec);
      throw FileError(detail::concat(path_.string(), ": ", written_records_, " records written for the ",
                                     declared_records_, " the header declares"));
    }
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) {
      std::error_code ignored;
      std::filesystem::remove(tmp_, ignored);
      throw FileError(detail::concat(path_.string(), ": cannot rename ", tmp_.string(), " into place: ", ec.message()));
    }
    finished_ = true;
  }

private:
  void separate() {
    if (!first_) out_ << ' ';
    first_ = false;
  }

  std::filesystem::path path_, tmp_;
  PlyFormat format_;
  std::ofstream out_;
  std::uint64_t declared_records_ = 0, written_records_ = 0;
  bool first_ = true;
  bool finished_ = false;
};

}  // namespace nbs
