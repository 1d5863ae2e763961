set(RAMIFORM_POLYGONIZE_SOURCES
  src/polygonize/marching_cubes.cpp)
list(APPEND RAMIFORM_POLYGONIZE_SOURCES
  src/polygonize/delaunay.cpp
  src/polygonize/edge_roots.cpp
  src/polygonize/tetrahedral.cpp)
