# SPDX-License-Identifier: BSD-3-Clause
# bench_workspace: workspace modeling at 4 x 4 x 2 m, 5 mm (Sec. 5.5): peak memory with flushing, NBV time, flush
# and reload throughput (issue 22 item 5).
if(TARGET nbs::embree)
  nbs_add_benchmark(workspace SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_workspace.cpp LIBS nbs::embree)
  target_include_directories(bench_workspace PRIVATE ${PROJECT_SOURCE_DIR}/tools)  # common/process_memory.hpp
endif()
