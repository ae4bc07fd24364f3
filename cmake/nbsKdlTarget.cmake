# SPDX-License-Identifier: BSD-3-Clause
# Gives KDL the imported target orocos_kdl::orocos_kdl when its CMake config does not (orocos_kdl 1.5 sets only the
# variables orocos_kdl_INCLUDE_DIRS / orocos_kdl_LIBRARIES), so that nbs::kdl links a target by name and the installed
# nbs package holds no absolute paths: the consumer's own find_package(orocos_kdl) fills the target in. Include after
# find_package(orocos_kdl).
if(NOT TARGET orocos_kdl::orocos_kdl)
  add_library(orocos_kdl::orocos_kdl INTERFACE IMPORTED GLOBAL)
  set_target_properties(orocos_kdl::orocos_kdl PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${orocos_kdl_INCLUDE_DIRS}"
                                                          INTERFACE_LINK_LIBRARIES "${orocos_kdl_LIBRARIES}")
endif()
