set(RAMIFORM_FIELD_SOURCES
  src/field/field.cpp
  src/field/kernels.cpp
  src/field/bvh.cpp
  src/field/operators.cpp
  src/field/skeleton_field.cpp
  src/field/skeleton_field_simd.cpp
  src/field/radius_fit.cpp)
