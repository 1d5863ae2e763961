set(RAMIFORM_polygonize_TESTS
  polygonize/mc_tables_test.cpp
  polygonize/marching_cubes_test.cpp
  polygonize/marching_cubes_skeleton_test.cpp
  polygonize/tetrahedral_test.cpp
  polygonize/refine_test.cpp
  polygonize/improve_test.cpp
  polygonize/lod_test.cpp
  polygonize/coarsen_test.cpp
  polygonize/delaunay_test.cpp
  polygonize/edge_roots_test.cpp
  polygonize/particle_layout_test.cpp
  polygonize/particle_merge_test.cpp
  polygonize/particles_test.cpp
  polygonize/memory_budget_test.cpp)

# The generator of src/polygonize/mc_tables.inc (header-only logic in tools/mc_table_generator.h,
# which mc_tables_test.cpp also uses). Regenerate with:
#   build/ramiform_gen_mc_tables src/polygonize/mc_tables.inc
if(NOT TARGET ramiform_gen_mc_tables)
  add_executable(ramiform_gen_mc_tables ${PROJECT_SOURCE_DIR}/tools/gen_mc_tables.cpp)
  target_link_libraries(ramiform_gen_mc_tables PRIVATE ramiform_flags)
  set_target_properties(ramiform_gen_mc_tables PROPERTIES
    RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})
endif()
