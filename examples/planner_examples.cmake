# Planner examples (issue 5): compose a planner from policies; plug in a user-defined utility term.
if(TARGET nbs::embree)
  nbs_add_example(02_compose_your_planner SOURCES ${CMAKE_CURRENT_LIST_DIR}/02_compose_your_planner.cpp LIBS nbs::embree)
endif()
if(TARGET nbs::embree)
  nbs_add_example(03_custom_utility_term SOURCES ${CMAKE_CURRENT_LIST_DIR}/03_custom_utility_term.cpp LIBS nbs::embree)
endif()
# A thin hardware-driver adapter (units and frames converted at the boundary); core only, runs without hardware.
nbs_add_example(04_driver_adapter SOURCES ${CMAKE_CURRENT_LIST_DIR}/04_driver_adapter.cpp)
