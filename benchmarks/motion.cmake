# SPDX-License-Identifier: BSD-3-Clause
# Joint-space transfer motions of the shipped arm (issue 19, item 3): bench_motion. Needs OMPL and the KDL robot.
# nbs::kdl is linked before nbs::ompl: Debian's libompl.so.16 and liborocos-kdl.so.1.5 both export Eigen's
# JacobiSVD<MatrixXd> instantiations, and with OMPL first KDL's LMA IK runs OMPL's copy and aborts on an Eigen
# assertion ("This SVD decomposition didn't compute U").
# bench_motion_loop.cpp (motion.c_a_at_10_robot_vs_free) runs nbs_eval's run_one: it needs what nbs_eval needs, and
# nbs_tool_options built with KDL and OMPL (tools/CMakeLists.txt links them in that order).
find_package(nlohmann_json 3 QUIET)
if(TARGET nbs::ompl AND TARGET nbs::kdl AND TARGET nbs::embree AND TARGET nlohmann_json::nlohmann_json
   AND TARGET nbs_tool_options)
  nbs_add_benchmark(motion SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_motion.cpp
                    ${CMAKE_CURRENT_LIST_DIR}/bench_motion_loop.cpp
                    LIBS nbs::kdl nbs::ompl nbs::embree nlohmann_json::nlohmann_json nbs_tool_options)
  target_include_directories(bench_motion PRIVATE ${PROJECT_SOURCE_DIR}/benchmarks)
endif()
