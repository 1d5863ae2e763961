set(RAMIFORM_TEST_SUPPORT_SOURCES
  support/fixtures.cpp
  support/glb_reader.cpp
  support/mesh_checkers.cpp
  support/neuron_fixture.cpp)
