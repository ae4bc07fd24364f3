# SPDX-License-Identifier: BSD-3-Clause
# The soak run (issue 17): nbs_soak, a plain executable (not run by ctest; scripts/bench.sh runs bench_* only, so
# not by bench.sh either). Needs the Embree scanner and tools/common (process_memory.hpp). Usage: nbs_soak [--quick].
if(TARGET nbs::embree AND NOT TARGET nbs_soak)
  add_executable(nbs_soak ${PROJECT_SOURCE_DIR}/benchmarks/bench_soak.cpp)
  target_link_libraries(nbs_soak PRIVATE nbs::nbs nbs::embree nbs_project_options)
  target_include_directories(nbs_soak PRIVATE ${PROJECT_SOURCE_DIR}/tools)  # common/process_memory.hpp
  target_compile_definitions(nbs_soak PRIVATE NBS_DATA_DIR="${PROJECT_SOURCE_DIR}/data")
endif()
