// SPDX-License-Identifier: BSD-3-Clause
// PlyWriter (the one PLY writer) and write_candidates_ply. Oracles: the strict header parser of the reader, bytes
// computed here, the ascii body parsed back with strtod.

#include "nbs_catch.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/detail/ply_header.hpp"
#include "nbs/io/ply_writer.hpp"
#include "nbs/io/write_candidates_ply.hpp"
#include "temp_dir.hpp"

namespace {

std::string body_of(const std::string& bytes) { return bytes.substr(bytes.find("end_header\n") + 11); }

}  // namespace

TEST_CASE("PlyWriter: header as declared, binary values in both byte orders, ascii numbers", "[io][ply][writer]") {
  const std::string path = (nbs_test::temp_dir() / "writer.ply").string();
  for (auto format : {nbs::PlyFormat::binary_little_endian, nbs::PlyFormat::binary_big_endian, nbs::PlyFormat::ascii}) {
    nbs::PlyWriter w(path, format);
    w.comment("test");
    w.element("thing", 1);
    w.property(nbs::PlyType::i8, "a");
    w.property(nbs::PlyType::u16, "b");
    w.property(nbs::PlyType::f32, "c");
    w.list_property(nbs::PlyType::u8, nbs::PlyType::i32, "d");
    w.end_header();
    w.value(std::int8_t{-2});
    w.value(std::uint16_t{0x0102});
    w.value(1.5f);
    w.value(std::uint8_t{1});
    w.value(std::int32_t{-1});
    w.end_record();
    w.finish();
    CHECK_FALSE(std::filesystem::exists(path + ".tmp"));

    const std::string bytes = nbs::io_detail::read_file_bytes(path);
    const nbs::io_detail::PlyHeader h = nbs::io_detail::parse_ply_header(path, bytes);
    CHECK(h.format == format);
    REQUIRE(h.elements.size() == 1);
    CHECK(h.elements[0].name == "thing");
    REQUIRE(h.elements[0].properties.size() == 4);
    CHECK(h.elements[0].properties[1].type == nbs::PlyType::u16);
    CHECK(h.elements[0].properties[3].is_list);
    CHECK(h.elements[0].properties[3].type == nbs::PlyType::i32);
    const std::string body = body_of(bytes);
    if (format == nbs::PlyFormat::ascii) {
      CHECK(body == "-2 258 1.5 1 -1\n");
      CHECK_THROWS_AS(nbs::PlyWriter(path, nbs::PlyFormat::binary_little_endian).ascii_token("1"),
                      nbs::InvalidArgument);
    } else {
      const bool le = format == nbs::PlyFormat::binary_little_endian;
      // 1.5f = 0x3FC00000
      const std::string expected = le ? std::string("\xFE\x02\x01\x00\x00\xC0\x3F\x01\xFF\xFF\xFF\xFF", 12)
                                      : std::string("\xFE\x01\x02\x3F\xC0\x00\x00\x01\xFF\xFF\xFF\xFF", 12);
      CHECK(body == expected);
    }
  }
}

TEST_CASE("PlyWriter: a file is complete or not there", "[io][ply][writer][bad-input]") {
  const std::string path = (nbs_test::temp_dir() / "atomic.ply").string();
  nbs_test::write_temp("atomic.ply", "old contents");
  {
    nbs::PlyWriter w(path, nbs::PlyFormat::ascii);
    w.element("vertex", 2);
    w.property(nbs::PlyType::f64, "x");
    w.end_header();
    w.value(1.0);
    w.end_record();
    CHECK(std::filesystem::exists(path + ".tmp"));
    CHECK_THROWS_WITH(w.finish(), nbs_test::Contains("atomic.ply") && nbs_test::Contains("1 records"));
  }
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  CHECK(nbs::io_detail::read_file_bytes(path) == "old contents");
  {
    nbs::PlyWriter w(path, nbs::PlyFormat::ascii);  // abandoned (an exception on the way): temporary file removed
    w.element("vertex", 0);
  }
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  CHECK(nbs::io_detail::read_file_bytes(path) == "old contents");
  CHECK_THROWS_WITH(nbs::PlyWriter("/nonexistent-dir/x.ply"),
                    nbs_test::Contains("/nonexistent-dir/x.ply") && nbs_test::Contains("cannot open"));
}

