set(RAMIFORM_IO_SOURCES
  src/io/atomic_file.cpp
  src/io/mesh_io.cpp
  src/io/obj_format.cpp
  src/io/ply_format.cpp
  src/io/points_io.cpp
  src/io/skeleton_io.cpp
  src/io/text_scan.cpp)
