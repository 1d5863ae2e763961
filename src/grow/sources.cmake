set(RAMIFORM_GROW_SOURCES
  src/grow/space_colonization.cpp
  src/grow/lsystem.cpp)
