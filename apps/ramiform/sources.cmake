# The CLI's shared parts (also linked by the Python module, python/): meshing a skeleton as
# `mesh` does, the check figures, the common options.
set(RAMIFORM_CLI_CORE_SOURCES
  common.cpp
  mesh_job.cpp
  reconstruct_job.cpp
  cmd_mesh.cpp)
set(RAMIFORM_APP_SOURCES
  main.cpp
  cmd_check.cpp
  cmd_convert.cpp
  cmd_demo.cpp
  cmd_eval.cpp
  cmd_generate.cpp
  cmd_script.cpp
  cmd_grow.cpp
  cmd_draw.cpp
  cmd_points.cpp
  cmd_studio.cpp
  surface_input.cpp)
# `ramiform studio`'s server (also linked by tests/studio).
set(RAMIFORM_STUDIO_SOURCES
  studio/line_views.cpp
  studio/runs.cpp
  studio/server.cpp
  studio/util.cpp)
