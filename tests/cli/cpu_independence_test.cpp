// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Outputs do not depend on the C library's choice of math routines (issue 15). glibc picks FMA
// variants of exp, log, pow, sin, cos, atan, ... on CPUs that have FMA; with them, 13 of the 43
// outputs of tools/output_hashes.sh used to differ from a run on a CPU without FMA. The library
// now uses its own functions (core/portable_math.h). Here the same commands run twice, once as
// they are and once with glibc told to ignore FMA and AVX2 (GLIBC_TUNABLES, as on an older CPU),
// and the files must be byte-identical. (On a CPU without FMA both runs are the same run.)

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "cli/cli_run.h"

namespace ramiform::test {
namespace {

class CpuIndependence : public CliDirTest {};

TEST_F(CpuIndependence, OutputsDoNotDependOnTheMathLibraryVariant) {
  const std::string examples = std::string(RAMIFORM_SOURCE_DIR) + "/examples";
  struct Job {
    std::string args;  // with OUT for the output's directory
    std::vector<std::string> outputs;
  };
  const std::vector<Job> jobs = {
      {"generate OUT/tree.json --segments 120 --seed 5", {"tree.json"}},
      {"mesh OUT/tree.json -o OUT/tets.ply --levels 1", {"tets.ply"}},
      {"mesh OUT/tree.json -o OUT/mc.ply --method mc --resolution 48", {"mc.ply"}},
      {"mesh OUT/tree.json -o OUT/dist.ply --surface distance --kernel blinn --levels 0",
       {"dist.ply"}},
      {"lsystem monopodial --iterations 5 -o OUT/plant.json", {"plant.json"}},
      {"run " + examples + "/deformations.rf --out OUT", {"bent_beam.ply", "twisted_column.ply"}},
  };
  auto run_all = [&](const std::string& sub) {
    std::filesystem::create_directories(path(sub));
    for (const Job& job : jobs) {
      std::string args = job.args;
      for (std::size_t at; (at = args.find("OUT")) != std::string::npos;) {
        args.replace(at, 3, path(sub));
      }
      const CliRun r = run_cli(args, 300);
      ASSERT_EQ(r.code, 0) << args << "\n" << r.out;
    }
  };
  run_all("plain");
  ASSERT_EQ(setenv("GLIBC_TUNABLES", "glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4,-AVX512F", 1), 0);
  run_all("no_fma");
  unsetenv("GLIBC_TUNABLES");
  for (const Job& job : jobs) {
    for (const std::string& name : job.outputs) {
      const std::string a = read_file(path("plain/" + name));
      ASSERT_FALSE(a.empty()) << name;
      EXPECT_TRUE(a == read_file(path("no_fma/" + name))) << name << " differs";
    }
  }
}

}  // namespace
}  // namespace ramiform::test
