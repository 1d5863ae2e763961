// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Realistic neurons (tests/support/neuron_fixture.h, ~3000 samples, tips of 0.2 um) meshed the
// way users mesh them: `ramiform mesh cell.swc -o cell.ply --fit-radii --stats stats.json`, the
// binary itself. Each soma convention of docs/formats.md ("SWC"), and a file in shuffled order
// with extra roots. The mesh read back must be closed, oriented, one piece per root, hold every
// skeleton node, carry each vertex's SWC type; the fitted radii must be within 2 % (median).

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/cli_run.h"
#include "io/io_test_util.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/swc_io.h"
#include "ramiform/skeleton/skeleton.h"
#include "support/mesh_checkers.h"
#include "support/neuron_fixture.h"

namespace ramiform {
namespace {

using io_test::TempDir;
using test::NeuronFacts;
using test::NeuronOptions;
using test::NeuronSoma;

// ---------------------------------------------------------------------------------------------
// The fixture itself: what a NeuroMorpho-like file looks like.

// The sample lines of SWC text (no comments), split into their seven fields.
std::vector<std::vector<std::string>> sample_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string f; fields >> f;) row.push_back(f);
    rows.push_back(row);
  }
  return rows;
}

TEST(NeuronFixture, IsDeterministicAndSeedDependent) {
  NeuronOptions o;
  const std::string a = test::neuron_swc(o);
  EXPECT_EQ(a, test::neuron_swc(o));
  o.seed = 2;
  EXPECT_NE(a, test::neuron_swc(o));
}

TEST(NeuronFixture, LooksLikeAReconstruction) {
  NeuronFacts facts;
  const std::string text = test::neuron_swc({}, &facts);
  const auto rows = sample_rows(text);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(facts.samples));
  // About the asked number of samples, tips at 0.2 um, the apical trunk the thickest neurite.
  EXPECT_GE(facts.samples, 2700);
  EXPECT_LE(facts.samples, 3300);
  EXPECT_EQ(facts.roots, 1);
  EXPECT_EQ(facts.soma_samples, 1);
  EXPECT_DOUBLE_EQ(facts.min_radius, 0.2);
  EXPECT_DOUBLE_EQ(facts.max_neurite_radius, 1.6);
  std::map<int, int> types;
  std::size_t tips = 0;
  std::map<std::string, int> children;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 7u);
    // x y z radius with exactly two decimals, as real files are rounded to 0.01 um.
    for (int k = 2; k <= 5; ++k) {
      const std::string& f = row[k];
      const std::size_t dot = f.find('.');
      ASSERT_NE(dot, std::string::npos) << f;
      EXPECT_EQ(f.size() - dot - 1, 2u) << f;
    }
    ++types[std::stoi(row[1])];
    ++children[row[6]];
  }
  for (const auto& row : rows) tips += children.count(row[0]) == 0 ? 1 : 0;
  // A soma, an axon (2), basal (3) and apical (4) dendrites and nothing else.
  EXPECT_EQ(types.size(), 4u);
  EXPECT_EQ(types[1], 1);
  EXPECT_GT(types[2], 300);  // the axon and its collaterals
  EXPECT_GT(types[3], 1000);
  EXPECT_GT(types[4], 100);
  // Branching trees: dozens of terminal tips, every branch forking in two.
  EXPECT_GT(tips, 30u);
  // The soma has the six primary dendrites and the axon as children.
  EXPECT_EQ(children["1"], 7);
}

TEST(NeuronFixture, ScalesToTheTargetSize) {
  for (const int dendrites : {4, 6, 8}) {
    for (const int target : {500, 3000, 10000}) {
      NeuronOptions o;
      o.dendrites = dendrites;
      o.target_samples = target;
      NeuronFacts facts;
      (void)test::neuron_swc(o, &facts);
      EXPECT_NEAR(facts.samples, target, 0.1 * target) << target << " samples, " << dendrites;
    }
  }
}

TEST(NeuronFixture, RefusesBadOptions) {
  NeuronOptions o;
  o.dendrites = 0;
  EXPECT_THROW((void)test::neuron_swc(o), std::invalid_argument);
  o = {};
  o.target_samples = 10;
  EXPECT_THROW((void)test::neuron_swc(o), std::invalid_argument);
}

