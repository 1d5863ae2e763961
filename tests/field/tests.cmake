set(RAMIFORM_field_TESTS
  field/kernels_test.cpp
  field/cauchy_integral_test.cpp
  field/skeleton_field_test.cpp
  field/operators_test.cpp
  field/radius_fit_test.cpp)
