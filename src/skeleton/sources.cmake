set(RAMIFORM_SKELETON_SOURCES
  src/skeleton/skeleton.cpp)
