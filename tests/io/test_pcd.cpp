// SPDX-License-Identifier: BSD-3-Clause
// PCD point clouds: read_pcd against write_pcd (ascii and binary, with and without normals, colours, viewpoint),
// PCL-style files built byte by byte (float fields, packed rgb, padding and extra fields, signed/unsigned integer
// types), binary_compressed against an independent LZF compressor and a hand-made LZF stream, organised clouds
// with NaN pixels, and malformed files rejected naming file, line or point and the value.
#include "nbs_catch.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "nbs/io/read_pcd.hpp"
#include "nbs/io/write_pcd.hpp"
#include "random_cloud.hpp"
#include "temp_dir.hpp"

using nbs_test::Contains;
using nbs::Vec3;

namespace {

/// Greedy LZF compressor written from the format's definition (brute-force match search): the oracle for the
/// decompressor, independent of it.
std::string lzf_compress(std::string_view in) {
  std::string out, lit;
  const auto flush = [&] {
    while (!lit.empty()) {
      const std::size_t n = std::min<std::size_t>(32, lit.size());
      out += static_cast<char>(n - 1);
      out += lit.substr(0, n);
      lit.erase(0, n);
    }
  };
  std::size_t i = 0;
  while (i < in.size()) {
    std::size_t best = 0, best_off = 0;
    for (std::size_t off = 1; off <= std::min<std::size_t>(i, 8192); ++off) {
      std::size_t l = 0;
      while (i + l < in.size() && l < 264 && in[i + l] == in[i + l - off]) ++l;
      if (l > best) best = l, best_off = off;
    }
    if (best < 3) {
      lit += in[i++];
      continue;
    }
    flush();
    const std::size_t len = best - 2, o = best_off - 1;
    if (len < 7) {
      out += static_cast<char>((len << 5) | (o >> 8));
    } else {
      out += static_cast<char>((7u << 5) | (o >> 8));
      out += static_cast<char>(len - 7);
    }
    out += static_cast<char>(o & 255u);
    i += best;
  }
  flush();
  return out;
}

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

std::uint32_t pack(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return (std::uint32_t{r} << 16) | (std::uint32_t{g} << 8) | b;
}

const std::string kPclHead =  // PCL's PointXYZRGBNormal layout: x y z _ rgb normal_x normal_y normal_z _ curvature
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
    "FIELDS x y z _ rgb normal_x normal_y normal_z _ curvature\nSIZE 4 4 4 1 4 4 4 4 1 4\n"
    "TYPE F F F U F F F F U F\nCOUNT 1 1 1 4 1 1 1 1 4 1\n";

}  // namespace

TEST_CASE("read_pcd reads write_pcd's output back exactly", "[io][pcd]") {
  int k = 0;
  for (const nbs::PcdFormat format : {nbs::PcdFormat::ascii, nbs::PcdFormat::binary}) {
    for (const bool normals : {false, true}) {
      for (const bool colors : {false, true}) {
        INFO("format " << static_cast<int>(format) << " normals " << normals << " colours " << colors);
        nbs::PointCloud c = nbs_test::random_cloud(193, normals, colors, static_cast<unsigned>(100 + ++k));
        if (k % 2 == 0) {
          nbs::Pose vp = nbs::Pose::Identity();
          vp.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
          vp.translation() = Vec3(0.1, -0.2, 1.5);
          c.viewpoint = vp;
        }
        const std::string path = (nbs_test::temp_dir() / ("cloud" + std::to_string(k) + ".pcd")).string();
        nbs::write_pcd(path, c, format);
        const nbs::PointCloud r = nbs::read_pcd(path);
        CHECK(r.points == c.points);  // 8-byte floats; ascii with 17 digits: exact
        CHECK(r.normals == c.normals);
        CHECK(r.colors == c.colors);
        CHECK(r.dropped == 0);
        REQUIRE(r.viewpoint.has_value());  // write_pcd always writes one (identity when the cloud has none)
        CHECK(r.viewpoint->isApprox(c.viewpoint.value_or(nbs::Pose::Identity()), 1e-12));
        CHECK(!std::filesystem::exists(path + ".tmp"));
      }
    }
  }
}

