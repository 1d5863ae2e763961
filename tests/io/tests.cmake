set(RAMIFORM_io_TESTS
  io/atomic_file_test.cpp
  io/curve_io_test.cpp
  io/mesh_io_test.cpp
  io/points_io_test.cpp
  io/qsm_test.cpp
  io/shared_data_test.cpp
  io/skeleton_io_test.cpp)
