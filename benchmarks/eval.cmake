# SPDX-License-Identifier: BSD-3-Clause
# The evaluation harness nbs_eval (issue 6): a plain executable, not a Google Benchmark (scripts/bench.sh runs
# bench_* only). Needs the Embree scanner, nlohmann-json (Debian nlohmann-json3-dev) and the tools' shared options
# (tools/common/options.hpp, CLI11).
find_package(nlohmann_json 3 QUIET)
if(TARGET nbs::embree AND TARGET nlohmann_json::nlohmann_json AND TARGET nbs_tool_options AND NOT TARGET nbs_eval)
  add_executable(nbs_eval ${PROJECT_SOURCE_DIR}/benchmarks/nbs_eval.cpp)
  target_include_directories(nbs_eval PRIVATE ${PROJECT_SOURCE_DIR}/benchmarks)
  target_link_libraries(nbs_eval PRIVATE nbs::nbs nbs::embree nlohmann_json::nlohmann_json nbs_tool_options)
endif()
