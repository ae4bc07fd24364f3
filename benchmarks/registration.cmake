# SPDX-License-Identifier: BSD-3-Clause
# Registration (issue 20): bench_registration — nbs::Icp against Open3D 0.16 and PCL 1.13 point-to-plane ICP on scan
# pairs of the bunny. Needs the Embree scanner. The incumbents are benchmark-only (scripts/install-deps.sh
# --with-bench-incumbents, which scripts/bench.sh passes) and each is optional: without it the bench prints nbs's own
# figures only. NBS_BENCH_OPEN3D / NBS_BENCH_PCL = OFF leave one out even when installed.
if(TARGET nbs::embree)
  option(NBS_BENCH_OPEN3D "bench_registration: compare with Open3D when found" ON)
  set(_nbs_reg_sources ${CMAKE_CURRENT_LIST_DIR}/bench_registration.cpp)
  set(_nbs_reg_libs nbs::embree)
  set(_nbs_reg_defs "")
  if(NBS_BENCH_OPEN3D)
    find_package(Open3D QUIET)  # its version file accepts only the exact version asked for: check it here
    find_package(OpenMP QUIET)  # Open3D's ICP runs on OpenMP threads; the bench sets them to 1 (see the .cpp)
    if(TARGET Open3D::Open3D AND Open3D_VERSION VERSION_GREATER_EQUAL 0.16 AND TARGET OpenMP::OpenMP_CXX)
      list(APPEND _nbs_reg_sources ${CMAKE_CURRENT_LIST_DIR}/registration_open3d.cpp)
      list(APPEND _nbs_reg_libs Open3D::Open3D OpenMP::OpenMP_CXX)
      list(APPEND _nbs_reg_defs NBS_BENCH_HAVE_OPEN3D=1)
    endif()
  endif()
  nbs_add_bench_pcl_unit(${CMAKE_CURRENT_LIST_DIR}/registration_pcl.cpp _nbs_reg_sources _nbs_reg_libs _nbs_reg_defs)
  nbs_add_benchmark(registration SOURCES ${_nbs_reg_sources} LIBS ${_nbs_reg_libs})
  target_compile_definitions(bench_registration PRIVATE ${_nbs_reg_defs})
  message(STATUS "bench_registration incumbents: ${_nbs_reg_defs}")
endif()
