# SPDX-License-Identifier: BSD-3-Clause
# Gives OMPL the imported target ompl::ompl when its CMake config does not (OMPL < 1.6 sets only the variables
# OMPL_INCLUDE_DIRS / OMPL_LIBRARIES), so that nbs::ompl links a target by name and the installed nbs package holds
# no absolute paths: the consumer's own find_package(ompl) fills the target in. Include after find_package(ompl).
if(NOT TARGET ompl::ompl)
  add_library(ompl::ompl INTERFACE IMPORTED GLOBAL)
  set_target_properties(ompl::ompl PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${OMPL_INCLUDE_DIRS}"
                                              INTERFACE_LINK_LIBRARIES "${OMPL_LIBRARIES}")
endif()
