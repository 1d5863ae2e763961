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
  field/mpu_test.cpp
  field/point_normals_test.cpp
  field/equipotential_test.cpp
  field/curves_test.cpp
  field/surface_skeleton_test.cpp
  field/bezier_curve_test.cpp
  field/anisotropic_test.cpp
  field/sweep_test.cpp
  field/sweep_region_test.cpp
  field/sweep_interpolation_test.cpp
  field/simd_targets_test.cpp
  field/bvh_test.cpp)
# The SIMD-target test forces Highway targets (hwy/targets.h; libhwy comes with the field
# library) and asks the internal kernels (src/field/skeleton_field_simd.h) which one they
# dispatch to. Internal headers are reachable from every test program (tests/CMakeLists.txt).
