# SPDX-License-Identifier: BSD-3-Clause
find_package(embree 3 QUIET)
if(embree_FOUND)
  nbs_add_adapter(embree embree 3)
  target_link_libraries(nbs_embree INTERFACE embree)
  message(STATUS "nbs: adapter nbs::embree enabled (Embree ${embree_VERSION})")
else()
  message(STATUS "nbs: Embree not found, nbs::embree disabled")
endif()