// Each soma convention is read as the kind docs/formats.md names, with the samples and roots
// the fixture wrote; shuffling the lines and adding fragments changes neither.
TEST(NeuronFixture, EachSomaIsReadAsItsKind) {
  const struct {
    NeuronSoma soma;
    SwcSomaKind kind;
    std::size_t samples;
  } cases[] = {{NeuronSoma::kSinglePoint, SwcSomaKind::kSinglePoint, 1},
               {NeuronSoma::kThreePoint, SwcSomaKind::kThreePoint, 3},
               {NeuronSoma::kContour, SwcSomaKind::kContour, 16},
               {NeuronSoma::kCylinders, SwcSomaKind::kCylinders, 7}};
  for (const auto& c : cases) {
    for (const bool shuffle : {false, true}) {
      NeuronOptions o;
      o.soma = c.soma;
      o.shuffle = shuffle;
      o.extra_trees = shuffle ? 2 : 0;
      NeuronFacts facts;
      const std::string text = test::neuron_swc(o, &facts);
      SwcReport report;
      const Skeleton s = parse_swc(text, "neuron.swc", {.report = &report});
      const std::string what =
          std::to_string(static_cast<int>(c.soma)) + (shuffle ? " shuffled" : "");
      EXPECT_EQ(report.samples, static_cast<std::size_t>(facts.samples)) << what;
      EXPECT_EQ(report.roots, static_cast<std::size_t>(facts.roots)) << what;
      EXPECT_EQ(facts.roots, shuffle ? 3 : 1) << what;
      ASSERT_EQ(report.somata.size(), 1u) << what;
      EXPECT_EQ(report.somata[0].kind, c.kind) << what;
      EXPECT_EQ(report.somata[0].samples, c.samples) << what;
      EXPECT_EQ(static_cast<int>(c.samples), facts.soma_samples) << what;
      if (c.kind != SwcSomaKind::kCylinders) {
        EXPECT_NEAR(report.somata[0].radius, 8.0, 0.01) << what;
      }
      EXPECT_EQ(s.node_types.size(), s.nodes.size()) << what;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Meshing through the CLI.

// The `swc_type` column of a binary little-endian PLY whose vertices are `double x y z nx ny nz`
// then `int swc_type` (what `mesh` writes); empty when the header is not that.
std::vector<std::int32_t> ply_swc_types(const std::string& path) {
  const std::string bytes = test::read_file(path);
  const std::size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) return {};
  const std::string header = bytes.substr(0, end);
  const std::string want =
      "property double x\nproperty double y\nproperty double z\nproperty double nx\n"
      "property double ny\nproperty double nz\nproperty int swc_type\nelement face";
  if (header.find("format binary_little_endian 1.0") == std::string::npos ||
      header.find(want) == std::string::npos) {
    return {};
  }
  const std::size_t at = header.find("element vertex ");
  const std::size_t n = std::stoul(header.substr(at + 15));
  const std::size_t stride = 6 * sizeof(double) + sizeof(std::int32_t);
  const std::size_t body = end + std::strlen("end_header\n");
  if (bytes.size() < body + n * stride) return {};
  std::vector<std::int32_t> types(n);
  for (std::size_t v = 0; v < n; ++v) {
    std::memcpy(&types[v], bytes.data() + body + v * stride + 6 * sizeof(double),
                sizeof(std::int32_t));
  }
  return types;
}

struct MeshedNeuron {
  NeuronFacts facts;
  Skeleton skeleton;  // as the mesher got it (soma regions)
  nlohmann::json stats;
  TriMesh mesh;  // read back from the PLY
  std::vector<std::int32_t> swc_types;
  double seconds = 0;
};

// Writes the neuron, runs `ramiform mesh --fit-radii`, reads back what it wrote.
MeshedNeuron mesh_neuron(const NeuronOptions& o) {
  MeshedNeuron m;
  const TempDir dir;
  const std::string swc = (dir.path() / "cell.swc").string();
  const std::string ply = (dir.path() / "cell.ply").string();
  const std::string stats = (dir.path() / "stats.json").string();
  const std::string text = test::neuron_swc(o, &m.facts);
  std::ofstream(swc, std::ios::binary) << text;
  m.skeleton = parse_swc(text, swc);
  const auto t0 = std::chrono::steady_clock::now();
  const test::CliRun run =
      test::run_cli("mesh " + swc + " -o " + ply + " --fit-radii --stats " + stats, 300);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(run.code, 0) << run.out;
  if (run.code != 0) return m;
  m.stats = nlohmann::json::parse(test::read_file(stats));
  m.mesh = read_mesh(ply);
  m.swc_types = ply_swc_types(ply);
  return m;
}

// What every meshed neuron must be; `what` names the case in failures.
void expect_good_neuron_mesh(const MeshedNeuron& m, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_FALSE(m.mesh.triangles.empty());
  const std::size_t roots = static_cast<std::size_t>(m.facts.roots);
  // The file as read back, checked here, not only as --stats says.
  EXPECT_TRUE(test::is_watertight(m.mesh));
  EXPECT_TRUE(test::is_oriented(m.mesh));
  EXPECT_TRUE(test::is_manifold(m.mesh));
  EXPECT_TRUE(test::has_components(m.mesh, roots));
  EXPECT_EQ(test::nodes_outside(m.mesh, m.skeleton), 0u);
  EXPECT_TRUE(m.stats.at("watertight").get<bool>());
  EXPECT_TRUE(m.stats.at("oriented").get<bool>());
  EXPECT_EQ(m.stats.at("components").get<std::size_t>(), roots);
  EXPECT_TRUE(m.stats.at("tolerance_reached").get<bool>());
  EXPECT_TRUE(m.stats.at("fit").at("converged").get<bool>());
  EXPECT_EQ(m.stats.at("triangles").get<std::size_t>(), m.mesh.triangle_count());
  // The requirement: fitted radii within 2 % of the file's (median over the measured rays).
  // Measured (Release, 2 cores): median 0.28-0.33 % for every soma convention, p90 1.9-2.1 %,
  // max 125-190 % at a few rays (docs/neurons.md, "What is weak").
  EXPECT_LE(m.stats.at("radius_error_median").get<double>(), 0.02);
  // Every vertex labelled with a type of the file, and each of soma, axon, basal and apical
  // dendrite labels part of the surface.
  ASSERT_EQ(m.swc_types.size(), m.mesh.positions.size());
  std::map<int, std::size_t> count;
  for (const std::int32_t t : m.swc_types) ++count[t];
  EXPECT_EQ(count.size(), 4u);
  for (const int t : {1, 2, 3, 4}) EXPECT_GT(count[t], 100u) << "swc_type " << t;
  std::cout << "[ neuron   ] " << what << ": " << m.facts.samples << " samples, "
            << m.mesh.triangle_count() << " triangles, radius error median "
            << m.stats.at("radius_error_median").get<double>() << " p90 "
            << m.stats.at("radius_error_p90").get<double>() << " max "
            << m.stats.at("radius_error_max").get<double>() << ", " << m.seconds << " s\n";
}

TEST(NeuronMesh, SinglePointSoma) {
  NeuronOptions o;
  o.soma = NeuronSoma::kSinglePoint;
  o.dendrites = 6;
  expect_good_neuron_mesh(mesh_neuron(o), "single-point soma, 6 dendrites");
}

TEST(NeuronMesh, ThreePointSoma) {
  NeuronOptions o;
  o.soma = NeuronSoma::kThreePoint;
  o.dendrites = 4;
  o.seed = 3;
  expect_good_neuron_mesh(mesh_neuron(o), "three-point soma, 4 dendrites");
}

TEST(NeuronMesh, ContourSoma) {
  NeuronOptions o;
  o.soma = NeuronSoma::kContour;
  o.dendrites = 8;
  o.seed = 4;
  expect_good_neuron_mesh(mesh_neuron(o), "contour soma, 8 dendrites");
}

TEST(NeuronMesh, CylinderStackSoma) {
  NeuronOptions o;
  o.soma = NeuronSoma::kCylinders;
  o.dendrites = 5;
  o.seed = 5;
  expect_good_neuron_mesh(mesh_neuron(o), "cylinder-stack soma, 5 dendrites");
}

// Lines in random order and two unconnected fragments: three roots, three pieces.
TEST(NeuronMesh, ShuffledWithExtraRoots) {
  NeuronOptions o;
  o.soma = NeuronSoma::kThreePoint;
  o.shuffle = true;
  o.extra_trees = 2;
  o.seed = 6;
  const MeshedNeuron m = mesh_neuron(o);
  ASSERT_EQ(m.facts.roots, 3);
  expect_good_neuron_mesh(m, "three-point soma, shuffled, 2 extra roots");
}

}  // namespace
}  // namespace ramiform
