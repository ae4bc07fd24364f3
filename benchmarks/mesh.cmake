nbs_add_benchmark(mesh SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_mesh.cpp)
