set(RAMIFORM_field_TESTS
  field/field_context_test.cpp
  field/kernels_test.cpp
  field/cauchy_integral_test.cpp
  field/skeleton_field_test.cpp
  field/operators_test.cpp
  field/radius_fit_test.cpp
  field/primitives_test.cpp
  field/warps_test.cpp
  field/rbf_test.cpp
  field/curves_test.cpp
  field/sweep_test.cpp
  field/sweep_region_test.cpp
  field/sweep_interpolation_test.cpp
  field/simd_targets_test.cpp)
# The sweep surfaces' 2-D distance and interpolation are internal (src/field/); their tests
# reach them directly.
set_source_files_properties(field/sweep_region_test.cpp field/sweep_interpolation_test.cpp
                            PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/src)
# The SIMD-target test forces Highway targets (hwy/targets.h; libhwy comes with the field
# library) and asks the internal kernels (src/field/skeleton_field_simd.h) which one they
# dispatch to.
set_source_files_properties(field/simd_targets_test.cpp
                            PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/src)
