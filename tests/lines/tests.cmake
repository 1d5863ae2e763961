set(RAMIFORM_lines_TESTS
  lines/camera_test.cpp
  lines/visibility_test.cpp)
