// SPDX-License-Identifier: BSD-3-Clause
#include <variant>

#include "nbs/sensor/presets.hpp"
#include "nbs_catch.hpp"

TEST_CASE("presets::by_name returns each named preset and rejects others", "[sensor][presets]") {
  const auto lsp = std::get<nbs::LaserStripeProfiler>(nbs::presets::by_name("dlr_lsp"));
  CHECK(lsp.fan_angle_rad == nbs::presets::dlr_lsp().fan_angle_rad);
  CHECK(std::get<nbs::LaserStripeProfiler>(nbs::presets::by_name("scancontrol_2700_100")).range.max_m ==
        nbs::presets::scancontrol_2700_100().range.max_m);
  CHECK(std::get<nbs::AreaSensor>(nbs::presets::by_name("asus_xtion_pro")).width_px == 640);
  CHECK(std::get<nbs::AreaSensor>(nbs::presets::by_name("guppy_pro_stereo")).width_px == 1292);
  for (std::string_view n : nbs::presets::kNames) CHECK_NOTHROW(nbs::presets::by_name(n));
  CHECK_THROWS_WITH(nbs::presets::by_name("DLR_LSP"), nbs_test::Contains("unknown sensor preset 'DLR_LSP'") &&
                                                          nbs_test::Contains("guppy_pro_stereo"));
  CHECK_THROWS_WITH(nbs::presets::lsp_by_name("asus_xtion_pro"), nbs_test::Contains("is an area sensor"));
  CHECK(nbs::presets::lsp_by_name("scancontrol_2700_100").range.min_m == 0.3);
}
