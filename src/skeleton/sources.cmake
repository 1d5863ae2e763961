set(RAMIFORM_SKELETON_SOURCES
  src/skeleton/from_points.cpp
  src/skeleton/generate.cpp
  src/skeleton/skeleton.cpp)
