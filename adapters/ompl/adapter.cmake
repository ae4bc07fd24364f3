# SPDX-License-Identifier: BSD-3-Clause
# nbs::ompl — transfer motions between scan paths with OMPL's RRT-Connect (Debian libompl-dev 1.5; Sec. 3.2.2).
# OMPL's CMake config links Boost (serialization, filesystem, system) and ODE, installed by scripts/install-deps.sh.
find_package(ompl QUIET)
if(ompl_FOUND OR OMPL_FOUND)
  include(${PROJECT_SOURCE_DIR}/cmake/nbsOmplTarget.cmake)  # ompl::ompl, also for the installed package
  nbs_add_adapter(ompl ompl)
  target_link_libraries(nbs_ompl INTERFACE ompl::ompl)
  message(STATUS "nbs: adapter nbs::ompl enabled (OMPL ${OMPL_VERSION})")
else()
  message(STATUS "nbs: OMPL not found, nbs::ompl disabled")
endif()
