// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// A minimal PNG encoder (8-bit RGB, no interlace) without a zlib dependency: the image data is stored in
/// uncompressed deflate blocks (RFC 1951 BTYPE = 00) inside a zlib stream (RFC 1950, Adler-32), each chunk with its
/// CRC-32 (ISO 3309 polynomial 0xEDB88320, reflected).

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"

namespace nbs {

namespace io_detail {
[[nodiscard]] inline std::uint32_t png_crc32_update(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::uint8_t b : bytes) crc = table[(crc ^ b) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}
inline void png_put32(std::vector<std::uint8_t>& v, std::uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(static_cast<std::uint8_t>(x >> s));
}
inline void png_chunk(std::vector<std::uint8_t>& out, std::string_view type, std::span<const std::uint8_t> data) {
  png_put32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type.begin(), type.end());
  out.insert(out.end(), data.begin(), data.end());
  png_put32(out, png_crc32_update(std::span(out).subspan(start)));
}
}  // namespace io_detail

/// CRC-32 of `bytes` as used by PNG chunks (and zlib's crc32).
[[nodiscard]] inline std::uint32_t png_crc32(std::span<const std::uint8_t> bytes) {
  return io_detail::png_crc32_update(bytes);
}

/// Encodes a row-major 8-bit RGB image (`rgb.size() == 3·width·height`, top row first) as a PNG file in memory.
/// Throws InvalidArgument for a zero or too large size or a size mismatch.
[[nodiscard]] inline std::vector<std::uint8_t> encode_png(std::uint32_t width, std::uint32_t height,
                                                          std::span<const std::uint8_t> rgb) {
  detail::require(width > 0 && height > 0 && width <= 65535 && height <= 65535, "encode_png: size ", width, " x ",
                  height, " must be in [1, 65535] per side");
  detail::require(rgb.size() == 3ull * width * height, "encode_png: ", rgb.size(), " bytes for ", width, " x ", height,
                  " RGB pixels");
  std::vector<std::uint8_t> raw;  // filter byte 0 (None) + row
  raw.reserve((3ull * width + 1) * height);
  for (std::uint32_t y = 0; y < height; ++y) {
    raw.push_back(0);
    const auto row = rgb.subspan(3ull * width * y, 3ull * width);
    raw.insert(raw.end(), row.begin(), row.end());
  }
  std::vector<std::uint8_t> z{0x78, 0x01};  // zlib: deflate, 32 K window, no dictionary, check bits
  std::uint32_t a = 1, b = 0;               // Adler-32
  for (std::uint8_t v : raw) a = (a + v) % 65521u, b = (b + a) % 65521u;
  for (std::size_t pos = 0; pos < raw.size() || pos == 0;) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + n == raw.size();
    z.push_back(last ? 1 : 0);  // BFINAL, BTYPE = 00 (stored)
    z.push_back(static_cast<std::uint8_t>(n)), z.push_back(static_cast<std::uint8_t>(n >> 8));
    z.push_back(static_cast<std::uint8_t>(~n)), z.push_back(static_cast<std::uint8_t>(~n >> 8));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos), raw.begin() + static_cast<std::ptrdiff_t>(pos + n));
    pos += n;
    if (last) break;
  }
  io_detail::png_put32(z, (b << 16) | a);
  std::vector<std::uint8_t> out{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  io_detail::png_put32(ihdr, width);
  io_detail::png_put32(ihdr, height);
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // bit depth 8, colour type 2 (RGB), deflate, filter 0, no interlace
  io_detail::png_chunk(out, "IHDR", ihdr);
  io_detail::png_chunk(out, "IDAT", z);
  io_detail::png_chunk(out, "IEND", {});
  return out;
}

/// Writes encode_png(...) to `path`. Throws FileError if the file cannot be written.
inline void write_png(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                      std::span<const std::uint8_t> rgb) {
  const std::vector<std::uint8_t> bytes = encode_png(width, height, rgb);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw FileError(detail::concat(path.string(), ": cannot open file for writing"));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw FileError(detail::concat(path.string(), ": write failed"));
}

}  // namespace nbs
