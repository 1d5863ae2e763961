set(RAMIFORM_skeleton_TESTS
  skeleton/skeleton_test.cpp
  skeleton/fixtures_test.cpp
  skeleton/curved_edges_test.cpp
  skeleton/from_points_test.cpp)
