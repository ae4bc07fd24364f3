// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Bounds-checked reading of PLY body values (ascii tokens or binary bytes of either endianness).

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/io/detail/ply_header.hpp"

namespace nbs::io_detail {

/// Reads the values of one record after another. Every read is checked; failures throw FileError naming the
/// file, the element and record (and, for ascii, the line).
class PlyBodyReader {
public:
  PlyBodyReader(const std::string& path, std::string_view bytes, const PlyHeader& h)
      : path_(path), bytes_(bytes), pos_(h.body_offset), line_(h.body_line - 1), format_(h.format) {}

  /// Starts record `index` of `element` (ascii: takes the next non-blank line).
  void begin_record(const PlyElement& element, std::uint64_t index) {
    element_ = &element;
    record_ = index;
    if (format_ != PlyFormat::ascii) return;
    words_.clear();
    next_word_ = 0;
    while (words_.empty()) {
      if (pos_ >= bytes_.size()) fail("file ends early (truncated?)");
      ++line_;
      std::size_t nl = bytes_.find('\n', pos_);
      if (nl == std::string_view::npos) nl = bytes_.size();
      words_ = split_words(trim_cr(bytes_.substr(pos_, nl - pos_)));
      pos_ = nl + 1;
    }
  }

  /// Ends the record (ascii: the line must hold no further values).
  void end_record() {
    if (format_ == PlyFormat::ascii && next_word_ != words_.size())
      fail(words_.size() - next_word_, " unexpected extra value(s) on the line");
  }

  /// After the last element: nothing but whitespace (ascii) or nothing at all (binary) may follow.
  void finish() {
    element_ = nullptr;
    if (pos_ >= bytes_.size()) return;
    const std::string_view rest = bytes_.substr(pos_);
    if (format_ == PlyFormat::ascii && rest.find_first_not_of(" \t\r\n") == std::string_view::npos) return;
    throw FileError(detail::concat(path_, ": ", rest.size(), " unexpected byte(s) after the last element"));
  }

  /// Reads an integer-typed value; a non-integer type, a non-integer token or an out-of-range value fails.
  [[nodiscard]] std::int64_t read_int(PlyType t, std::string_view what) {
    if (!ply_type_is_integer(t)) fail(what, " must have an integer type");
    if (format_ == PlyFormat::ascii) {
      const std::string_view w = word(what);
      std::int64_t v = 0;
      const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
      if (r.ec != std::errc() || r.ptr != w.data() + w.size()) fail(what, ": '", w, "' is not an integer");
      if (v < type_min(t) || v > type_max(t)) fail(what, ": ", v, " is out of range for its type");
      return v;
    }
    switch (t) {
      case PlyType::i8: return binary<std::int8_t>();
      case PlyType::u8: return binary<std::uint8_t>();
      case PlyType::i16: return binary<std::int16_t>();
      case PlyType::u16: return binary<std::uint16_t>();
      case PlyType::i32: return binary<std::int32_t>();
      default: return binary<std::uint32_t>();
    }
  }

  /// Reads any scalar as double.
  [[nodiscard]] double read_real(PlyType t, std::string_view what) {
    if (ply_type_is_integer(t)) return static_cast<double>(read_int(t, what));
    if (format_ == PlyFormat::ascii) {
      const std::string_view w = word(what);
      double v = 0.0;
      const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
      if (r.ec != std::errc() || r.ptr != w.data() + w.size()) fail(what, ": '", w, "' is not a number");
      return v;
    }
    if (t == PlyType::f32) return std::bit_cast<float>(binary<std::uint32_t>());
    return std::bit_cast<double>(binary<std::uint64_t>());
  }

  /// Skips `n` values of type `t`.
  void skip(PlyType t, std::uint64_t n, std::string_view what) {
    if (format_ == PlyFormat::ascii) {
      for (std::uint64_t i = 0; i < n; ++i) (void)read_real(t, what);
      return;
    }
    const std::uint64_t size = ply_type_size(t);
    if (n > (bytes_.size() - pos_) / size) fail(what, ": ", n, " values do not fit in the rest of the file");
    pos_ += static_cast<std::size_t>(n * size);
  }

  /// Bytes not read yet.
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - std::min(pos_, bytes_.size()); }

  /// Throws FileError "<path>: [line L, ]element 'e' record r: <message>".
  template <class... Args>
  [[noreturn]] void fail(const Args&... msg) const {
    std::string where = format_ == PlyFormat::ascii ? detail::concat("line ", line_, ", ") : std::string();
    if (element_ != nullptr) where += detail::concat("element '", element_->name, "' record ", record_, ": ");
    throw FileError(detail::concat(path_, ": ", where, msg...));
  }

private:
  [[nodiscard]] static std::string_view trim_cr(std::string_view s) {
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    return s;
  }

  std::string_view word(std::string_view what) {
    if (next_word_ >= words_.size()) fail("line ends before ", what);
    return words_[next_word_++];
  }

  template <class T>
  T binary() {
    if (bytes_.size() - pos_ < sizeof(T)) fail("file ends early (truncated?)");
    using U = std::make_unsigned_t<T>;
    U u = 0;
    std::memcpy(&u, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    const bool file_little = format_ == PlyFormat::binary_little_endian;
    if (file_little != (std::endian::native == std::endian::little)) u = byteswap(u);
    return static_cast<T>(u);
  }

  template <class U>
  [[nodiscard]] static U byteswap(U u) {
    U r = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) r = static_cast<U>((r << 8) | ((u >> (8 * i)) & 0xFFu));
    return r;
  }

  [[nodiscard]] static std::int64_t type_min(PlyType t) {
    switch (t) {
      case PlyType::i8: return std::numeric_limits<std::int8_t>::min();
      case PlyType::i16: return std::numeric_limits<std::int16_t>::min();
      case PlyType::i32: return std::numeric_limits<std::int32_t>::min();
      default: return 0;
    }
  }
  [[nodiscard]] static std::int64_t type_max(PlyType t) {
    switch (t) {
      case PlyType::i8: return std::numeric_limits<std::int8_t>::max();
      case PlyType::u8: return std::numeric_limits<std::uint8_t>::max();
      case PlyType::i16: return std::numeric_limits<std::int16_t>::max();
      case PlyType::u16: return std::numeric_limits<std::uint16_t>::max();
      case PlyType::i32: return std::numeric_limits<std::int32_t>::max();
      default: return std::numeric_limits<std::uint32_t>::max();
    }
  }

  const std::string& path_;
  std::string_view bytes_;
  std::size_t pos_;
  std::size_t line_;
  PlyFormat format_;
  const PlyElement* element_ = nullptr;
  std::uint64_t record_ = 0;
  std::vector<std::string_view> words_;
  std::size_t next_word_ = 0;
};

}  // namespace nbs::io_detail
