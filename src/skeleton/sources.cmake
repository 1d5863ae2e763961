set(RAMIFORM_SKELETON_SOURCES
  src/skeleton/generate.cpp
  src/skeleton/skeleton.cpp)
