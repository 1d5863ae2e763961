# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# .glb output as users see it (docs/viewing.md): the Khronos glTF validator, and three.js in
# headless Chromium, over files made by the CLI. The tools are in tools/web (npm ci); without
# node, tools/web/node_modules or /usr/bin/chromium the tests skip (exit 77) and say what is
# missing. Not in sanitizer builds: they check what the files hold, not how the program ran,
# and would only add minutes to `make sanitize`.
if(NOT RAMIFORM_SANITIZE AND NOT RAMIFORM_TSAN)
  foreach(test gltf_validator gltf_render_upright)
    add_test(NAME ${test}
             COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/${test}.sh $<TARGET_FILE:ramiform>
                     ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/test-tmp/${test})
    set_tests_properties(${test} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)
  endforeach()
endif()
