set(RAMIFORM_CORE_SOURCES
  src/core/context.cpp
  src/core/errors.cpp
  src/core/nnls.cpp
  src/core/numbers.cpp
  src/core/parallel.cpp
  src/core/random.cpp
  src/core/roots.cpp)
