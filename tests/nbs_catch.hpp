// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Catch2 for the tests, v2 (Debian 12's single header) or v3 (Debian 13, Ubuntu 24.04), chosen by what is
// installed. The tests use `Approx` and `nbs_test::Contains` (a substring matcher), which exist under these names in
// both: v3 moved Approx into Catch:: and renamed the substring matcher ContainsSubstring.
#if __has_include(<catch2/catch_all.hpp>)
#include <catch2/catch_all.hpp>

#include <string>

using Catch::Approx;
namespace nbs_test {
[[nodiscard]] inline auto Contains(const std::string& text, Catch::CaseSensitive cs = Catch::CaseSensitive::Yes) {
  return Catch::Matchers::ContainsSubstring(text, cs);
}
}  // namespace nbs_test
#else
#include <catch2/catch.hpp>
namespace nbs_test {
using Catch::Matchers::Contains;
}  // namespace nbs_test
#endif
