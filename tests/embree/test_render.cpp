// The headless renderer (nbs/embree/render.hpp), the PNG encoder (png.hpp), the utility colour map and the report
// JSON helpers. Oracles: analytic silhouettes of a sphere, an independent bitwise CRC-32 and Adler-32, a stored-block
// deflate decoder written here, hand-computed colours and strings.

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "analytic_meshes.hpp"
#include "nbs/embree/png.hpp"
#include "nbs/embree/render.hpp"
#include "nbs/embree/report_json.hpp"

namespace {

using nbs::Vec3;
namespace ne = nbs::embree;

// Independent bitwise CRC-32 (reflected, polynomial 0xEDB88320), no table.
std::uint32_t crc_bitwise(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

std::uint32_t be32(const std::vector<std::uint8_t>& v, std::size_t at) {
  return (std::uint32_t(v[at]) << 24) | (std::uint32_t(v[at + 1]) << 16) | (std::uint32_t(v[at + 2]) << 8) | v[at + 3];
}

struct Chunk {
  std::string type;
  std::vector<std::uint8_t> data;
};

// Splits a PNG into chunks, checking the signature and every CRC with crc_bitwise.
std::vector<Chunk> parse_png(const std::vector<std::uint8_t>& png) {
  const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  REQUIRE(png.size() >= 8);
  for (int i = 0; i < 8; ++i) REQUIRE(png[i] == sig[i]);
  std::vector<Chunk> out;
  std::size_t at = 8;
  while (at < png.size()) {
    REQUIRE(at + 12 <= png.size());
    const std::uint32_t len = be32(png, at);
    REQUIRE(at + 12 + len <= png.size());
    Chunk c{std::string(png.begin() + long(at) + 4, png.begin() + long(at) + 8),
            std::vector<std::uint8_t>(png.begin() + long(at) + 8, png.begin() + long(at) + 8 + len)};
    CHECK(be32(png, at + 8 + len) == crc_bitwise(png.data() + at + 4, 4 + len));
    out.push_back(std::move(c));
    at += 12 + len;
  }
  return out;
}

// Inflates a zlib stream made of stored blocks only; checks header and Adler-32 (computed here).
std::vector<std::uint8_t> inflate_stored(const std::vector<std::uint8_t>& z) {
  REQUIRE(z.size() >= 6);
  CHECK((z[0] & 0x0F) == 8);                      // deflate
  CHECK((unsigned(z[0]) * 256 + z[1]) % 31 == 0);  // FCHECK
  CHECK((z[1] & 0x20) == 0);                      // no preset dictionary
  std::vector<std::uint8_t> raw;
  std::size_t at = 2;
  for (bool final = false; !final;) {
    REQUIRE(at + 5 <= z.size());
    final = (z[at] & 1) != 0;
    REQUIRE(((z[at] >> 1) & 3) == 0);  // stored
    const unsigned len = z[at + 1] | (z[at + 2] << 8), nlen = z[at + 3] | (z[at + 4] << 8);
    REQUIRE((len ^ 0xFFFFu) == nlen);
    REQUIRE(at + 5 + len <= z.size());
    raw.insert(raw.end(), z.begin() + long(at) + 5, z.begin() + long(at) + 5 + len);
    at += 5 + len;
  }
  REQUIRE(at + 4 == z.size());
  std::uint64_t a = 1, b = 0;
  for (std::uint8_t v : raw) {
    a = (a + v) % 65521;
    b = (b + a) % 65521;
  }
  CHECK(be32(z, at) == ((b << 16) | a));
  return raw;
}

std::size_t count_color(const ne::Image& img, const ne::Rgb8& c) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < img.rgb.size(); k += 3)
    n += img.rgb[k] == c[0] && img.rgb[k + 1] == c[1] && img.rgb[k + 2] == c[2];
  return n;
}

}  // namespace

TEST_CASE("PNG: signature, chunk CRCs, IHDR and the pixels round-trip", "[embree][render][png]") {
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(ne::png_crc32(check) == 0xCBF43926u);  // the CRC-32 check value
  CHECK(crc_bitwise(check, 9) == 0xCBF43926u);

  for (const auto& [w, h] : {std::pair<std::uint32_t, std::uint32_t>{5, 3}, {1, 1}, {200, 150}}) {  // 200×150 > 64 KiB
    INFO(w << " x " << h);
    std::vector<std::uint8_t> rgb(3ull * w * h);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>((i * 37u + i / 7u) & 0xFF);
    const std::vector<std::uint8_t> png = ne::encode_png(w, h, rgb);
    const std::vector<Chunk> chunks = parse_png(png);
    REQUIRE(chunks.size() == 3);
    CHECK(chunks[0].type == "IHDR");
    CHECK(chunks[1].type == "IDAT");
    CHECK(chunks[2].type == "IEND");
    CHECK(chunks[2].data.empty());
    REQUIRE(chunks[0].data.size() == 13);
    CHECK(be32(chunks[0].data, 0) == w);
    CHECK(be32(chunks[0].data, 4) == h);
    CHECK(chunks[0].data[8] == 8);   // bit depth
    CHECK(chunks[0].data[9] == 2);   // RGB
    CHECK(chunks[0].data[10] == 0);  // deflate
    CHECK(chunks[0].data[11] == 0);  // filter method
    CHECK(chunks[0].data[12] == 0);  // no interlace
    const std::vector<std::uint8_t> raw = inflate_stored(chunks[1].data);
    REQUIRE(raw.size() == (3ull * w + 1) * h);
    bool same = true;
    for (std::uint32_t y = 0; y < h; ++y) {
      same = same && raw[(3ull * w + 1) * y] == 0;  // filter None
      for (std::size_t x = 0; x < 3ull * w; ++x) same = same && raw[(3ull * w + 1) * y + 1 + x] == rgb[3ull * w * y + x];
    }
    CHECK(same);
  }
}

