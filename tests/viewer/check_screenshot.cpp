// SPDX-License-Identifier: BSD-3-Clause
// Checks two screenshots of the session viewer (tests/viewer/viewer_test.sh): in the object's screen region
// (a box given as fractions of the image) the first one must show the mesh — at least MIN_FILL of the pixels differ
// from the background (the most frequent colour of the region's border) by more than 80 in some channel (the lit
// mesh does, the pedestal grid's lines do not) — and the two must differ (moving the slider changes the picture):
// at least MIN_DIFF of the pixels differ by more than 24 in some channel.
// Usage: check_screenshot A.png B.png X0 Y0 X1 Y1 MIN_FILL MIN_DIFF   (X, Y: fractions of width and height)
// Exit 0 when both hold, 1 when not, 2 on bad input. libpng's simplified API (as nbs::png).
#include <png.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace {

struct Image {
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgb;
  [[nodiscard]] const std::uint8_t* at(int x, int y) const {
    return &rgb[3 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
  }
};

bool read_png(const char* path, Image& img) {
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&p, path)) {
    std::fprintf(stderr, "check_screenshot: %s: %s\n", path, p.message);
    return false;
  }
  p.format = PNG_FORMAT_RGB;
  img.w = int(p.width);
  img.h = int(p.height);
  img.rgb.resize(PNG_IMAGE_SIZE(p));
  if (!png_image_finish_read(&p, nullptr, img.rgb.data(), 0, nullptr)) {
    std::fprintf(stderr, "check_screenshot: %s: %s\n", path, p.message);
    return false;
  }
  return true;
}

bool differ(const std::uint8_t* a, const std::uint8_t* b, int tol) {
  return std::abs(a[0] - b[0]) > tol || std::abs(a[1] - b[1]) > tol || std::abs(a[2] - b[2]) > tol;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 9) {
    std::fprintf(stderr, "usage: check_screenshot A.png B.png X0 Y0 X1 Y1 MIN_FILL MIN_DIFF\n");
    return 2;
  }
  Image a, b;
  if (!read_png(argv[1], a) || !read_png(argv[2], b)) return 2;
  if (a.w != b.w || a.h != b.h || a.w == 0) {
    std::fprintf(stderr, "check_screenshot: the screenshots differ in size or are empty\n");
    return 2;
  }
  const int x0 = int(std::atof(argv[3]) * a.w), y0 = int(std::atof(argv[4]) * a.h);
  const int x1 = int(std::atof(argv[5]) * a.w), y1 = int(std::atof(argv[6]) * a.h);
  const double min_fill = std::atof(argv[7]), min_diff = std::atof(argv[8]);
  if (!(0 <= x0 && x0 < x1 && x1 <= a.w && 0 <= y0 && y0 < y1 && y1 <= a.h)) {
    std::fprintf(stderr, "check_screenshot: bad region\n");
    return 2;
  }
  // background: the most frequent colour on the border of the region in A
  std::map<std::uint32_t, int> hist;
  const auto key = [](const std::uint8_t* p) { return std::uint32_t(p[0]) << 16 | std::uint32_t(p[1]) << 8 | p[2]; };
  for (int x = x0; x < x1; ++x) ++hist[key(a.at(x, y0))], ++hist[key(a.at(x, y1 - 1))];
  for (int y = y0; y < y1; ++y) ++hist[key(a.at(x0, y))], ++hist[key(a.at(x1 - 1, y))];
  const auto most = [](const auto& l, const auto& r) { return l.second < r.second; };
  const std::uint32_t bg = std::max_element(hist.begin(), hist.end(), most)->first;
  const std::uint8_t bgc[3] = {std::uint8_t(bg >> 16), std::uint8_t(bg >> 8), std::uint8_t(bg)};
  std::size_t filled = 0, changed = 0, n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++n) {
      filled += differ(a.at(x, y), bgc, 80) ? 1 : 0;
      changed += differ(a.at(x, y), b.at(x, y), 24) ? 1 : 0;
    }
  const double fill = double(filled) / double(n), diff = double(changed) / double(n);
  std::printf("region %d..%d x %d..%d of %d x %d, background #%06x: filled %.1f %% (need %.1f %%), "
              "changed %.1f %% (need %.1f %%)\n",
              x0, x1, y0, y1, a.w, a.h, unsigned(bg), 100 * fill, 100 * min_fill, 100 * diff, 100 * min_diff);
  const bool ok = fill >= min_fill && diff >= min_diff;
  std::printf("%s\n", ok ? "OK" : "FAIL");
  return ok ? 0 : 1;
}
