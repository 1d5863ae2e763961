set(RAMIFORM_lines_TESTS
  lines/camera_test.cpp
  lines/suggestive_test.cpp)
