# SPDX-License-Identifier: BSD-3-Clause
# nbs::png — compressed PNG files through libpng's simplified API (Debian libpng-dev 1.6; CMake's FindPNG, which
# also finds zlib). The core stays free of libpng: nbs_model's pictures use this adapter.
find_package(PNG 1.6 QUIET)
if(PNG_FOUND)
  nbs_add_adapter(png PNG 1.6)
  target_link_libraries(nbs_png INTERFACE PNG::PNG)
  message(STATUS "nbs: adapter nbs::png enabled (libpng ${PNG_VERSION_STRING})")
else()
  message(STATUS "nbs: libpng not found, nbs::png disabled")
endif()
