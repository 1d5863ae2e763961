# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# `cmake --install` puts the headers, the stage libraries, ramiform/version.h and
# ramiformConfig.cmake (+ its version file) under the prefix, so that another project can
#   find_package(ramiform 0.1 REQUIRED)
#   target_link_libraries(app PRIVATE ramiform::ramiform)
# Header-only dependencies used inside the library (nanoflann, nlohmann_json) are not needed by
# users; the compiled ones (oneTBB, Highway) are found again by the config file because the
# stages are static libraries. Eigen is public: Vec3 and Aabb are Eigen types.

include(CMakePackageConfigHelpers)

configure_file(${PROJECT_SOURCE_DIR}/cmake/version.h.in
               ${RAMIFORM_GENERATED_INCLUDE}/ramiform/version.h @ONLY)

set(RAMIFORM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/ramiform)

install(TARGETS ${RAMIFORM_STAGE_TARGETS} ramiform_lib EXPORT ramiformTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/ramiform ${RAMIFORM_GENERATED_INCLUDE}/ramiform
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(EXPORT ramiformTargets NAMESPACE ramiform:: DESTINATION ${RAMIFORM_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ramiformConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/ramiformConfig.cmake
                              INSTALL_DESTINATION ${RAMIFORM_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ramiformConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ramiformConfig.cmake
              ${PROJECT_BINARY_DIR}/ramiformConfigVersion.cmake
        DESTINATION ${RAMIFORM_INSTALL_CMAKEDIR})
