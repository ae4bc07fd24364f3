# SPDX-License-Identifier: BSD-3-Clause
# nbs_reorient: the bottom by reorientation (Sec. 5.3, issue 22 item 3) measured on a mesh; not a CTest (a run takes
# a minute: docs/evaluation.md, "Bottom by reorientation").
if(TARGET nbs::embree)
  nbs_add_example(nbs_reorient SOURCES nbs_reorient.cpp LIBS nbs::embree)
endif()
