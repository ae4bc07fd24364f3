#pragma once
/// \file
/// A minimal PNG encoder (8-bit RGB, no interlace) without a zlib dependency: the image data is stored in
/// uncompressed deflate blocks (RFC 1951 BTYPE = 00) inside a zlib stream (RFC 1950, Adler-32), each chunk with its
/// CRC-32 (ISO 3309 polynomial 0xEDB88320, reflected). Plus the colour map of the candidate pictures (Fig. 4.16).
/// Header-only, no Embree needed; lives in the Embree adapter next to the renderer that uses it.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"

namespace nbs::embree {

/// 8-bit RGB colour.
using Rgb8 = std::array<std::uint8_t, 3>;

/// Colour of a normalised utility u ∈ [0, 1]: red (u = 0, low) → yellow (0.5) → green (u = 1, high), as in
/// Fig. 4.16. Values outside [0, 1] are clamped; NaN maps to red.
[[nodiscard]] inline Rgb8 utility_color(double u) {
  const double t = std::isnan(u) ? 0.0 : std::clamp(u, 0.0, 1.0);
  const auto c = [](double v) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); };
  return {c(2.0 * (1.0 - t)), c(2.0 * t), 0};
}

/// Normalises `values` to [0, 1] by min/max (all equal → 1, i.e. green); non-finite values give 0.
[[nodiscard]] inline std::vector<double> normalize_utilities(std::span<const double> values) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  std::vector<double> out(values.size(), 0.0);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) out[i] = hi > lo ? (values[i] - lo) / (hi - lo) : 1.0;
  return out;
}

namespace png_detail {
[[nodiscard]] inline std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0) {
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
inline void put32(std::vector<std::uint8_t>& v, std::uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(static_cast<std::uint8_t>(x >> s));
}
inline void chunk(std::vector<std::uint8_t>& out, std::string_view type, std::span<const std::uint8_t> data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type.begin(), type.end());
  out.insert(out.end(), data.begin(), data.end());
  put32(out, crc32(std::span(out).subspan(start)));
}
}  // namespace png_detail

/// CRC-32 of `bytes` as used by PNG chunks (and zlib's crc32).
[[nodiscard]] inline std::uint32_t png_crc32(std::span<const std::uint8_t> bytes) { return png_detail::crc32(bytes); }

/// Encodes a row-major 8-bit RGB image (`rgb.size() == 3·width·height`, top row first) as a PNG file in memory.
/// Throws InvalidArgument for a zero or too large size or a size mismatch.
[[nodiscard]] inline std::vector<std::uint8_t> encode_png(std::uint32_t width, std::uint32_t height,
                                                          std::span<const std::uint8_t> rgb) {
  nbs::detail::require(width > 0 && height > 0 && width <= 65535 && height <= 65535, "encode_png: size ", width, " x ",
                  height, " must be in [1, 65535] per side");
  nbs::detail::require(rgb.size() == 3ull * width * height, "encode_png: ", rgb.size(), " bytes for ", width, " x ", height,
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
  png_detail::put32(z, (b << 16) | a);
  std::vector<std::uint8_t> out{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  png_detail::put32(ihdr, width);
  png_detail::put32(ihdr, height);
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // bit depth 8, colour type 2 (RGB), deflate, filter 0, no interlace
  png_detail::chunk(out, "IHDR", ihdr);
  png_detail::chunk(out, "IDAT", z);
  png_detail::chunk(out, "IEND", {});
  return out;
}

/// Writes encode_png(...) to `path`. Throws FileError if the file cannot be written.
inline void write_png(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                      std::span<const std::uint8_t> rgb) {
  const std::vector<std::uint8_t> bytes = encode_png(width, height, rgb);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw FileError(nbs::detail::concat(path.string(), ": cannot open file for writing"));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw FileError(nbs::detail::concat(path.string(), ": write failed"));
}

}  // namespace nbs::embree
