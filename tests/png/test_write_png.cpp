// SPDX-License-Identifier: BSD-3-Clause
// PNG files through libpng (nbs/png/write_png.hpp). Oracle: libpng's own decoder (simplified read API) gives back
// the exact pixels; sizes from the PNG header.

#include "nbs_catch.hpp"

#include <png.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/png/write_png.hpp"
#include "io/temp_dir.hpp"

namespace {

using nbs_test::temp_dir;

struct Decoded {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

// Decodes `path` with libpng into 8-bit pixels of `format` (PNG_FORMAT_RGB or PNG_FORMAT_RGBA).
Decoded decode(const std::string& path, std::uint32_t format) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&image, path.c_str()) != 0);
  image.format = format;
  Decoded d{image.width, image.height, std::vector<std::uint8_t>(PNG_IMAGE_SIZE(image))};
  const int ok = png_image_finish_read(&image, nullptr, d.pixels.data(), 0, nullptr);
  INFO(image.message);
  REQUIRE(ok != 0);
  return d;
}

// A smooth image: gradients in x and y (and alpha).
std::vector<std::uint8_t> smooth(std::uint32_t w, std::uint32_t h, std::uint32_t channels) {
  std::vector<std::uint8_t> px(std::size_t{channels} * w * h);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      std::uint8_t* p = &px[(std::size_t{y} * w + x) * channels];
      p[0] = static_cast<std::uint8_t>(255 * x / w);
      p[1] = static_cast<std::uint8_t>(255 * y / h);
      p[2] = static_cast<std::uint8_t>((x + y) / 4);
      if (channels == 4) p[3] = static_cast<std::uint8_t>(255 - 200 * y / h);
    }
  return px;
}

}  // namespace

TEST_CASE("write_png: libpng decodes the exact pixels; RGB and RGBA; a smooth image is compressed", "[png]") {
  using nbs::png::PixelFormat;
  for (const auto& [w, h, format] :
       {std::tuple{1u, 1u, PixelFormat::rgb}, std::tuple{5u, 3u, PixelFormat::rgba},
        std::tuple{480u, 360u, PixelFormat::rgb}, std::tuple{301u, 77u, PixelFormat::rgba}}) {
    const auto channels = static_cast<std::uint32_t>(format);
    INFO(w << " x " << h << " x " << channels);
    std::vector<std::uint8_t> px = smooth(w, h, channels);
    if (w * h < 100)  // small ones: every byte value pattern, not only gradients
      for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>(i * 37u + 11u);
    const std::string path = (temp_dir() / "image.png").string();
    nbs::png::write_png(path, w, h, px, format);
    CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
    const Decoded d = decode(path, channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB);
    CHECK(d.width == w);
    CHECK(d.height == h);
    CHECK(d.pixels == px);
    const std::vector<std::uint8_t> bytes = nbs::png::encode_png(w, h, px, format);
    CHECK(nbs::io_detail::read_file_bytes(path) == std::string(bytes.begin(), bytes.end()));  // the file is encode_png
    if (w * h >= 100) {
      const auto size = std::filesystem::file_size(path);
      INFO("file " << size << " bytes, pixels " << px.size() << " bytes");
      CHECK(size * 10 < px.size());  // deflate with row filters: a smooth image shrinks more than tenfold
    }
  }
}

TEST_CASE("write_png: bad sizes throw InvalidArgument and write nothing", "[png][bad-input]") {
  using nbs::png::PixelFormat;
  const std::string path = (temp_dir() / "bad.png").string();
  const std::vector<std::uint8_t> px(12);
  CHECK_THROWS_AS(nbs::png::write_png(path, 0, 4, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::png::write_png(path, 4, 0, {}), nbs::InvalidArgument);
  CHECK_THROWS_WITH(nbs::png::write_png(path, 2, 3, px), nbs_test::Contains("12 bytes for 2 x 3"));
  CHECK_THROWS_AS(nbs::png::write_png(path, 2, 2, px, PixelFormat::rgba), nbs::InvalidArgument);  // 12 for 16
  CHECK_THROWS_AS(nbs::png::write_png(path, nbs::png::kMaxSide + 1, 1, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::png::write_png(path, 1, 1, std::vector<std::uint8_t>(5), static_cast<PixelFormat>(5)),
                  nbs::InvalidArgument);
  CHECK_FALSE(std::filesystem::exists(path));
  CHECK_NOTHROW(nbs::png::write_png(path, 2, 2, px));
  CHECK_NOTHROW(nbs::png::write_png(path, 3, 1, px, PixelFormat::rgba));
}

TEST_CASE("write_png: a failed write throws FileError naming the file and leaves no file", "[png][bad-input]") {
  const std::vector<std::uint8_t> px = smooth(8, 8, 3);
  const std::string missing = (temp_dir() / "no-such-dir" / "x.png").string();
  CHECK_THROWS_WITH(nbs::png::write_png(missing, 8, 8, px), nbs_test::Contains(missing));
  CHECK_THROWS_AS(nbs::png::write_png(missing, 8, 8, px), nbs::FileError);
  CHECK_FALSE(std::filesystem::exists(missing));
  // A non-empty directory in the way: the temporary file is written, the rename fails and the temporary is removed.
  const std::filesystem::path dir = temp_dir() / "in-the-way.png";
  std::filesystem::create_directories(dir / "child");
  CHECK_THROWS_AS(nbs::png::write_png(dir.string(), 8, 8, px), nbs::FileError);
  CHECK(std::filesystem::is_directory(dir));
  CHECK_FALSE(std::filesystem::exists(dir.string() + ".tmp"));
  // A failed write keeps the old file.
  const std::string old = (temp_dir() / "old.png").string();
  nbs::png::write_png(old, 8, 8, px);
  const std::string before = nbs::io_detail::read_file_bytes(old);
  CHECK_THROWS_AS(nbs::png::write_png(old, 8, 9, px), nbs::InvalidArgument);
  CHECK(nbs::io_detail::read_file_bytes(old) == before);
}
