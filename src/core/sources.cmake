set(RAMIFORM_CORE_SOURCES
  src/core/context.cpp
  src/core/errors.cpp
  src/core/parallel.cpp
  src/core/random.cpp)
