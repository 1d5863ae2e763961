set(RAMIFORM_POLYGONIZE_SOURCES
  src/polygonize/marching_cubes.cpp)
list(APPEND RAMIFORM_POLYGONIZE_SOURCES
  src/polygonize/coarsen.cpp
  src/polygonize/delaunay.cpp
  src/polygonize/edge_roots.cpp
  src/polygonize/improve.cpp
  src/polygonize/lod.cpp
  src/polygonize/refine.cpp
  src/polygonize/tetrahedral.cpp
  src/polygonize/tetrahedral_checks.cpp
  src/polygonize/tetrahedral_cleanup.cpp
  src/polygonize/tetrahedral_extract.cpp
  src/polygonize/tetrahedral_lattice.cpp
  src/polygonize/tetrahedral_mesh.cpp
  src/polygonize/tetrahedral_points.cpp
  src/polygonize/tetrahedral_region.cpp)
