# SPDX-License-Identifier: BSD-3-Clause
# nbs_workspace: workspace modeling at room scale (Sec. 5.5, issue 22 item 1), simulated; not a CTest (the full
# 4 x 4 x 2 m run takes minutes: docs/evaluation.md, "Workspace modeling"). With the OctoMap adapter it also writes
# the collision model as a .bt file.
if(TARGET nbs::embree AND TARGET nbs::png AND TARGET nbs_tool_options)
  set(_nbs_ws_libs nbs::embree nbs::png nbs_tool_options)
  if(TARGET nbs::octomap)
    list(APPEND _nbs_ws_libs nbs::octomap)
  endif()
  nbs_add_example(nbs_workspace SOURCES nbs_workspace.cpp LIBS ${_nbs_ws_libs})
  if(TARGET nbs::octomap)
    target_compile_definitions(nbs_workspace PRIVATE NBS_WORKSPACE_OCTOMAP)
  endif()
endif()
