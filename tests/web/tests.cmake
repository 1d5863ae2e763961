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

# The studio page (web/studio, docs/studio.md) driven in headless Chromium against the real
# `ramiform studio`: run, param slider, line mode, error marker, sketch, cancel. Skips (exit 77)
# without node, web/studio/node_modules, Chromium or the built page.
if(NOT RAMIFORM_SANITIZE AND NOT RAMIFORM_TSAN)
  add_test(NAME studio_e2e
           COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/studio_e2e.sh $<TARGET_FILE:ramiform>
                   ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/test-tmp/studio_e2e)
  set_tests_properties(studio_e2e PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
endif()
# The page's browser-free logic (slider ranges, sketch → script text): node --test, no packages.
add_test(NAME studio_page_logic
         COMMAND bash -c "command -v node >/dev/null 2>&1 || { echo 'SKIP: node is not installed (Debian: nodejs)'; exit 77; }; exec node --test \"$1\"" studio_page_logic
                 ${PROJECT_SOURCE_DIR}/web/studio/test/page_logic.test.mjs)
set_tests_properties(studio_page_logic PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 60)
