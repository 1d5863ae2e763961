set(RAMIFORM_mesh_TESTS
  mesh/checks_test.cpp
  mesh/cleanup_test.cpp
  mesh/deviation_test.cpp
  mesh/winding_test.cpp
  mesh/mesh_field_test.cpp)
