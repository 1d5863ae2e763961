set(RAMIFORM_mesh_TESTS
  mesh/bark_uv_test.cpp
  mesh/checks_test.cpp
  mesh/cleanup_test.cpp
  mesh/deviation_test.cpp
  mesh/normals_test.cpp
  mesh/winding_test.cpp
  mesh/mesh_field_test.cpp)
