set(RAMIFORM_lines_TESTS
  lines/camera_test.cpp
  lines/features_test.cpp
  lines/silhouettes_test.cpp
  lines/suggestive_test.cpp
  lines/visibility_test.cpp)
