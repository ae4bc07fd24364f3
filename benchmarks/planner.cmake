# Planner (issue 5): bench_planner — t_nbs of C_H on the bunny at 160 mm, Tab. 4.3, 2 threads. Needs Embree.
if(TARGET nbs::embree)
  nbs_add_benchmark(planner SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_planner.cpp LIBS nbs::embree)
endif()
