set(RAMIFORM_GROW_SOURCES
  src/grow/space_colonization.cpp
  src/grow/branch_cleanup.cpp
  src/grow/lsystem.cpp)
