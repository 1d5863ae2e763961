set(RAMIFORM_APP_SOURCES
  main.cpp
  common.cpp
  mesh_job.cpp
  cmd_check.cpp
  cmd_demo.cpp
  cmd_eval.cpp
  cmd_mesh.cpp)
