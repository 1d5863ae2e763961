// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Every script in examples/ runs and every mesh it writes is watertight; every ```rf example
// of docs/language.md runs.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "ramiform/core/errors.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/script/script.h"
#include "support/fixtures.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = RAMIFORM_SOURCE_DIR;

std::vector<fs::path> example_scripts() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(kSource / "examples")) {
    if (e.path().extension() == ".rf") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

class ExampleScript : public ::testing::TestWithParam<std::string> {};

// A grown or loaded skeleton: one tree (connected, edges = nodes - 1); with pipe-model radii
// (exponent 2.5, the default of grow) every fork satisfies r^n = sum r_child^n.
void expect_tree(const fs::path& path, bool pipe_model) {
  const Skeleton s = read_skeleton(path.string());
  EXPECT_EQ(connected_components(s).count, 1u) << path;
  EXPECT_EQ(s.edge_count() + 1, s.node_count()) << path;
  if (!pipe_model) return;
  std::vector<std::vector<std::uint32_t>> adjacent(s.node_count());
  for (const auto& e : s.edges) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  std::vector<int> parent(s.node_count(), -2);
  std::vector<std::uint32_t> order = {0};
  parent[0] = -1;
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (std::uint32_t w : adjacent[order[i]]) {
      if (parent[w] == -2) {
        parent[w] = static_cast<int>(order[i]);
        order.push_back(w);
      }
    }
  }
  std::size_t forks = 0;
  for (std::uint32_t v = 0; v < s.node_count(); ++v) {
    double sum = 0;
    std::size_t children = 0;
    for (std::uint32_t w : adjacent[v]) {
      if (parent[w] == static_cast<int>(v)) {
        sum += std::pow(s.nodes[w].radius, 2.5);
        ++children;
      }
    }
    if (children == 0) continue;
    forks += children > 1 ? 1 : 0;
    EXPECT_NEAR(std::pow(s.nodes[v].radius, 2.5), sum, 1e-9 * sum) << path << " node " << v;
  }
  EXPECT_GT(forks, 0u) << path;
}

TEST_P(ExampleScript, RunsAndWritesOnlyWatertightMeshes) {
  const fs::path script = kSource / "examples" / GetParam();
  const fs::path out = temp_dir("example-" + script.stem().string());
  ScriptOptions options;
  options.out_dir = out.string();
  const auto results = run_script(script.string(), options);
  std::size_t meshes = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string ext = e.path().extension().string();
    ASSERT_NE(e.path().filename().string().rfind(".rf-staged", 0), 0u)
        << "left staged: " << e.path();
    if (ext == ".json") {
      expect_tree(e.path(), GetParam() != "fork.rf");
      continue;
    }
    if (ext == ".txt") {
      EXPECT_GT(read_points(e.path().string()).size(), 0u) << e.path();
      continue;
    }
    if (ext == ".svg") {  // a line drawing (docs/drawing.md): an SVG with its stroke groups
      std::ifstream in(e.path());
      const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(text.find("<svg"), std::string::npos) << e.path();
      EXPECT_NE(text.find("<g id=\"silhouette\""), std::string::npos) << e.path();
      EXPECT_NE(text.find("<path"), std::string::npos) << e.path();
      continue;
    }
    if (ext == ".glb") {
      std::ifstream in(e.path(), std::ios::binary);
      std::string magic(4, '\0');
      in.read(magic.data(), 4);
      EXPECT_EQ(magic, "glTF") << e.path();
      continue;
    }
    ASSERT_TRUE(ext == ".ply" || ext == ".obj" || ext == ".off") << e.path();
    const TriMesh mesh = read_mesh(e.path().string());
    const MeshReport r = check_mesh(mesh);
    EXPECT_TRUE(r.watertight) << e.path() << ": " << r.boundary_edges << " boundary edges";
    EXPECT_TRUE(r.oriented) << e.path();
    EXPECT_TRUE(r.manifold) << e.path();
    EXPECT_EQ(r.components, 1u) << e.path();
    EXPECT_GT(signed_volume(mesh), 0.0) << e.path();
    ++meshes;
  }
  EXPECT_GT(meshes, 0u) << "an example should write at least one mesh";
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(Examples, ExampleScript, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const fs::path& p : example_scripts())
                             names.push_back(p.filename().string());
                           return names;
                         }()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = fs::path(info.param).stem().string();
                           for (char& c : n) {
                             if (std::isalnum(static_cast<unsigned char>(c)) == 0) c = '_';
                           }
                           return n;
                         });

TEST(LanguageDoc, EveryExampleBlockRuns) {
  std::ifstream in(kSource / "docs" / "language.md");
  ASSERT_TRUE(in) << "docs/language.md is missing";
  std::string line;
  std::string block;
  bool inside = false;
  std::size_t block_line = 0;
  std::size_t line_no = 0;
  int blocks = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!inside && line.rfind("```rf", 0) == 0) {
      inside = true;
      block.clear();
      block_line = line_no + 1;
      continue;
    }
    if (inside && line.rfind("```", 0) == 0) {
      inside = false;
      ++blocks;
      const fs::path out = temp_dir("language-doc-" + std::to_string(blocks));
      ScriptOptions options;
      options.out_dir = out.string();
      options.input_dir = (kSource / "examples").string();
      ScriptSession session(options);
      // A block that shows an error says so on its first line: "# error: WORDS".
      const std::string expect_error =
          block.rfind("# error: ", 0) == 0 ? block.substr(9, block.find('\n') - 9) : std::string();
      try {
        session.run_text(block, "docs/language.md:" + std::to_string(block_line));
        EXPECT_TRUE(expect_error.empty())
            << "block at line " << block_line << " should fail with: " << expect_error;
      } catch (const InputError& e) {
        EXPECT_FALSE(expect_error.empty()) << "block at line " << block_line << ": " << e.what();
        if (!expect_error.empty()) {
          EXPECT_NE(std::string(e.what()).find(expect_error), std::string::npos) << e.what();
        }
      }
      session.discard();
      fs::remove_all(out);
      continue;
    }
    if (inside) block += line + "\n";
  }
  EXPECT_FALSE(inside) << "unterminated code block";
  EXPECT_GE(blocks, 20) << "every command should have an example";
}

}  // namespace
}  // namespace ramiform::test

namespace ramiform::test {
namespace {

// Every command has a heading in docs/language.md and is used in at least one of its example
// blocks (which EveryExampleBlockRuns runs).
TEST(LanguageDoc, EveryCommandHasAHeadingAndAnExample) {
  std::ifstream in(kSource / "docs" / "language.md");
  ASSERT_TRUE(in);
  std::set<std::string> headed;
  std::set<std::string> used;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      inside = !inside && line.rfind("```rf", 0) == 0;
      continue;
    }
    if (inside) {
      std::istringstream words(line);
      std::string first;
      if (words >> first) used.insert(first);
    } else if (line.rfind("### ", 0) == 0) {
      std::istringstream words(line.substr(4));
      std::string w;
      while (words >> w) {
        while (!w.empty() && (w.back() == ',' || w.back() == '`')) w.pop_back();
        headed.insert(w);
      }
    }
  }
  for (const std::string& name : ScriptSession::command_names()) {
    EXPECT_TRUE(headed.count(name) == 1) << "docs/language.md has no heading for " << name;
    EXPECT_TRUE(used.count(name) == 1) << "docs/language.md has no example using " << name;
  }
}

}  // namespace
}  // namespace ramiform::test
