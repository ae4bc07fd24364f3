# SPDX-License-Identifier: BSD-3-Clause
# Recognition (issue 21): bench_recognition — match_ppf on partial views of the bunny; headline
# recognition.ppf_match_ms_per_cluster.
nbs_add_benchmark(recognition SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_recognition.cpp)
