// SPDX-License-Identifier: BSD-3-Clause
// The utility colour map (color.hpp) and JSON files (write_json.hpp). Oracles: hand-computed colours, nlohmann-json's
// parser and strtod for the numbers written.

#include "nbs_catch.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nbs/io/color.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/io/write_json.hpp"
#include "temp_dir.hpp"

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

TEST_CASE("write_json: doubles round-trip, non-finite is null, key order kept, atomic", "[io][json]") {
  const std::string path = (nbs_test::temp_dir() / "report.json").string();
  const std::vector<double> values{0.1,         -1.0 / 3.0, 1e-300, 6.02214076e23,
                                   123456789.0, 0.0,        5e-324, 1.7976931348623157e308};
  nlohmann::ordered_json j;
  j["method"] = "C_H";
  j["series"] = {{"c_a", values}, {"scan", {1, 2, 3}}};
  j["final"] = {{"e_rms_m", std::numeric_limits<double>::quiet_NaN()},
                {"l_s_m", -std::numeric_limits<double>::infinity()},
                {"name", "a\"b\\c\nd\x01"}};
  nbs::write_json(path, j);
  const std::string text = nbs::io_detail::read_file_bytes(path);
  CHECK(text.back() == '\n');
  CHECK(text.find("\"method\"") < text.find("\"series\""));  // insertion order, not sorted
  CHECK(text.find("\"series\"") < text.find("\"final\""));
  const nlohmann::json back = nlohmann::json::parse(text);
  REQUIRE(back["series"]["c_a"].size() == values.size());
  for (std::size_t i = 0; i < values.size(); ++i) CHECK(back["series"]["c_a"][i].get<double>() == values[i]);  // exact
  CHECK(back["series"]["scan"][2].is_number_integer());
  CHECK(back["final"]["e_rms_m"].is_null());
  CHECK(back["final"]["l_s_m"].is_null());
  CHECK(back["final"]["name"] == "a\"b\\c\nd\x01");
  CHECK(back["method"] == "C_H");
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));

  // Invalid UTF-8: InvalidArgument naming the file, the old file untouched.
  CHECK_THROWS_WITH(nbs::write_json(path, nlohmann::json{{"mesh", "\xff\xfe"}}),
                    nbs_test::Contains(path) && nbs_test::Contains("cannot write JSON"));
  CHECK(nbs::io_detail::read_file_bytes(path) == text);
  // A write that fails leaves no file: a missing directory, and a directory in the way of the rename.
  const std::string missing = (nbs_test::temp_dir() / "no-such-dir" / "x.json").string();
  CHECK_THROWS_AS(nbs::write_json(missing, j), nbs::FileError);
  CHECK_FALSE(std::filesystem::exists(missing));
  const std::filesystem::path dir = nbs_test::temp_dir() / "a-directory.json";
  std::filesystem::create_directories(dir / "child");
  CHECK_THROWS_WITH(nbs::write_json(dir.string(), j), nbs_test::Contains(dir.string()));
  CHECK(std::filesystem::is_directory(dir));
  CHECK_FALSE(std::filesystem::exists(dir.string() + ".tmp"));
}
