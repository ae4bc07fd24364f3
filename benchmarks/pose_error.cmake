# SPDX-License-Identifier: BSD-3-Clause
# Pose error + registration in the loop (issue 20): bench_pose_error — ē of C_H on the bunny with exact poses, a
# 1 mm / 0.1° pose error, and the error with ICP, through nbs_eval's run_one. Needs what nbs_eval needs.
if(TARGET nbs::embree AND TARGET nlohmann_json::nlohmann_json AND TARGET nbs_tool_options)
  nbs_add_benchmark(pose_error SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_pose_error.cpp
                    LIBS nbs::embree nlohmann_json::nlohmann_json nbs_tool_options)
  target_include_directories(bench_pose_error PRIVATE ${PROJECT_SOURCE_DIR}/benchmarks)
endif()
