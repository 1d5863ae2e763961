set(RAMIFORM_cli_TESTS cli/cli_test.cpp cli/convert_test.cpp cli/readme_example_test.cpp
  cli/mesh_tets_test.cpp cli/script_cli_test.cpp cli/pipeline_cli_test.cpp cli/help_docs_test.cpp
  cli/hostile_inputs_test.cpp cli/kill_safety_test.cpp)
