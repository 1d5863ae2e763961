// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors

// Writes the marching-cubes tables to stdout, or to the file named by the first argument:
//   gen_mc_tables src/polygonize/mc_tables.inc
#include <exception>
#include <fstream>
#include <iostream>

#include "mc_table_generator.h"

int main(int argc, char** argv) {
  try {
    const std::string text =
        ramiform::mc_gen::format_mc_tables(ramiform::mc_gen::generate_mc_tables());
    if (argc < 2) {
      std::cout << text;
      return 0;
    }
    std::ofstream out(argv[1], std::ios::binary);
    out << text;
    if (!out) {
      std::cerr << "gen_mc_tables: cannot write " << argv[1] << "\n";
      return 3;
    }
  } catch (const std::exception& e) {
    std::cerr << "gen_mc_tables: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
