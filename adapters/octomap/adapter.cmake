# SPDX-License-Identifier: BSD-3-Clause
# nbs::octomap — the OctoMap backend of the probabilistic voxel space (Debian liboctomap-dev 1.9.7).
find_package(octomap QUIET)
if(octomap_FOUND)
  nbs_add_adapter(octomap octomap)
  target_link_libraries(nbs_octomap INTERFACE octomap octomath)
  message(STATUS "nbs: adapter nbs::octomap enabled (OctoMap ${OCTOMAP_VERSION})")
else()
  message(STATUS "nbs: OctoMap not found, nbs::octomap disabled")
endif()
