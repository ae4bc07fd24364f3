# SPDX-License-Identifier: BSD-3-Clause
# bench_workspace: workspace modeling at 4 x 4 x 2 m, 5 mm (Sec. 5.5): peak memory with flushing, NBV time, flush
# and reload throughput (issue 22 item 5).
# nbs_tool_options: tools/common/process_memory.hpp.
if(TARGET nbs::embree AND TARGET nbs_tool_options)
  nbs_add_benchmark(workspace SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_workspace.cpp LIBS nbs::embree nbs_tool_options)
endif()
