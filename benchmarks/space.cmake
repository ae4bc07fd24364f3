# SPDX-License-Identifier: BSD-3-Clause
# Probabilistic voxel space vs OctoMap (issue 3): bench_space. Needs the Embree scanner (bunny scans) and OctoMap.
if(TARGET nbs::octomap AND TARGET nbs::embree)
  nbs_add_benchmark(space SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_space.cpp LIBS nbs::octomap nbs::embree)
endif()
