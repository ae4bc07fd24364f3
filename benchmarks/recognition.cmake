# SPDX-License-Identifier: BSD-3-Clause
# Recognition (issue 21): bench_recognition — match_ppf on partial views of the bunny; headlines
# recognition.ppf_match_ms_per_cluster and, when PCL 1.13 is found (benchmark-only incumbent, see
# nbs_find_bench_pcl in CMakeLists.txt), recognition.ppf_vs_pcl against pcl::PPFRegistration. Without PCL the bench
# prints nbs's own figures only.
set(_nbs_rec_sources ${CMAKE_CURRENT_LIST_DIR}/bench_recognition.cpp)
set(_nbs_rec_libs "")
set(_nbs_rec_defs "")
nbs_find_bench_pcl(_nbs_rec_pcl)
if(_nbs_rec_pcl)
  list(APPEND _nbs_rec_sources ${CMAKE_CURRENT_LIST_DIR}/recognition_pcl.cpp)
  # As registration_pcl.cpp: GCC 12 -Warray-bounds false positive inside Eigen's SSE code inlined from PCL's
  # templates; this unit only, which holds no nbs code.
  set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/recognition_pcl.cpp PROPERTIES COMPILE_OPTIONS
                              -Wno-array-bounds)
  list(APPEND _nbs_rec_libs nbs_bench_pcl)
  list(APPEND _nbs_rec_defs NBS_BENCH_HAVE_PCL=1)
endif()
nbs_add_benchmark(recognition SOURCES ${_nbs_rec_sources} LIBS ${_nbs_rec_libs})
target_compile_definitions(bench_recognition PRIVATE ${_nbs_rec_defs})
message(STATUS "bench_recognition incumbents: ${_nbs_rec_defs}")
