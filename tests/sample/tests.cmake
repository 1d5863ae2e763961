set(RAMIFORM_sample_TESTS
  sample/point_sets_test.cpp
  sample/parsing_test.cpp
  sample/point_grid_test.cpp
  sample/sum_tree_test.cpp)
