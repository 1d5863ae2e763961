set(RAMIFORM_LINES_SOURCES
  src/lines/camera.cpp)
