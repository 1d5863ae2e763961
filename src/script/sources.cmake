set(RAMIFORM_SCRIPT_SOURCES
  src/script/session.cpp
  src/script/commands_shapes.cpp
  src/script/commands_curves.cpp
  src/script/commands_skeletal.cpp
  src/script/commands_output.cpp
  src/script/commands_growth.cpp
  src/script/commands_points.cpp)
