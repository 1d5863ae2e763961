set(RAMIFORM_sample_TESTS
  sample/point_sets_test.cpp
  sample/parsing_test.cpp
  sample/point_grid_test.cpp
  sample/sum_tree_test.cpp)
# The sum tree and the grids are internal (src/sample/); their tests reach them directly.
set_source_files_properties(sample/point_grid_test.cpp sample/sum_tree_test.cpp
                            PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/src)
