set(RAMIFORM_PARTICLES_SOURCES
  src/particles/particle_cells.cpp
  src/particles/particle_common.cpp
  src/particles/surface_particles.cpp)
