// SPDX-License-Identifier: BSD-3-Clause
// The Catch2 main, compiled once: v2 generates it here; v3 links Catch2::Catch2WithMain (tests/CMakeLists.txt).
#if !__has_include(<catch2/catch_all.hpp>)
#define CATCH_CONFIG_MAIN
#endif
#include "nbs_catch.hpp"
