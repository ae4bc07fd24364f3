# SPDX-License-Identifier: BSD-3-Clause
# Candidate evaluation (issue 5): bench_utility. Needs the Embree scanner (bunny scans).
if(TARGET nbs::embree)
  nbs_add_benchmark(utility SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_utility.cpp LIBS nbs::embree)
endif()
