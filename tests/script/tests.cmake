set(RAMIFORM_script_TESTS script/script_test.cpp script/examples_test.cpp
                          script/hostile_scripts_test.cpp)
# The hostile-script test looks into a session's objects (src/script/session.h) to read the
# evaluation counters of its fields.
set_source_files_properties(script/hostile_scripts_test.cpp PROPERTIES INCLUDE_DIRECTORIES
                            ${PROJECT_SOURCE_DIR}/src)
