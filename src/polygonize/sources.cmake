set(RAMIFORM_POLYGONIZE_SOURCES
  src/polygonize/marching_cubes.cpp)
