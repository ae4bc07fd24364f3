// SPDX-License-Identifier: BSD-3-Clause
// The PNG encoder (nbs/io/png.hpp), the utility colour map (color.hpp) and the report JSON helpers
// (json_format.hpp). Oracles: an independent bitwise CRC-32 and Adler-32, a stored-block deflate decoder written
// here, hand-computed colours and strings.

#include "nbs_catch.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "nbs/io/color.hpp"
#include "nbs/io/json_format.hpp"
#include "nbs/io/png.hpp"

namespace {


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

}  // namespace

TEST_CASE("PNG: signature, chunk CRCs, IHDR and the pixels round-trip", "[io][png]") {
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(nbs::png_crc32(check) == 0xCBF43926u);  // the CRC-32 check value
  CHECK(crc_bitwise(check, 9) == 0xCBF43926u);

  for (const auto& [w, h] : {std::pair<std::uint32_t, std::uint32_t>{5, 3}, {1, 1}, {200, 150}}) {  // 200×150 > 64 KiB
    INFO(w << " x " << h);
    std::vector<std::uint8_t> rgb(3ull * w * h);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>((i * 37u + i / 7u) & 0xFF);
    const std::vector<std::uint8_t> png = nbs::encode_png(w, h, rgb);
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

TEST_CASE("PNG: bad arguments throw InvalidArgument", "[io][png][bad-input]") {
  const std::vector<std::uint8_t> rgb(12);
  CHECK_THROWS_AS(nbs::encode_png(0, 4, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::encode_png(4, 0, {}), nbs::InvalidArgument);
  CHECK_THROWS_AS(nbs::encode_png(2, 3, rgb), nbs::InvalidArgument);  // 12 bytes for 18
  CHECK_NOTHROW(nbs::encode_png(2, 2, rgb));
}

TEST_CASE("utility colours: red (low) to green (high), normalisation by min and max", "[io][color]") {
  CHECK(nbs::utility_color(0.0) == nbs::Rgb{255, 0, 0});
  CHECK(nbs::utility_color(1.0) == nbs::Rgb{0, 255, 0});
  CHECK(nbs::utility_color(0.5) == nbs::Rgb{255, 255, 0});
  CHECK(nbs::utility_color(-3.0) == nbs::Rgb{255, 0, 0});
  CHECK(nbs::utility_color(7.0) == nbs::Rgb{0, 255, 0});
  CHECK(nbs::utility_color(std::numeric_limits<double>::quiet_NaN()) == nbs::Rgb{255, 0, 0});
  for (int i = 0; i < 100; ++i) {  // red never rises, green never falls, blue stays 0
    const nbs::Rgb a = nbs::utility_color(i / 100.0), b = nbs::utility_color((i + 1) / 100.0);
    CHECK(b[0] <= a[0]);
    CHECK(b[1] >= a[1]);
    CHECK(a[2] == 0);
  }
  const std::vector<double> u{2.0, 4.0, 3.0, std::numeric_limits<double>::infinity()};
  CHECK(nbs::normalize_utilities(u) == std::vector<double>{0.0, 1.0, 0.5, 0.0});
  CHECK(nbs::normalize_utilities(std::vector<double>{5.0, 5.0}) == std::vector<double>{1.0, 1.0});
  CHECK(nbs::normalize_utilities(std::vector<double>{}).empty());
}

TEST_CASE("report JSON: numbers round-trip, non-finite is null, strings escaped", "[io][json]") {
  for (double v : {0.1, -1.0 / 3.0, 1e-300, 6.02214076e23, 0.0, 123456789.0}) {
    const std::string s = nbs::json_number(v);
    CHECK(std::strtod(s.c_str(), nullptr) == v);
  }
  CHECK(nbs::json_number(std::numeric_limits<double>::quiet_NaN()) == "null");
  CHECK(nbs::json_number(-std::numeric_limits<double>::infinity()) == "null");
  CHECK(nbs::json_number(3.0) == "3");
  CHECK(nbs::json_string("a\"b\\c\nd\x01") == "\"a\\\"b\\\\c\\nd\\u0001\"");
  CHECK(nbs::json_string("C_H") == "\"C_H\"");
  CHECK(nbs::json_array(std::vector<double>{1.5, std::nan("")}) == "[1.5, null]");
  CHECK(nbs::json_array(std::vector<std::string>{"BS", "HR"}) == "[\"BS\", \"HR\"]");
  CHECK(nbs::json_array(std::vector<double>{}) == "[]");
}
