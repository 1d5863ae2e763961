set(RAMIFORM_LINES_SOURCES
  src/lines/camera.cpp
  src/lines/draw.cpp
  src/lines/features.cpp
  src/lines/line_common.cpp
  src/lines/options.cpp
  src/lines/silhouettes.cpp
  src/lines/suggestive.cpp)
