# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# cmake -DCXX=... -DSTAGE_INCLUDE=<build>/stage-include -DEIGEN_INCLUDE=... -DWORK_DIR=... -P this
#
# The build enforces the layering: compiled with the field stage's include path, a file that
# includes field's and skeleton's headers (public and internal) compiles, and one that reaches up
# into io/ (public or internal) does not, because those headers are not on the path at all.
file(MAKE_DIRECTORY ${WORK_DIR})
set(flags -std=c++20 -fsyntax-only -I${STAGE_INCLUDE}/field/public -I${STAGE_INCLUDE}/field/private)
foreach(dir ${EIGEN_INCLUDE})
  list(APPEND flags -isystem ${dir})
endforeach()

function(compile name text expect_ok)
  file(WRITE ${WORK_DIR}/${name}.cpp "${text}")
  execute_process(COMMAND ${CXX} ${flags} ${WORK_DIR}/${name}.cpp RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(expect_ok AND NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: an allowed include did not compile:\n${err}")
  endif()
  if(NOT expect_ok)
    if(rc EQUAL 0)
      message(FATAL_ERROR "${name}: a backward include compiled; the stage include path leaks")
    endif()
    if(NOT err MATCHES "No such file or directory")
      message(FATAL_ERROR "${name}: failed for another reason than the missing header:\n${err}")
    endif()
  endif()
endfunction()

compile(allowed "#include \"ramiform/field/field.h\"\n#include \"ramiform/skeleton/skeleton.h\"\n#include \"field/bvh.h\"\nint main() {}\n" TRUE)
compile(backward_public "#include \"ramiform/field/field.h\"\n#include \"ramiform/io/mesh_io.h\"\nint main() {}\n" FALSE)
compile(backward_internal "#include \"io/text_scan.h\"\nint main() {}\n" FALSE)
compile(backward_polygonize "#include \"ramiform/polygonize/tetrahedral.h\"\nint main() {}\n" FALSE)
file(REMOVE_RECURSE ${WORK_DIR})
message(STATUS "backward includes do not build: 4 passed, 0 failed")
