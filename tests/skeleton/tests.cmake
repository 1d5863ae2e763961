set(RAMIFORM_skeleton_TESTS
  skeleton/skeleton_test.cpp
  skeleton/fixtures_test.cpp)
