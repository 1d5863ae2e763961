set(RAMIFORM_sample_TESTS sample/point_sets_test.cpp)
