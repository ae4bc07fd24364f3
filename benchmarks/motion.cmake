# SPDX-License-Identifier: BSD-3-Clause
# Joint-space transfer motions of the shipped arm (issue 19, item 3): bench_motion. Needs OMPL and the KDL robot.
# nbs::kdl is linked before nbs::ompl: Debian's libompl.so.16 and liborocos-kdl.so.1.5 both export Eigen's
# JacobiSVD<MatrixXd> instantiations, and with OMPL first KDL's LMA IK runs OMPL's copy and aborts on an Eigen
# assertion ("This SVD decomposition didn't compute U").
if(TARGET nbs::ompl AND TARGET nbs::kdl)
  nbs_add_benchmark(motion SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_motion.cpp LIBS nbs::kdl nbs::ompl)
endif()
