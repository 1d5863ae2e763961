set(RAMIFORM_MESH_SOURCES
  src/mesh/checks.cpp
  src/mesh/cleanup.cpp
  src/mesh/deviation.cpp
  src/mesh/bark_uv.cpp
  src/mesh/mesh_field.cpp
  src/mesh/surface_points.cpp
  src/mesh/winding.cpp)
