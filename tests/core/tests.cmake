set(RAMIFORM_core_TESTS
  core/random_test.cpp
  core/parallel_test.cpp
  core/errors_test.cpp
  core/nnls_test.cpp
  core/numbers_test.cpp
  core/roots_test.cpp
  core/types_test.cpp)