TEST_CASE("write_candidates_ply: vertices at the path ends, one coloured edge with its utility per path",
          "[io][ply][candidates]") {
  const std::vector<nbs::LinearScanPath> paths{
      nbs::LinearScanPath(nbs::Viewpoint::look_at({0.1, 0.2, 0.3}, {0, 0, 0}), {0.1, 0.25, 0.3}),
      nbs::LinearScanPath(nbs::Viewpoint::look_at({-0.5, 0.125, 1.0 / 3.0}, {0, 0, 0}), {-0.5, 0.0, 1.0 / 3.0}),
      nbs::LinearScanPath(nbs::Viewpoint::look_at({0.0, 0.4, 0.2}, {0, 0, 0}), {0.05, 0.4, 0.2})};
  const std::vector<double> utility{2.0, 4.0, 1.0 / 3.0};
  const std::string path = (nbs_test::temp_dir() / "candidates.ply").string();
  nbs::write_candidates_ply(path, paths, utility);

  const std::string bytes = nbs::io_detail::read_file_bytes(path);
  const nbs::io_detail::PlyHeader h = nbs::io_detail::parse_ply_header(path, bytes);
  CHECK(h.format == nbs::PlyFormat::ascii);
  REQUIRE(h.elements.size() == 2);
  CHECK(h.elements[0].name == "vertex");
  CHECK(h.elements[0].count == 6);
  CHECK(h.elements[1].name == "edge");
  CHECK(h.elements[1].count == 3);
  for (const char* p : {"x", "y", "z", "red", "green", "blue"}) CHECK(h.elements[0].find(p) >= 0);
  for (const char* p : {"vertex1", "vertex2", "red", "green", "blue", "utility"}) CHECK(h.elements[1].find(p) >= 0);
  CHECK(h.elements[1].properties[5].type == nbs::PlyType::f64);

  std::istringstream body(body_of(bytes));
  const std::vector<double> u01 = nbs::normalize_utilities(utility);
  for (std::size_t i = 0; i < paths.size(); ++i)
    for (const nbs::Vec3& expected : {paths[i].start().position(), paths[i].end_position()}) {
      double x, y, z;
      int r, g, b;
      REQUIRE(body >> x >> y >> z >> r >> g >> b);
      CHECK(x == Approx(expected.x()).epsilon(1e-8));  // 9 significant digits
      CHECK(y == Approx(expected.y()).epsilon(1e-8));
      CHECK(z == Approx(expected.z()).epsilon(1e-8));
      const nbs::Rgb c = nbs::utility_color(u01[i]);
      CHECK(nbs::Rgb{std::uint8_t(r), std::uint8_t(g), std::uint8_t(b)} == c);
    }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    int v1, v2, r, g, b;
    std::string u;
    REQUIRE(body >> v1 >> v2 >> r >> g >> b >> u);
    CHECK(v1 == int(2 * i));
    CHECK(v2 == int(2 * i + 1));
    CHECK(std::strtod(u.c_str(), nullptr) == utility[i]);  // 17 digits: exact
  }
  std::string rest;
  CHECK_FALSE(body >> rest);
  CHECK(nbs::utility_color(u01[1]) == nbs::Rgb{0, 255, 0});  // the best is green
  CHECK(nbs::utility_color(u01[2]) == nbs::Rgb{255, 0, 0});  // the worst red

  CHECK_THROWS_AS(nbs::write_candidates_ply(path, paths, std::vector<double>{1.0}), nbs::InvalidArgument);
  nbs::write_candidates_ply(path, {}, {});
  CHECK(nbs::io_detail::parse_ply_header(path, nbs::io_detail::read_file_bytes(path)).elements[1].count == 0);
}