TEST_CASE("read_pcd: PCL's binary layout with padding, packed rgb and extra fields", "[io][pcd]") {
  const float xyz[2][3] = {{0.5f, -1.25f, 2.0f}, {3.0f, 0.0f, -0.125f}};
  const float nrm[2][3] = {{0.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 0.0f}};
  const std::uint32_t rgb[2] = {pack(255, 128, 1), pack(0, 10, 200)};
  std::string body;
  for (int i = 0; i < 2; ++i) {
    for (float v : xyz[i]) put(body, v);
    put(body, std::uint32_t{0xDEADBEEF});              // padding `_` COUNT 4
    put(body, std::bit_cast<float>(rgb[i]));           // rgb stored as a float's bits
    for (float v : nrm[i]) put(body, v);
    put(body, std::uint32_t{0});                       // padding
    put(body, 0.25f * static_cast<float>(i));          // curvature
  }
  const std::string file = kPclHead + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS 2\nDATA binary\n" + body;
  const nbs::PointCloud c = nbs::read_pcd_bytes("pcl.pcd", file);
  REQUIRE(c.size() == 2);
  CHECK(c.points[0] == Vec3(0.5, -1.25, 2.0));
  CHECK(c.points[1] == Vec3(3.0, 0.0, -0.125));
  CHECK(c.normals[1] == Vec3(1, 0, 0));
  CHECK(c.colors[0] == nbs::Rgb{255, 128, 1});
  CHECK(c.colors[1] == nbs::Rgb{0, 10, 200});
  CHECK(c.viewpoint->translation() == Vec3(1, 2, 3));

  SECTION("the same points as ascii, rgb written as PCL writes it (unsigned) and as a float") {
    const std::string ascii = kPclHead + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n0.5 -1.25 2 0 0 0 0 " +
                              std::to_string(rgb[0]) + " 0 0 1 0 0 0 0 0\n\n3 0 -0.125 1 2 3 4 " +
                              "1.5 1 0 0 0 0 0 0 0.25\n";
    const nbs::PointCloud a = nbs::read_pcd_bytes("pcl.pcd", ascii);
    CHECK(a.points == c.points);
    CHECK(a.normals == c.normals);
    CHECK(a.colors[0] == c.colors[0]);
    CHECK(a.colors[1] == nbs::Rgb{192, 0, 0});  // the float 1.5 has the bits 0x3FC00000
    CHECK(!a.viewpoint.has_value());
  }
}

TEST_CASE("read_pcd: integer field types and their ranges", "[io][pcd]") {
  const std::string head = "FIELDS x y z\nSIZE 1 2 8\nTYPE I U I\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ";
  std::string bin;
  put(bin, std::int8_t{-128});
  put(bin, std::uint16_t{65535});
  put(bin, std::int64_t{-(std::int64_t{1} << 40)});
  CHECK(nbs::read_pcd_bytes("i.pcd", head + "binary\n" + bin).points[0] == Vec3(-128, 65535, -1099511627776.0));
  CHECK(nbs::read_pcd_bytes("i.pcd", head + "ascii\n-128 65535 -1099511627776\n").points[0] ==
        Vec3(-128, 65535, -1099511627776.0));
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("i.pcd", head + "ascii\n-129 0 0\n"),
                    Contains("line 8, point 0: x: '-129' is not a number of type I1"));
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("i.pcd", head + "ascii\n0 65536 0\n"), Contains("'65536'"));
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("i.pcd", head + "ascii\n0 -1 0\n"), Contains("'-1'"));
}

