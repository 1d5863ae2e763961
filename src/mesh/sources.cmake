set(RAMIFORM_MESH_SOURCES
  src/mesh/checks.cpp
  src/mesh/cleanup.cpp
  src/mesh/mesh_field.cpp
  src/mesh/winding.cpp)
