# SPDX-License-Identifier: BSD-3-Clause
# Recognition (issue 21): bench_recognition — match_ppf on partial views of the bunny; headlines
# recognition.ppf_match_ms_per_cluster and, when PCL 1.13 is found (benchmark-only incumbent, see
# nbs_add_bench_pcl_unit in CMakeLists.txt), recognition.ppf_vs_pcl against pcl::PPFRegistration. Without PCL the bench
# prints nbs's own figures only.
set(_nbs_rec_sources ${CMAKE_CURRENT_LIST_DIR}/bench_recognition.cpp)
set(_nbs_rec_libs "")
set(_nbs_rec_defs "")
nbs_add_bench_pcl_unit(${CMAKE_CURRENT_LIST_DIR}/recognition_pcl.cpp _nbs_rec_sources _nbs_rec_libs _nbs_rec_defs)
nbs_add_benchmark(recognition SOURCES ${_nbs_rec_sources} LIBS ${_nbs_rec_libs})
target_compile_definitions(bench_recognition PRIVATE ${_nbs_rec_defs})
message(STATUS "bench_recognition incumbents: ${_nbs_rec_defs}")
