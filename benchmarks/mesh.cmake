# SPDX-License-Identifier: BSD-3-Clause
# Streaming mesh (issue 4): bench_mesh. With nbs::embree the throughput headline streams simulated LSP scans of the
# bundled bunny; without it, a synthetic sphere stream.
if(TARGET nbs::embree)
  nbs_add_benchmark(mesh SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_mesh.cpp LIBS nbs::embree)
  target_compile_definitions(bench_mesh PRIVATE NBS_BENCH_MESH_BUNNY)
else()
  nbs_add_benchmark(mesh SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_mesh.cpp)
endif()