TEST_CASE("LZF: a hand-made stream, and round trips through an independent compressor", "[io][pcd][lzf]") {
  // "abc" as a literal run (control 2), then a back reference of length 4 + 2 = 6 at offset 2 + 1 = 3.
  const std::string stream = std::string("\x02" "abc") + static_cast<char>(4 << 5) + static_cast<char>(2);
  std::string out;
  CHECK(!nbs::io_detail::lzf_decompress(stream, 9, out).has_value());
  CHECK(out == "abcabcabc");
  CHECK(nbs::io_detail::lzf_decompress(stream, 10, out).value() == "decompresses to fewer bytes than declared");
  CHECK(nbs::io_detail::lzf_decompress(stream, 8, out).value() == "back reference past the declared uncompressed size");
  CHECK(nbs::io_detail::lzf_decompress(std::string("\x02" "ab"), 3, out).value() ==
        "literal run past the end of the compressed data");
  CHECK(nbs::io_detail::lzf_decompress(std::string("\x00" "a", 2) + static_cast<char>(1 << 5) + '\x05', 4, out)
            .value() == "back reference before the start of the data");

  std::mt19937 rng(7);
  for (const std::size_t size : {std::size_t{1}, std::size_t{31}, std::size_t{33}, std::size_t{5000}}) {
    std::string data(size, '\0');
    for (auto& ch : data) ch = static_cast<char>("aab\0c"[rng() % 5]);  // repetitive: many back references
    const std::string z = lzf_compress(data);
    REQUIRE(!nbs::io_detail::lzf_decompress(z, data.size(), out).has_value());
    CHECK(out == data);
  }
}

TEST_CASE("read_pcd: binary_compressed (field-major, LZF) equals the binary file", "[io][pcd][lzf]") {
  const nbs::PointCloud c = nbs_test::random_cloud(300, true, true, 42);
  const std::string path = (nbs_test::temp_dir() / "compressed_ref.pcd").string();
  nbs::write_pcd(path, c, nbs::PcdFormat::binary);
  const std::string bin = nbs::io_detail::read_file_bytes(path);
  const std::size_t body_at = bin.find("DATA binary\n") + 12;
  // Field-major: all x, all y, ... , all rgb (as PCL's writeBinaryCompressed arranges them).
  std::string fields;
  const std::size_t rec = 52, n = c.size();
  for (const auto& [offset, size] : {std::pair{0, 8}, {8, 8}, {16, 8}, {24, 8}, {32, 8}, {40, 8}, {48, 4}})
    for (std::size_t i = 0; i < n; ++i) fields.append(bin, body_at + i * rec + offset, size);
  // Make it compressible: repeat the field-major data's structure? Random doubles barely compress; keep honest.
  const std::string z = lzf_compress(fields);
  std::string file = bin.substr(0, body_at - 12) + "DATA binary_compressed\n";
  put(file, static_cast<std::uint32_t>(z.size()));
  put(file, static_cast<std::uint32_t>(fields.size()));
  file += z;
  const nbs::PointCloud r = nbs::read_pcd_bytes("z.pcd", file);
  CHECK(r.points == c.points);
  CHECK(r.normals == c.normals);
  CHECK(r.colors == c.colors);

  std::string bad = file;
  bad[body_at - 12 + 23 + 4] ^= 1;  // uncompressed size
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("z.pcd", bad), Contains("z.pcd: compressed data declares"));
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("z.pcd", file.substr(0, file.size() - 1)),
                    Contains("bytes but " + std::to_string(z.size() - 1) + " follow"));
}

TEST_CASE("read_pcd: an organised cloud with NaN pixels is an error unless asked to drop them", "[io][pcd]") {
  const std::string file = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n"
                           "0 0 1\nnan nan nan\n1 0 1\n1 1 1\n";
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("org.pcd", file),
                    Contains("org.pcd: line 9, point 1: non-finite coordinate (nan nan nan)"));
  nbs::PcdReadOptions drop;
  drop.drop_non_finite = true;
  const nbs::PointCloud c = nbs::read_pcd_bytes("org.pcd", file, drop);
  CHECK(c.size() == 3);
  CHECK(c.dropped == 1);
  CHECK(c.points[1] == Vec3(1, 0, 1));
  CHECK_THROWS_WITH(nbs::read_pcd_bytes("org.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\n"
                                                   "DATA ascii\ninf 0 0\n", drop),
                    Contains("all 1 points have non-finite coordinates or normals"));
}

