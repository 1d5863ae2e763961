set(RAMIFORM_script_TESTS script/script_test.cpp script/examples_test.cpp
                          script/hostile_scripts_test.cpp script/equipotential_test.cpp
                          script/skeletal_commands_test.cpp script/points_commands_test.cpp)
