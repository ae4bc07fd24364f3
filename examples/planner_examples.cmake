# SPDX-License-Identifier: BSD-3-Clause
# The numbered examples, in order of difficulty; each runs as the CTest test example.<name> and exits non-zero when
# its own result is wrong.
# 01: embed NbsPlanner<> in your program; core only (an analytic sphere stands in for the robot).
nbs_add_example(01_embed_the_planner SOURCES ${CMAKE_CURRENT_LIST_DIR}/01_embed_the_planner.cpp TEST)
# 02, 03: compose the planner's policies; plug in your own utility term (the bunny, Embree scanner).
if(TARGET nbs::embree)
  nbs_add_example(02_compose_your_planner SOURCES ${CMAKE_CURRENT_LIST_DIR}/02_compose_your_planner.cpp
                  LIBS nbs::embree TEST)
  nbs_add_example(03_custom_utility_term SOURCES ${CMAKE_CURRENT_LIST_DIR}/03_custom_utility_term.cpp
                  LIBS nbs::embree TEST)
endif()
# 04: a thin hardware-driver adapter (units and frames converted at the boundary); core only, runs without hardware.
nbs_add_example(04_driver_adapter SOURCES ${CMAKE_CURRENT_LIST_DIR}/04_driver_adapter.cpp TEST)
# 05: your own voxel space as the planner's Space policy (examples/my_voxel_space.hpp; the bunny, Embree scanner).
if(TARGET nbs::embree)
  nbs_add_example(05_your_own_voxel_space SOURCES ${CMAKE_CURRENT_LIST_DIR}/05_your_own_voxel_space.cpp
                  LIBS nbs::embree TEST)
endif()
