set(RAMIFORM_cli_TESTS cli/cli_test.cpp cli/convert_test.cpp cli/readme_example_test.cpp
  cli/mesh_tets_test.cpp cli/script_cli_test.cpp cli/pipeline_cli_test.cpp cli/help_docs_test.cpp
  cli/hostile_inputs_test.cpp cli/kill_safety_test.cpp cli/malformed_files_test.cpp
  cli/cpu_independence_test.cpp cli/mesh_output_test.cpp cli/mesh_particles_test.cpp
  cli/eval_distance_test.cpp cli/reconstruct_cli_test.cpp cli/draw_cli_test.cpp
  cli/tree_reconstruct_test.cpp)
# The malformed-files test writes the table of docs/reliability.md into the build directory.
set_source_files_properties(cli/malformed_files_test.cpp PROPERTIES
  COMPILE_DEFINITIONS RAMIFORM_BUILD_DIR="${CMAKE_BINARY_DIR}")
