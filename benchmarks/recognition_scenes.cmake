# SPDX-License-Identifier: BSD-3-Clause
# Recognition from random single views of seeded scenes (issue 21 items 6-7, thesis Sec. 5.6.2):
# bench_recognition_scenes; headlines recognition.single_view_recall and recognition.false_positive_rate. Needs the
# Embree scanner (area-sensor frames of the scene, model rendering for q_h).
if(TARGET nbs::embree)
  nbs_add_benchmark(recognition_scenes SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_recognition_scenes.cpp LIBS nbs::embree)
endif()
