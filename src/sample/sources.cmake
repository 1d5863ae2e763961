set(RAMIFORM_SAMPLE_SOURCES
  src/sample/point_sets.cpp
  src/sample/props.cpp)
