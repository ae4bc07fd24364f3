// SPDX-License-Identifier: BSD-3-Clause
// The headless renderer (nbs/embree/render.hpp). Oracles: analytic silhouettes of a sphere, hand-computed pixels.
// The colour map it uses is tested in tests/io/test_color_json.cpp, PNG files in tests/png/test_write_png.cpp.

#include "nbs_catch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "analytic_meshes.hpp"
#include "nbs/embree/render.hpp"

namespace {

using nbs::Vec3;
namespace ne = nbs::embree;

std::size_t count_color(const ne::Image& img, const nbs::Rgb& c) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < img.rgb.size(); k += 3)
    n += img.rgb[k] == c[0] && img.rgb[k + 1] == c[1] && img.rgb[k + 2] == c[2];
  return n;
}

}  // namespace

TEST_CASE("renderer: bad arguments throw InvalidArgument", "[embree][render][bad-input]") {
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

TEST_CASE("renderer: the pedestal disc under the object, its rim, and the world axes", "[embree][render]") {
  // A sphere (r = 5 cm) standing on a disc of radius 10 cm at z = 0, seen straight from above (orthographic):
  // a ray hits the disc where |xy| <= 10 cm and the sphere does not hide it; the headlight is vertical there, so the
  // pixel shows the disc's albedo exactly (the outer 3 % at half of it), beyond it the background.
  const ne::Scene scene(nbs_test::sphere_mesh(Vec3(0, 0, 0.05), 0.05, 96));
  ne::Camera c;
  c.orthographic = true;
  c.ortho_height_m = 0.3;
  c.eye = Vec3(0, 0, 1);
  c.target = Vec3::Zero();
  c.up = Vec3(0, 1, 0);
  ne::RenderSetting s;
  s.width = s.height = 301;
  s.pedestal = ne::Disc{Vec3::Zero(), 0.1};
  const ne::Image img = ne::render(&scene, c, {}, s);
  const auto pixel = [&](const Vec3& p) {
    const auto q = ne::project(c, s, p);
    REQUIRE(q);
    const std::size_t k = 3 * (std::size_t(q->y()) * s.width + std::size_t(q->x()));
    return nbs::Rgb{img.rgb[k], img.rgb[k + 1], img.rgb[k + 2]};
  };
  CHECK(pixel(Vec3(0.08, 0.0, 0.0)) == s.pedestal->color);   // disc, beside the sphere
  CHECK(pixel(Vec3(0.0, -0.075, 0.0)) == s.pedestal->color);
  CHECK(pixel(Vec3(0.0988, 0.0, 0.0)) == nbs::Rgb{95, 87, 75});  // rim: half the albedo
  CHECK(pixel(Vec3(0.12, 0.0, 0.0)) == s.background);        // beyond the disc
  CHECK(pixel(Vec3(0.0, 0.0, 0.0)) == s.surface);            // the sphere's top hides the disc (head-on: albedo)
  // Depth: the sphere's top at 1 − 0.1 m, the disc at 1 m.
  const auto depth = [&](const Vec3& p) {
    const auto q = ne::project(c, s, p);
    return img.depth[std::size_t(q->y()) * s.width + std::size_t(q->x())];
  };
  CHECK(depth(Vec3(0, 0, 0)) == Approx(0.9).margin(1e-3));
  CHECK(depth(Vec3(0.08, 0, 0)) == Approx(1.0).margin(1e-9));
  // Without the pedestal the same pixel is background.
  ne::RenderSetting bare = s;
  bare.pedestal.reset();
  CHECK(count_color(ne::render(&scene, c, {}, bare), s.pedestal->color) == 0);
  // Bad pedestal: InvalidArgument naming it.
  ne::RenderSetting bad = s;
  bad.pedestal->radius_m = -1.0;
  CHECK_THROWS_WITH(ne::render(&scene, c, {}, bad), nbs_test::Contains("pedestal"));
  // The axes: three 2-px segments from the origin, x red, y green, z blue.
  const auto ax = ne::axes(Vec3(0.01, 0.02, 0.0), 0.05);
  CHECK((ax[0].b - Vec3(0.06, 0.02, 0.0)).norm() < 1e-15);
  CHECK((ax[1].b - Vec3(0.01, 0.07, 0.0)).norm() < 1e-15);
  CHECK((ax[2].b - Vec3(0.01, 0.02, 0.05)).norm() < 1e-15);
  const ne::Image with_axes = ne::render(nullptr, c, ax, s);
  CHECK(count_color(with_axes, ax[0].color) > 0);
  CHECK(count_color(with_axes, ax[1].color) > 0);
}

TEST_CASE("renderer: layers show the nearest surface in its own albedo; a null layer changes nothing",
          "[embree][render]") {
  // The object (r = 10 cm at the origin) and an "arm" sphere (r = 5 cm) sticking out of it, over a pedestal.
  // Oracle: each pixel of the two-layer picture is the one-layer picture of whichever layer is nearer there
  // (the headlight shading depends only on the pixel's own hit).
  const ne::Scene object(nbs_test::sphere_mesh(Vec3::Zero(), 0.1, 64));
  const ne::Scene arm(nbs_test::sphere_mesh(Vec3(0.1, 0.0, 0.03), 0.05, 64));
  ne::Camera c;
  c.eye = Vec3(0.2, -0.8, 0.3);
  ne::RenderSetting s;
  s.width = 160;
  s.height = 120;
  s.threads = 2;
  s.pedestal = ne::Disc{Vec3(0, 0, -0.1), 0.15};
  const nbs::Rgb orange{225, 150, 85};
  const ne::Image alone = ne::render(&object, c, {}, s);
  const std::array<ne::SceneLayer, 2> with_null{ne::SceneLayer{&object, s.surface}, ne::SceneLayer{nullptr, orange}};
  const ne::Image same = ne::render(with_null, c, {}, s);
  CHECK(same.rgb == alone.rgb);
  CHECK(same.depth == alone.depth);

  const std::array<ne::SceneLayer, 1> arm_only{ne::SceneLayer{&arm, orange}};
  const ne::Image arm_alone = ne::render(arm_only, c, {}, s);
  const std::array<ne::SceneLayer, 2> both{ne::SceneLayer{&object, s.surface}, ne::SceneLayer{&arm, orange}};
  const ne::Image img = ne::render(both, c, {}, s);
  ne::RenderSetting bare = s;
  bare.pedestal.reset();
  const ne::Image arm_mask = ne::render(&arm, c, {}, bare);  // where the arm projects
  std::size_t arm_front = 0, arm_hidden = 0, mismatches = 0;
  for (std::size_t k = 0; k < img.depth.size(); ++k) {
    const bool arm_nearer = arm_alone.depth[k] < alone.depth[k];
    const ne::Image& expect = arm_nearer ? arm_alone : alone;
    arm_front += arm_nearer;
    arm_hidden += std::isfinite(arm_mask.depth[k]) && !arm_nearer;
    mismatches += img.depth[k] != expect.depth[k] || !std::equal(img.rgb.begin() + std::ptrdiff_t(3 * k),
                                                                 img.rgb.begin() + std::ptrdiff_t(3 * k + 3),
                                                                 expect.rgb.begin() + std::ptrdiff_t(3 * k));
  }
  CHECK(mismatches == 0);
  CHECK(arm_front > 100);  // the arm is seen, and partly hidden by the object
  CHECK(arm_hidden > 20);
}

TEST_CASE("renderer: a layer with vertex colours shades each hit's interpolated colour as a single-colour layer",
          "[embree][render][color]") {
  // Two quads in the plane y = 0 side by side (x < 0 red, x > 0 blue; no shared vertex), seen in perspective from
  // (0, −1, 0.4): the plane x = 0 holds the eye, the target and up, so it splits the image at the middle column.
  // Oracle: every pixel of the coloured picture equals the single-colour picture in red (left half) or blue (right
  // half) — same Lambert × ambient shading, since the shading depends only on the hit.
  const nbs::Rgb red{220, 40, 30}, blue{30, 60, 210};
  nbs::IndexedMesh quads;
  quads.vertices = {Vec3(-0.1, 0, -0.1), Vec3(0, 0, -0.1), Vec3(0, 0, 0.1),   Vec3(-0.1, 0, 0.1),
                    Vec3(0, 0, -0.1),    Vec3(0.1, 0, -0.1), Vec3(0.1, 0, 0.1), Vec3(0, 0, 0.1)};
  quads.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  quads.colors = {red, red, red, red, blue, blue, blue, blue};
  const ne::Scene scene(quads);
  ne::Camera c;
  c.eye = Vec3(0, -1, 0.4);
  ne::RenderSetting s;
  s.width = 120;
  s.height = 90;
  const std::array<ne::SceneLayer, 1> colored{ne::SceneLayer{&scene, s.surface, &quads}};
  const std::array<ne::SceneLayer, 1> in_red{ne::SceneLayer{&scene, red}}, in_blue{ne::SceneLayer{&scene, blue}};
  const ne::Image img = ne::render(colored, c, {}, s), r = ne::render(in_red, c, {}, s),
                  b = ne::render(in_blue, c, {}, s);
  REQUIRE(img.hit_count() > 1000);
  CHECK(img.depth == r.depth);
  std::size_t hits_left = 0, hits_right = 0, mismatches = 0;
  for (std::uint32_t j = 0; j < s.height; ++j)
    for (std::uint32_t i = 0; i < s.width; ++i) {
      const std::size_t k = std::size_t(j) * s.width + i;
      if (!std::isfinite(img.depth[k])) continue;
      const bool left = i < s.width / 2;
      (left ? hits_left : hits_right) += 1;
      const ne::Image& expect = left ? r : b;
      mismatches += !std::equal(img.rgb.begin() + std::ptrdiff_t(3 * k), img.rgb.begin() + std::ptrdiff_t(3 * k + 3),
                                expect.rgb.begin() + std::ptrdiff_t(3 * k));
    }
  CHECK(mismatches == 0);
  CHECK(hits_left > 500);
  CHECK(hits_right > 500);
  // The shading is not trivial here (the plane is seen at an angle): the red picture is darker than the albedo.
  const std::size_t centre = 3 * (std::size_t(s.height / 2) * s.width + s.width / 2 - 5);
  REQUIRE(std::isfinite(r.depth[centre / 3]));
  CHECK(int(r.rgb[centre]) < int(red[0]) - 5);

  SECTION("barycentric interpolation inside a triangle, head-on") {
    nbs::IndexedMesh tri;
    tri.vertices = {Vec3(-0.1, 0, -0.1), Vec3(0.1, 0, -0.1), Vec3(0, 0, 0.1)};
    tri.triangles = {{0, 1, 2}};
    tri.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
    const ne::Scene one(tri);
    ne::Camera o;
    o.orthographic = true;
    o.ortho_height_m = 0.3;
    o.eye = Vec3(0, -1, 0);
    ne::RenderSetting h;
    h.width = h.height = 301;  // 1 mm per pixel; the centre pixel's ray passes through (0, 0, 0)
    const std::array<ne::SceneLayer, 1> layer{ne::SceneLayer{&one, h.surface, &tri}};
    const ne::Image t = ne::render(layer, o, {}, h);
    // (0, 0, 0) = 0.25 a + 0.25 b + 0.5 c; head-on: shade 1, the pixel is the interpolated colour.
    const std::size_t k = 3 * (std::size_t(150) * h.width + 150);
    CHECK(int(t.rgb[k]) == Approx(64).margin(1));
    CHECK(int(t.rgb[k + 1]) == Approx(64).margin(1));
    CHECK(int(t.rgb[k + 2]) == Approx(128).margin(1));
  }
  SECTION("bad colours throw InvalidArgument naming them") {
    nbs::IndexedMesh bad = quads;
    bad.colors.pop_back();
    const std::array<ne::SceneLayer, 1> layer{ne::SceneLayer{&scene, s.surface, &bad}};
    CHECK_THROWS_WITH(ne::render(layer, c, {}, s), nbs_test::Contains("colours for 8 vertices"));
  }
}
