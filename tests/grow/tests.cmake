set(RAMIFORM_grow_TESTS grow/space_colonization_test.cpp grow/branch_cleanup_test.cpp grow/lsystem_test.cpp)
