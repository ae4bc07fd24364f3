# SPDX-License-Identifier: BSD-3-Clause
# nbs::fcl — FCL collision checking of the sensor head (Debian libfcl-dev 0.7.0, built with OctoMap support).
# The obstacle voxels reach FCL as an octomap::OcTree exported by nbs::octomap, so nbs::fcl needs both.
find_package(fcl QUIET)
if(fcl_FOUND AND TARGET nbs_octomap)
  nbs_add_adapter(fcl fcl)
  target_link_libraries(nbs_fcl INTERFACE fcl nbs_octomap)
  message(STATUS "nbs: adapter nbs::fcl enabled (FCL ${FCL_VERSION})")
elseif(fcl_FOUND)
  message(STATUS "nbs: FCL found but nbs::octomap is disabled, nbs::fcl disabled")
else()
  message(STATUS "nbs: FCL not found, nbs::fcl disabled")
endif()
