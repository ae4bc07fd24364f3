// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Compressed 8-bit RGB / RGBA PNG files through libpng's simplified API (png_image, libpng 1.6): libpng's default
/// row filters and zlib level; the file is written atomically (temporary file renamed into place).

#include <png.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/file_bytes.hpp"

namespace nbs::png {

/// Bytes per pixel: 3 = RGB, 4 = RGBA (straight, not premultiplied, alpha).
enum class PixelFormat : std::uint32_t { rgb = 3, rgba = 4 };

/// Largest width or height accepted: libpng's default limit (PNG_USER_WIDTH_MAX, PNG_USER_HEIGHT_MAX).
inline constexpr std::uint32_t kMaxSide = 1'000'000;

/// Encodes a row-major image, top row first, `pixels.size() == channels · width · height`, as a PNG in memory.
/// Throws InvalidArgument for a side outside [1, kMaxSide] or a size mismatch, Error if libpng fails.
[[nodiscard]] inline std::vector<std::uint8_t> encode_png(std::uint32_t width, std::uint32_t height,
                                                          std::span<const std::uint8_t> pixels,
                                                          PixelFormat format = PixelFormat::rgb) {
  const auto channels = static_cast<std::uint32_t>(format);
  detail::require(channels == 3 || channels == 4, "encode_png: pixel format must be rgb (3) or rgba (4), got ",
                  channels);
  detail::require(width >= 1 && height >= 1 && width <= kMaxSide && height <= kMaxSide, "encode_png: size ", width,
                  " x ", height, " must be in [1, ", kMaxSide, "] per side");
  detail::require(pixels.size() == std::uint64_t{channels} * width * height, "encode_png: ", pixels.size(),
                  " bytes for ", width, " x ", height, " pixels of ", channels, " bytes");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  std::vector<std::uint8_t> out(PNG_IMAGE_PNG_SIZE_MAX(image));
  png_alloc_size_t size = out.size();
  const int ok = png_image_write_to_memory(&image, out.data(), &size, 0, pixels.data(),
                                           static_cast<png_int_32>(channels * width), nullptr);
  const std::string message = image.message;
  png_image_free(&image);
  if (!ok || size > out.size()) throw Error(detail::concat("encode_png: libpng: ", message));
  out.resize(size);
  return out;
}

/// Writes encode_png(...) to `<path>.tmp`, then renames it to `path`: `path` keeps its old contents or holds the
/// whole PNG. Throws InvalidArgument as encode_png (nothing is written), FileError naming the file if it cannot be
/// written (the temporary file is removed).
inline void write_png(const std::string& path, std::uint32_t width, std::uint32_t height,
                      std::span<const std::uint8_t> pixels, PixelFormat format = PixelFormat::rgb) {
  const std::vector<std::uint8_t> bytes = encode_png(width, height, pixels, format);
  io_detail::write_file_atomic(path, {reinterpret_cast<const char*>(bytes.data()), bytes.size()});
}

}  // namespace nbs::png