TEST_CASE("PNG and renderer: bad arguments throw InvalidArgument", "[embree][render][bad-input]") {
  const std::vector<std::uint8_t> rgb(12);
  CHECK_THROWS_AS(ne::encode_png(0, 4, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(ne::encode_png(4, 0, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(ne::encode_png(2, 3, rgb), nbs::InvalidArgument);  // 12 bytes for 18
  CHECK_NOTHROW(ne::encode_png(2, 2, rgb));

  ne::RenderSetting s;
  s.width = 0;
  CHECK_THROWS_AS(ne::render(nullptr, ne::Camera{}, {}, s), nbs::InvalidArgument);
  s = {};
  s.threads = 0;
  CHECK_THROWS_AS(ne::render(nullptr, ne::Camera{}, {}, s), nbs::InvalidArgument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ne::Camera c;
  c.eye = Vec3(nan, 0, 1);
  CHECK_THROWS_AS(ne::render(nullptr, c), nbs::InvalidArgument);
  CHECK_THROWS_AS(ne::project(c, {}, Vec3::Zero()), nbs::InvalidArgument);
  c = {};
  c.target = c.eye;  // eye = target
  CHECK_THROWS_AS(ne::render(nullptr, c), nbs::InvalidArgument);
  c = {};
  c.eye = Vec3(0, 0, 1);  // looking straight down with up = +z
  CHECK_THROWS_AS(ne::render(nullptr, c), nbs::InvalidArgument);
  c = {};
  c.vertical_fov_rad = 0.0;
  CHECK_THROWS_AS(ne::render(nullptr, c), nbs::InvalidArgument);
  c = {};
  c.orthographic = true;
  c.ortho_height_m = -1.0;
  CHECK_THROWS_AS(ne::render(nullptr, c), nbs::InvalidArgument);
}

TEST_CASE("renderer: a sphere's silhouette is the analytic disc (orthographic and perspective)", "[embree][render]") {
  const double r = 0.1;
  const ne::Scene scene(nbs_test::sphere_mesh(Vec3::Zero(), r, 96));
  ne::RenderSetting s;
  s.width = 400;
  s.height = 300;
  s.threads = 2;

  SECTION("orthographic") {
    ne::Camera c;
    c.orthographic = true;
    c.ortho_height_m = 0.3;
    c.eye = Vec3(0.7, -0.4, 0.3);
    const ne::Image img = ne::render(&scene, c, {}, s);
    const double px = c.ortho_height_m / s.height;  // metres per pixel
    const double expected = std::numbers::pi * r * r / (px * px);
    CHECK(std::abs(double(img.hit_count()) / expected - 1.0) < 0.02);
    // Headlight Lambert: the pixel at the centre sees the sphere head-on → shade ≈ 1 → the albedo.
    const std::size_t k = 3 * (std::size_t(s.height / 2) * s.width + s.width / 2);
    for (int ch = 0; ch < 3; ++ch) CHECK(std::abs(int(img.rgb[k + ch]) - int(s.surface[ch])) <= 2);
    // Depth at the centre: distance eye → sphere surface.
    CHECK(img.depth[std::size_t(s.height / 2) * s.width + s.width / 2] ==
          Approx(c.eye.norm() - r).margin(2e-3));
  }
  SECTION("perspective") {
    ne::Camera c;
    c.eye = Vec3(0.3, -0.4, 0.2);
    c.vertical_fov_rad = 0.6;
    const double alpha = std::asin(r / c.eye.norm());  // angular radius of the sphere
    const double rad_px = std::tan(alpha) / std::tan(0.5 * c.vertical_fov_rad) * 0.5 * s.height;
    const ne::Image img = ne::render(&scene, c, {}, s);
    CHECK(std::abs(double(img.hit_count()) / (std::numbers::pi * rad_px * rad_px) - 1.0) < 0.02);
    double cx = 0, cy = 0;
    for (std::uint32_t j = 0; j < s.height; ++j)
      for (std::uint32_t i = 0; i < s.width; ++i)
        if (std::isfinite(img.depth[std::size_t(j) * s.width + i])) cx += i + 0.5, cy += j + 0.5;
    CHECK(cx / double(img.hit_count()) == Approx(0.5 * s.width).margin(0.5));
    CHECK(cy / double(img.hit_count()) == Approx(0.5 * s.height).margin(0.5));
    // Thread count does not change the image.
    s.threads = 1;
    CHECK(ne::render(&scene, c, {}, s).rgb == img.rgb);
  }
}

TEST_CASE("renderer: projection and segments", "[embree][render]") {
  ne::Camera c;
  c.orthographic = true;
  c.ortho_height_m = 0.2;  // 1 mm per pixel at 200 rows
  c.eye = Vec3(0, -1, 0);
  ne::RenderSetting s;
  s.width = 300;
  s.height = 200;
  const auto centre = ne::project(c, s, Vec3::Zero());
  REQUIRE(centre);
  CHECK(centre->x() == Approx(150.0));
  CHECK(centre->y() == Approx(100.0));
  const auto right_up = ne::project(c, s, Vec3(0.05, 0.3, 0.02));  // +x is right, +z is up; depth ignored
  REQUIRE(right_up);
  CHECK(right_up->x() == Approx(200.0));
  CHECK(right_up->y() == Approx(80.0));
  ne::Camera p;  // perspective: points behind the eye do not project
  p.eye = Vec3(0, -1, 0);
  CHECK_FALSE(ne::project(p, s, Vec3(0, -2, 0)).has_value());

  const ne::Segment horizontal{Vec3(-0.1005, 0, 0.0305), Vec3(0.0995, 0, 0.0305), {0, 255, 0}, 1};  // 200 px, row 69
  const ne::Segment vertical{Vec3(0.0405, 0, -0.0495), Vec3(0.0405, 0, 0.0495), {255, 0, 0}, 3};    // 99 px, 3 wide
  const std::vector<ne::Segment> segs{horizontal, vertical};
  const ne::Image img = ne::render(nullptr, c, segs, s);
  CHECK(img.hit_count() == 0);
  // The vertical (drawn last, 3 px wide) covers 3 pixels of the horizontal line.
  CHECK(count_color(img, {0, 255, 0}) == 201 - 3);
  CHECK(count_color(img, {255, 0, 0}) == 3 * (100 + 2));  // 3×3 stamp: one extra row at each end
  const std::size_t row = 69;  // 100 − 30.5 → floor 69
  for (std::size_t i : {50u, 100u, 150u, 180u}) CHECK(img.rgb[3 * (row * s.width + i) + 1] == 255);
}

TEST_CASE("utility colours: red (low) to green (high), normalisation by min and max", "[embree][render][color]") {
  CHECK(ne::utility_color(0.0) == ne::Rgb8{255, 0, 0});
  CHECK(ne::utility_color(1.0) == ne::Rgb8{0, 255, 0});
  CHECK(ne::utility_color(0.5) == ne::Rgb8{255, 255, 0});
  CHECK(ne::utility_color(-3.0) == ne::Rgb8{255, 0, 0});
  CHECK(ne::utility_color(7.0) == ne::Rgb8{0, 255, 0});
  CHECK(ne::utility_color(std::numeric_limits<double>::quiet_NaN()) == ne::Rgb8{255, 0, 0});
  for (int i = 0; i < 100; ++i) {  // red never rises, green never falls, blue stays 0
    const ne::Rgb8 a = ne::utility_color(i / 100.0), b = ne::utility_color((i + 1) / 100.0);
    CHECK(b[0] <= a[0]);
    CHECK(b[1] >= a[1]);
    CHECK(a[2] == 0);
  }
  const std::vector<double> u{2.0, 4.0, 3.0, std::numeric_limits<double>::infinity()};
  CHECK(ne::normalize_utilities(u) == std::vector<double>{0.0, 1.0, 0.5, 0.0});
  CHECK(ne::normalize_utilities(std::vector<double>{5.0, 5.0}) == std::vector<double>{1.0, 1.0});
  CHECK(ne::normalize_utilities(std::vector<double>{}).empty());
}

TEST_CASE("report JSON: numbers round-trip, non-finite is null, strings escaped", "[embree][render][json]") {
  for (double v : {0.1, -1.0 / 3.0, 1e-300, 6.02214076e23, 0.0, 123456789.0}) {
    const std::string s = ne::json_number(v);
    CHECK(std::strtod(s.c_str(), nullptr) == v);
  }
  CHECK(ne::json_number(std::numeric_limits<double>::quiet_NaN()) == "null");
  CHECK(ne::json_number(-std::numeric_limits<double>::infinity()) == "null");
  CHECK(ne::json_number(3.0) == "3");
  CHECK(ne::json_string("a\"b\\c\nd\x01") == "\"a\\\"b\\\\c\\nd\\u0001\"");
  CHECK(ne::json_string("C_H") == "\"C_H\"");
  CHECK(ne::json_array(std::vector<double>{1.5, std::nan("")}) == "[1.5, null]");
  CHECK(ne::json_array(std::vector<std::string>{"BS", "HR"}) == "[\"BS\", \"HR\"]");
  CHECK(ne::json_array(std::vector<double>{}) == "[]");
}
