set(RAMIFORM_particles_TESTS
  particles/surface_particles_test.cpp
  particles/regenerate_test.cpp)
