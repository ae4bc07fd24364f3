// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <cmath>
#include <numbers>

#include "nbs/sensor/presets.hpp"

using nbs_test::Contains;
using nbs::Vec3;

TEST_CASE("Area sensor corner rays lie half a pixel inside the FOV", "[sensor][area]") {
  nbs::AreaSensor s = nbs::presets::asus_xtion_pro();
  s.width_px = 64;
  s.height_px = 48;
  const auto view = nbs::Viewpoint::look_at({1, 0.5, 0.4}, {0, 0, 0.1});
  const auto dirs = s.frame_directions(view);
  REQUIRE(dirs.size() == 64u * 48u);
  const Vec3 sx = view.x_axis(), sy = view.y_axis(), sz = view.view_direction();
  // Pixel-centre oracle: tan(angle) = tan(fov/2)·(1 − 1/n) at the outermost pixel.
  const double ax = std::atan(std::tan(0.5 * s.horizontal_fov_rad) * (1.0 - 1.0 / 64));
  const double ay = std::atan(std::tan(0.5 * s.vertical_fov_rad) * (1.0 - 1.0 / 48));
  const Vec3& top_left = dirs.front();  // (u, v) = (0, 0): x < 0, y < 0 (image y points down)
  const Vec3& bottom_right = dirs.back();
  CHECK(std::atan2(top_left.dot(sx), top_left.dot(sz)) == Approx(-ax));
  CHECK(std::atan2(top_left.dot(sy), top_left.dot(sz)) == Approx(-ay));
  CHECK(std::atan2(bottom_right.dot(sx), bottom_right.dot(sz)) == Approx(ax));
  CHECK(std::atan2(bottom_right.dot(sy), bottom_right.dot(sz)) == Approx(ay));
  const Vec3& top_right = dirs[63];  // row-major
  CHECK(std::atan2(top_right.dot(sx), top_right.dot(sz)) == Approx(ax));
  for (const Vec3& d : dirs) CHECK(d.norm() == Approx(1.0));
}

TEST_CASE("Area sensor with odd resolution has a central ray along the view direction", "[sensor][area]") {
  nbs::AreaSensor s = nbs::presets::guppy_pro_stereo();
  s.width_px = 5;
  s.height_px = 3;
  CHECK(s.ray_count() == 15);
  CHECK(s.ray_direction_sensor(2, 1).isApprox(Vec3::UnitZ()));
}

TEST_CASE("Area sensor presets follow Tab. 5.1", "[sensor][area]") {
  const auto deg = [](double d) { return d * std::numbers::pi / 180.0; };
  const auto x = nbs::presets::asus_xtion_pro();
  x.validate();
  CHECK((x.width_px == 640 && x.height_px == 480));
  CHECK(x.horizontal_fov_rad == Approx(deg(58)));
  CHECK(x.vertical_fov_rad == Approx(deg(45)));
  CHECK((x.range.min_m == 0.5 && x.range.max_m == 3.5));
  const auto g = nbs::presets::guppy_pro_stereo();
  g.validate();
  CHECK((g.width_px == 1292 && g.height_px == 964));
  CHECK(g.horizontal_fov_rad == Approx(deg(57.4)));
  CHECK(g.vertical_fov_rad == Approx(deg(44.3)));
  CHECK(g.range.min_m == 0.2);
}

TEST_CASE("Area sensor parameter validation names field and value", "[sensor][area][bad-input]") {
  auto check_bad = [](auto mutate, const char* field) {
    nbs::AreaSensor s = nbs::presets::asus_xtion_pro();
    mutate(s);
    CHECK_THROWS_WITH(s.validate(), Contains(field));
    CHECK_THROWS_AS(s.frame_directions(nbs::Viewpoint()), nbs::InvalidArgument);
  };
  check_bad([](auto& s) { s.width_px = 0; }, "width_px");
  check_bad([](auto& s) { s.height_px = -3; }, "height_px");
  check_bad([](auto& s) { s.horizontal_fov_rad = std::nan(""); }, "horizontal_fov_rad");
  check_bad([](auto& s) { s.vertical_fov_rad = 0.0; }, "vertical_fov_rad");
  check_bad([](auto& s) { s.range.min_m = 0.0; }, "range.min_m");
  check_bad([](auto& s) { s.range.max_m = std::nan(""); }, "range.max_m");
}
