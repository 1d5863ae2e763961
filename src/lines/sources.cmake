set(RAMIFORM_LINES_SOURCES
  src/lines/camera.cpp
  src/lines/draw.cpp
  src/lines/options.cpp
  src/lines/visibility.cpp)
