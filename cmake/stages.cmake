# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# ramiform_stage(NAME [STAGES lower stages...])
#
# Adds the static library ramiform_NAME from src/NAME/sources.cmake (RAMIFORM_<NAME>_SOURCES).
# It links the listed lower stages publicly (what a stage uses inside is linked privately by
# the caller). Its include path is a directory
# of links made at configure time, build/stage-include/NAME/, holding
#   ramiform/<stage> -> include/ramiform/<stage>   (public headers)
#   <stage>          -> src/<stage>                (internal headers, private)
# for NAME and its STAGES only, so a stage that includes a header of a stage it may not use
# fails to compile. The generated headers (ramiform/version.h) are visible to every stage.

include(GNUInstallDirs)

# ramiform_read_stages(FILE): reads the table between <!-- stages:begin --> and
# <!-- stages:end --> in FILE (rows "| stage | lower, stages |") and sets RAMIFORM_STAGES (in
# table order, bottom up) and RAMIFORM_STAGE_<stage>_MAY_INCLUDE. A stage may include only
# stages listed above it.
macro(ramiform_read_stages file)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${file})
  file(STRINGS ${file} _ramiform_lines)
  set(RAMIFORM_STAGES "")
  set(_ramiform_in_table FALSE)
  foreach(_line IN LISTS _ramiform_lines)
    if(_line MATCHES "<!-- stages:begin -->")
      set(_ramiform_in_table TRUE)
    elseif(_line MATCHES "<!-- stages:end -->")
      set(_ramiform_in_table FALSE)
    elseif(_ramiform_in_table AND _line MATCHES "^\\| *([a-z_]+) *\\|([a-z_, ]*)\\| *$")
      set(_stage ${CMAKE_MATCH_1})
      string(REGEX REPLACE "[ ,]+" ";" _lower "${CMAKE_MATCH_2}")
      list(REMOVE_ITEM _lower "")
      if(NOT _stage STREQUAL "stage")
        foreach(_dep IN LISTS _lower)
          if(NOT _dep IN_LIST RAMIFORM_STAGES)
            message(FATAL_ERROR "${file}: stage '${_stage}' may include '${_dep}', which is not a "
                                "stage listed above it")
          endif()
        endforeach()
        list(APPEND RAMIFORM_STAGES ${_stage})
        set(RAMIFORM_STAGE_${_stage}_MAY_INCLUDE ${_lower})
      endif()
    endif()
  endforeach()
  if(NOT RAMIFORM_STAGES)
    message(FATAL_ERROR "${file}: no stage table between <!-- stages:begin --> and <!-- stages:end -->")
  endif()
endmacro()

set(RAMIFORM_GENERATED_INCLUDE ${PROJECT_BINARY_DIR}/generated/include)
set(RAMIFORM_STAGE_TARGETS "")

function(ramiform_stage name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "STAGES")
  string(TOUPPER ${name} upper)
  include(${PROJECT_SOURCE_DIR}/src/${name}/sources.cmake)
  set(public_dir ${PROJECT_BINARY_DIR}/stage-include/${name}/public)
  set(private_dir ${PROJECT_BINARY_DIR}/stage-include/${name}/private)
  file(REMOVE_RECURSE ${PROJECT_BINARY_DIR}/stage-include/${name})
  file(MAKE_DIRECTORY ${public_dir}/ramiform ${private_dir})
  foreach(stage ${name} ${arg_STAGES})
    if(EXISTS ${PROJECT_SOURCE_DIR}/include/ramiform/${stage})
      file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/ramiform/${stage} ${public_dir}/ramiform/${stage}
           SYMBOLIC)
    endif()
    if(EXISTS ${PROJECT_SOURCE_DIR}/src/${stage})
      file(CREATE_LINK ${PROJECT_SOURCE_DIR}/src/${stage} ${private_dir}/${stage} SYMBOLIC)
    endif()
  endforeach()

  add_library(ramiform_${name} STATIC ${RAMIFORM_${upper}_SOURCES})
  add_library(ramiform::ramiform_${name} ALIAS ramiform_${name})
  set_target_properties(ramiform_${name} PROPERTIES
    OUTPUT_NAME ramiform_${name} EXPORT_NAME ramiform_${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(ramiform_${name}
    PUBLIC $<BUILD_INTERFACE:${public_dir}> $<BUILD_INTERFACE:${RAMIFORM_GENERATED_INCLUDE}>
           $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${private_dir})
  set(lower "")
  foreach(stage ${arg_STAGES})
    list(APPEND lower ramiform_${stage})
  endforeach()
  target_link_libraries(ramiform_${name} PUBLIC ${lower} PRIVATE $<BUILD_INTERFACE:ramiform_flags>)
  if(name STREQUAL "core")
    target_link_libraries(ramiform_${name} PUBLIC Eigen3::Eigen)
  endif()
  if(RAMIFORM_SANITIZE)
    target_link_options(ramiform_${name} PUBLIC $<BUILD_INTERFACE:-fsanitize=address,undefined>)
  endif()
  set(RAMIFORM_STAGE_TARGETS ${RAMIFORM_STAGE_TARGETS} ramiform_${name} PARENT_SCOPE)
endfunction()
