# SPDX-License-Identifier: BSD-3-Clause
# The main job (scripts/demo.sh): needs the Embree scanner.
if(TARGET nbs::embree)
  nbs_add_example(nbs_model SOURCES nbs_model.cpp LIBS nbs::embree)
endif()
