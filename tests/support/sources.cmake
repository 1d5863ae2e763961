set(RAMIFORM_TEST_SUPPORT_SOURCES
  support/fixtures.cpp
  support/mesh_checkers.cpp)
