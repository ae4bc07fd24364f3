# SPDX-License-Identifier: BSD-3-Clause
# The main job (scripts/demo.sh): needs the Embree scanner, libpng for its pictures and the tools' shared options
# (CLI11, tools/).
if(TARGET nbs::embree AND TARGET nbs::png AND TARGET nbs_tool_options)
  nbs_add_example(nbs_model SOURCES nbs_model.cpp LIBS nbs::embree nbs::png nbs_tool_options)
  if(NBS_INSTALL)
    install(TARGETS nbs_model RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endif()
# nbs_explore: the scene-exploration loop (issue 21 item 5) with the Embree scanner; not a CTest (a run takes
# minutes: docs/evaluation.md, "Scene exploration").
if(TARGET nbs::embree AND TARGET nbs::png AND TARGET nbs_tool_options)
  nbs_add_example(nbs_explore SOURCES nbs_explore.cpp LIBS nbs::embree nbs::png nbs_tool_options)
endif()
