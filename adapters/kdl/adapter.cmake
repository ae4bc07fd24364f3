# SPDX-License-Identifier: BSD-3-Clause
# nbs::kdl — a URDF robot (urdfdom) with KDL's kinematics (Debian liborocos-kdl-dev 1.5.1, liburdfdom-dev 3.0.1;
# issue 19). The KDL chain is built from urdfdom's model here (Debian's kdl_parser package pulls in ROS 1).
find_package(orocos_kdl QUIET)
find_package(urdfdom QUIET)
if(orocos_kdl_FOUND AND urdfdom_FOUND)
  include(${PROJECT_SOURCE_DIR}/cmake/nbsKdlTarget.cmake)  # orocos_kdl::orocos_kdl, also for the installed package
  nbs_add_adapter(kdl "orocos_kdl+urdfdom")
  target_link_libraries(nbs_kdl INTERFACE orocos_kdl::orocos_kdl urdfdom::urdfdom_model)
  message(STATUS "nbs: adapter nbs::kdl enabled (orocos_kdl ${orocos_kdl_VERSION}, urdfdom ${urdfdom_VERSION})")
else()
  message(STATUS "nbs: orocos_kdl or urdfdom not found, nbs::kdl disabled")
endif()
