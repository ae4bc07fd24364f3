# SPDX-License-Identifier: BSD-3-Clause
# The main job (scripts/demo.sh): needs the Embree scanner and libpng for its pictures.
if(TARGET nbs::embree AND TARGET nbs::png)
  nbs_add_example(nbs_model SOURCES nbs_model.cpp LIBS nbs::embree nbs::png)
endif()
