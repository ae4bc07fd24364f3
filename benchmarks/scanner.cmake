# SPDX-License-Identifier: BSD-3-Clause
# Simulated scanner vs raw Embree (issue 2): bench_scanner.
if(TARGET nbs::embree)
  nbs_add_benchmark(scanner SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_scanner.cpp LIBS nbs::embree)
endif()