TEST_CASE("read_pcd rejects malformed files naming file, line or point and the value", "[io][pcd][bad-input]") {
  const std::string h = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n";
  struct Bad { std::string text, message; };
  const std::vector<Bad> bad = {
      {"", "the header ends without a DATA line"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n", "the header ends without a DATA line"},
      {"FIELDS x y z\nFIELDS x y z\n", "line 2: repeated FIELDS"},
      {"FOO 1\n", "line 1: unknown header keyword 'FOO'"},
      {"FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n", "SIZE has 2 values for 3 FIELDS (line 1)"},
      {"FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nDATA ascii\n", "field 'z': SIZE 3 is not valid for TYPE F"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F D\nWIDTH 1\nDATA ascii\n", "field 'z': TYPE 'D' is not I, U or F"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 0 1\nWIDTH 1\nDATA ascii\n", "field 'y': COUNT 0 is not in"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n",
       "POINTS 3 is not WIDTH x HEIGHT = 2 x 2"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH -1\n", "line 4: WIDTH: '-1' is not a non-negative integer"},
      {"FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n0 0\n", "no field 'z'"},
      {"FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 1\nDATA ascii\n0 0 0 0\n", "field 'x' appears twice"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 2\nWIDTH 1\nDATA ascii\n0 0 0 0\n",
       "field 'z' has COUNT 2, not 1"},
      {"FIELDS x y z normal_x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 1\nDATA ascii\n0 0 0 0\n",
       "only some of the fields normal_x normal_y normal_z"},
      {"FIELDS x y z rgb\nSIZE 4 4 4 2\nTYPE F F F U\nWIDTH 1\nDATA ascii\n0 0 0 0\n",
       "colour field 'rgb' has SIZE 2, not 4"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nDATA ascii\n", "the point cloud has no points"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nVIEWPOINT 0 0 0 2 0 0 0\nDATA ascii\n0 0 0\n",
       "VIEWPOINT quaternion (2 0 0 0) has norm 2, not 1"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nVIEWPOINT 0 nan 0 1 0 0 0\nDATA ascii\n0 0 0\n",
       "VIEWPOINT value 2 'nan' is not a finite number"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA zip\n", "DATA 'zip' is not ascii, binary or"},
      {h + "0 0 0\n", "2 points of 3 values cannot fit in the 6 bytes that follow (truncated?)"},
      {h + "0 0 0\n\n\n\n\n\n\n", "line 14, point 1: file ends early (truncated?)"},
      {h + "0 0 0\n10 10\n", "line 9, point 1: 2 values on the line, the fields need 3"},
      {h + "0 0 0\n1 1 x\n", "line 9, point 1: z: 'x' is not a number of type F4"},
      {h + "0 0 0\n1 1 1\n2 2 2\n", "unexpected data after the last of the 2 points"},
      {h.substr(0, h.size() - 6) + "binary\n" + std::string(23, '\0'),
       "binary data has 23 bytes, fewer than 2 points of 12 bytes need (truncated?)"},
      {h.substr(0, h.size() - 6) + "binary\n" + std::string(25, '\0'), "1 unexpected byte(s) after the 2 points"},
      {h.substr(0, h.size() - 6) + "binary_compressed\n" + std::string(7, '\0'),
       "compressed data ends before its two sizes"},
  };
  for (const Bad& b : bad) {
    INFO(b.text);
    CHECK_THROWS_AS(nbs::read_pcd_bytes("bad.pcd", b.text), nbs::FileError);
    CHECK_THROWS_WITH(nbs::read_pcd_bytes("bad.pcd", b.text), Contains("bad.pcd: ") && Contains(b.message));
  }
  CHECK_THROWS_WITH(nbs::read_pcd((nbs_test::temp_dir() / "missing.pcd").string()), Contains("cannot open file"));
}

TEST_CASE("write_pcd: an invalid cloud is refused and the file left as it was", "[io][pcd][bad-input]") {
  const std::string path = (nbs_test::temp_dir() / "kept.pcd").string();
  nbs::PointCloud good = nbs_test::random_cloud(3, false, false, 1);
  nbs::write_pcd(path, good);
  nbs::PointCloud bad = good;
  bad.points[1].y() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(nbs::write_pcd(path, bad), Contains("point 1 is not finite"));
  bad = good;
  bad.normals.resize(2);
  CHECK_THROWS_WITH(nbs::write_pcd(path, bad), Contains("2 normals for 3 points"));
  CHECK(nbs::read_pcd(path).points == good.points);
  CHECK(!std::filesystem::exists(path + ".tmp"));
}
