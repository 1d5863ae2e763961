// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// One source of truth for defaults and ranges: the library's options structs. For every option
// the CLI or the scene language takes from an options struct, `ramiform CMD --help`, the scene
// language's `help CMD`, docs/cli.md and docs/language.md must state the struct's default (and
// range, where the struct has bounds), and the CLI and the scene language must behave as if
// given the struct's default.
//
// How a stated value is found (the convention the docs follow, stable on purpose):
//   - the text is the option's line of --help, the command's `help` text, or the command's
//     section of a page: docs/cli.md from the heading "## `ramiform CMD" to the next "## ",
//     docs/language.md from "### CMD" to the next "### " or "## " (line breaks read as spaces);
//   - after the first mention of the option (`--flag` in --help and docs/cli.md, the key in
//     backquotes, `key`, in `help` and docs/language.md), the first "(default D)" or
//     "(default D, MIN–MAX)" (an en dash; a remark may follow after "; ") within kNear
//     characters is what the text states.

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "cli/cli_run.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/field/mpu.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/grow/space_colonization.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/script/script.h"
#include "ramiform/skeleton/from_points.h"
#include "ramiform/skeleton/generate.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kNear = 400;  // characters between a mention and its "(default"
constexpr const char* kDash = "\u2013";

/// A default and, when the struct bounds it, its range.
struct Value {
  double value = 0;
  std::optional<double> min, max;
};

/// One option with the struct values it must state. An empty flag or key: not on that side.
struct OptionCase {
  std::string cli_command;     // `ramiform CLI_COMMAND --help` and "## `ramiform CLI_COMMAND"
  std::string flag;            // "--levels"
  std::string script_command;  // `help SCRIPT_COMMAND` and "### SCRIPT_COMMAND"
  std::string key;             // "levels"
  Value expected;
  bool default_is_the_structs = true;  // false: the command's own default, the range only
};

Value def(double v) { return {v, std::nullopt, std::nullopt}; }
Value def(double v, double min, double max) { return {v, min, max}; }

std::vector<OptionCase> cases() {
  using Mc = MarchingCubesOptions;
  using Tets = TetrahedralOptions;
  using Tree = BranchingTreeOptions;
  using Grow = ColonizationOptions;
  using LSys = LSystemOptions;
  const Mc mc;
  const Tets tets;
  const Tree tree;
  const Grow grow;
  const LSys ls;
  const ScriptOptions script;
  using Tol = ToleranceOptions;
  const Tol tol;
  // The levels of the base mesh that `mesh` and `save_mesh` refine to the tolerance.
  const Value levels = def(tol.tets.levels, Tets::kMinLevels, Tets::kMaxLevels);
  const Value tolerance = def(tol.tolerance, Tol::kMinTolerance, Tol::kMaxTolerance);
  const Value scale = def(tets.section_scale, Tets::kMinSectionScale, Tets::kMaxSectionScale);
  const Value resolution = def(mc.resolution, Mc::kMinResolution, Mc::kMaxResolution);
  const Value grow_exponent =
      def(grow.pipe_exponent, Grow::kMinPipeExponent, Grow::kMaxPipeExponent);
  const MpuOptions mpu;
  const TreeFromPointsOptions tfp;
  const NormalOptions normals;
  const ParticleOptions particles;
  const LineOptions lines;
  using Particles = ParticleOptions;
  return {
      {"reconstruct", "--tolerance", "", "", def(mpu.tolerance)},
      {"reconstruct", "--support", "", "", def(mpu.support)},
      {"reconstruct", "--min-points", "", "", def(mpu.min_points, 6, 100000)},
      {"reconstruct", "--max-depth", "", "", def(mpu.max_depth, 0, 20)},
      {"reconstruct", "--neighbours", "", "", def(normals.neighbours, 3, 256)},
      {"reconstruct", "--bin", "", "", def(tfp.bin_width)},
      {"reconstruct", "--bin-spacings", "", "", def(tfp.bin_spacings)},
      {"reconstruct", "--min-radius", "", "", def(tfp.min_radius)},
      {"reconstruct", "--pipe-exponent", "", "", def(tfp.pipe_exponent, 1, 4)},
      {"reconstruct", "--straight-tolerance", "", "", def(tfp.straight_tolerance, 0, 1)},
      {"reconstruct", "--min-branch-points", "", "",
       def(static_cast<double>(tfp.min_branch_points))},
      {"reconstruct", "--min-branch-bins", "", "", def(static_cast<double>(tfp.min_branch_bins))},
      {"particles", "--per-cell", "", "", def(static_cast<double>(particles.per_cell), 1, 1000)},
      {"particles", "--iterations", "", "",
       def(particles.iterations, 0, Particles::kMaxIterations)},
      {"particles", "--cell-depth", "", "", def(particles.max_depth, 0, Particles::kMaxDepth)},
      {"particles", "--flatness", "", "", def(particles.flatness_deg)},
      {"draw", "--k-c", "", "", def(lines.k_c, 0, 1)},
      {"draw", "--k-e", "", "", def(lines.k_e)},
      {"draw", "--chain-distance", "", "", def(lines.chain_distance)},
      {"draw", "--k-d", "", "", def(lines.k_d)},
      {"draw", "--theta-sc", "", "", def(lines.theta_sc_deg, 0, 90)},
      {"draw", "--t-d", "", "", def(lines.t_d)},
      {"draw", "--k-trim", "", "", def(lines.k_trim, 1, 1000)},
      {"draw", "--k-a", "", "", def(lines.k_a_deg, 0, 180)},
      {"mesh", "--levels", "save_mesh", "levels", levels},
      {"mesh", "--tolerance", "save_mesh", "tolerance", tolerance},
      {"demo", "--tolerance", "", "", tolerance},
      {"mesh", "--section-scale", "save_mesh", "section_scale", scale},
      {"mesh", "--resolution", "save_mesh", "resolution", resolution},
      {"demo", "--levels", "", "", def(1, Tets::kMinLevels, Tets::kMaxLevels), false},
      {"generate", "--segments", "", "",
       def(static_cast<double>(tree.segments), static_cast<double>(Tree::kMinSegments),
           static_cast<double>(Tree::kMaxSegments))},
      {"generate", "--seed", "", "", def(static_cast<double>(tree.seed))},
      {"generate", "--trunk-length", "", "", def(tree.trunk_length)},
      {"generate", "--length-ratio", "", "",
       def(tree.length_ratio, Tree::kMinLengthRatio, Tree::kMaxLengthRatio)},
      {"generate", "--branch-angle", "", "", def(tree.branch_angle_deg)},
      {"generate", "--jitter", "", "", def(tree.jitter_deg, 0, Tree::kMaxJitterDeg)},
      {"generate", "--tip-radius", "", "", def(tree.tip_radius)},
      {"generate", "--pipe-exponent", "", "",
       def(tree.pipe_exponent, Tree::kMinPipeExponent, Tree::kMaxPipeExponent)},
      {"grow", "--step", "grow", "step", def(grow.step)},
      {"grow", "--influence", "grow", "influence", def(grow.influence)},
      {"grow", "--kill", "grow", "kill", def(grow.kill)},
      {"grow", "--max-iterations", "grow", "max_iterations", def(grow.max_iterations)},
      {"grow", "--tip-radius", "grow", "tip_radius", def(grow.tip_radius)},
      {"grow", "--pipe-exponent", "grow", "pipe_exponent", grow_exponent},
      {"grow", "--smooth", "grow", "smooth",
       def(grow.smooth_iterations, 0, BranchCleanupOptions::kMaxSmoothIterations)},
      {"grow", "--max-turn", "grow", "max_turn", def(grow.max_turn_deg)},
      {"grow", "--prune", "grow", "prune", def(grow.prune_steps)},
      {"lsystem", "--iterations", "lsystem", "iterations",
       def(ls.iterations, 0, LSys::kMaxIterations)},
      {"lsystem", "--angle", "lsystem", "angle", def(ls.angle_deg)},
      {"lsystem", "--step", "lsystem", "step", def(ls.step)},
      {"lsystem", "--width", "lsystem", "width", def(ls.width)},
      {"run", "--seed", "", "", def(static_cast<double>(script.seed))},
      {"shell", "--seed", "", "", def(static_cast<double>(script.seed))},
  };
}

double number(const std::string& text, const std::string& where) {
  double v = 0;
  EXPECT_EQ(parse_number(text, v), NumberStatus::kOk) << where << ": '" << text << "'";
  return v;
}

/// The value stated after `text[from]` (see the file comment); nullopt with a failure if none.
std::optional<Value> stated_after(const std::string& text, std::size_t from,
                                  const std::string& where) {
  const std::string open = "(default ";
  const std::size_t at = text.find(open, from);
  if (at == std::string::npos || at - from > kNear) {
    ADD_FAILURE() << where << ": no \"(default ...)\" after the option";
    return std::nullopt;
  }
  const std::size_t close = text.find(')', at);
  if (close == std::string::npos) {
    ADD_FAILURE() << where << ": unclosed \"(default\"";
    return std::nullopt;
  }
  std::string inner = text.substr(at + open.size(), close - at - open.size());
  inner = inner.substr(0, inner.find(';'));  // "(default 3, 2–1000; a remark)"
  Value v;
  const std::size_t comma = inner.find(", ");
  v.value = number(inner.substr(0, comma), where);
  if (comma != std::string::npos) {
    const std::string range = inner.substr(comma + 2);
    const std::size_t dash = range.find(kDash);
    if (dash == std::string::npos) {
      ADD_FAILURE() << where << ": range '" << range << "' is not MIN" << kDash << "MAX";
      return std::nullopt;
    }
    v.min = number(range.substr(0, dash), where);
    v.max = number(range.substr(dash + std::string(kDash).size()), where);
  }
  return v;
}

/// Checks what `text` states after its first `marker` against the case's values.
void expect_states(const std::string& text, const std::string& marker, const OptionCase& c,
                   const std::string& where) {
  const std::size_t at = text.find(marker);
  ASSERT_NE(at, std::string::npos) << where << ": " << marker << " is not mentioned";
  const std::optional<Value> v = stated_after(text, at + marker.size(), where);
  if (!v) return;
  if (c.default_is_the_structs) {
    EXPECT_EQ(v->value, c.expected.value) << where << " default";
  }
  EXPECT_EQ(v->min.has_value(), c.expected.min.has_value()) << where << ": range stated?";
  if (v->min && c.expected.min) {
    EXPECT_EQ(*v->min, *c.expected.min) << where << " minimum";
    EXPECT_EQ(*v->max, *c.expected.max) << where << " maximum";
  }
}

/// Whitespace runs (line breaks included) as single spaces, so that wrapped prose reads whole.
std::string squeeze(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const bool blank = ch == ' ' || ch == '\n' || ch == '\t' || ch == '\r';
    if (!blank) {
      out += ch;
    } else if (!out.empty() && out.back() != ' ') {
      out += ' ';
    }
  }
  return out;
}

/// From the first line starting with `heading` to the next line starting with one of `ends`.
std::string section(const std::string& page, const std::string& heading,
                    const std::vector<std::string>& ends) {
  const std::size_t start = page.find("\n" + heading);
  if (start == std::string::npos) return {};
  std::size_t stop = page.size();
  for (const std::string& e : ends) stop = std::min(stop, page.find("\n" + e, start + 1));
  return squeeze(page.substr(start, stop - start));
}

/// The line of `help` that documents `flag` ("  --flag TYPE  text", "  -o,--flag ..."), with the
/// line its text moves to when the names are long (indented, not starting with '-').
std::string help_line(const std::string& help, const std::string& flag) {
  std::vector<std::string> lines;
  for (std::size_t start = 0; start < help.size();) {
    std::size_t end = help.find('\n', start);
    if (end == std::string::npos) end = help.size();
    lines.push_back(help.substr(start, end - start));
    start = end + 1;
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t first = lines[i].find_first_not_of(' ');
    if (first == std::string::npos) continue;
    const std::string names = lines[i].substr(first, lines[i].find(' ', first) - first);
    if (names != flag && !names.ends_with("," + flag)) continue;
    std::string text = lines[i];
    if (i + 1 < lines.size()) {
      const std::size_t next = lines[i + 1].find_first_not_of(' ');
      if (next != std::string::npos && next > first && lines[i + 1][next] != '-') {
        text += " " + lines[i + 1].substr(next);
      }
    }
    return text;
  }
  return {};
}

std::string doc(const std::string& name) {
  return read_file(std::string(RAMIFORM_SOURCE_DIR) + "/docs/" + name);
}

TEST(HelpDocs, HelpAndDocsStateTheOptionsStructs) {
  const std::string cli_md = doc("cli.md");
  const std::string language_md = doc("language.md");
  ASSERT_FALSE(cli_md.empty());
  ASSERT_FALSE(language_md.empty());
  for (const OptionCase& c : cases()) {
    SCOPED_TRACE(c.cli_command + " " + c.flag + " / " + c.script_command + " " + c.key);
    if (!c.flag.empty()) {
      const CliRun help = run_cli(c.cli_command + " --help");
      ASSERT_EQ(help.code, 0) << help.out;
      const std::string line = help_line(help.out, c.flag);
      ASSERT_FALSE(line.empty()) << c.cli_command << " --help has no " << c.flag << ":\n"
                                 << help.out;
      expect_states(line, c.flag, c, "ramiform " + c.cli_command + " --help");
      const std::string sec = section(cli_md, "## `ramiform " + c.cli_command, {"## "});
      ASSERT_FALSE(sec.empty()) << "docs/cli.md has no section for " << c.cli_command;
      expect_states(sec, "`" + c.flag, c, "docs/cli.md, " + c.cli_command);
    }
    if (!c.key.empty()) {
      const std::string help = squeeze(ScriptSession::command_help(c.script_command));
      expect_states(help, "`" + c.key + "`", c, "help " + c.script_command);
      const std::string sec =
          section(language_md, "### " + c.script_command + "\n", {"### ", "## "});
      ASSERT_FALSE(sec.empty()) << "docs/language.md has no section for " << c.script_command;
      expect_states(sec, "`" + c.key + "`", c, "docs/language.md, " + c.script_command);
    }
  }
}

class HelpDocsRunTest : public CliDirTest {};

// The CLI's defaults are the structs': a run without the option equals one that passes the
// struct's value, and the stats report it.
TEST_F(HelpDocsRunTest, CliDefaultsAreTheStructs) {
  const std::string skel = y_fork();
  const ToleranceOptions tol;
  const TetrahedralOptions& tets = tol.tets;
  ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("t.ply") + " --stats " + path("t.json")).code,
            0);
  const std::string stats = read_file(path("t.json"));
  EXPECT_NE(stats.find("\"levels\": " + std::to_string(tets.levels)), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"tolerance\": " + format_number(tol.tolerance)), std::string::npos)
      << stats;
  const CliRun explicit_tets =
      run_cli("mesh " + skel + " -o " + path("t2.ply") + " --levels " +
              std::to_string(tets.levels) + " --section-scale " +
              std::to_string(tets.section_scale) + " --tolerance " + format_number(tol.tolerance));
  ASSERT_EQ(explicit_tets.code, 0) << explicit_tets.out;
  EXPECT_EQ(read_file(path("t.ply")), read_file(path("t2.ply")));
  // --levels alone: the paper's uniform levels, unrefined (a different, coarser mesh).
  ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("t3.ply") + " --levels " +
                    std::to_string(tets.levels) + " --stats " + path("t3.json"))
                .code,
            0);
  EXPECT_EQ(read_file(path("t3.json")).find("\"tolerance\""), std::string::npos);
  EXPECT_LT(read_file(path("t3.ply")).size(), read_file(path("t.ply")).size());

  const MarchingCubesOptions mc;
  ASSERT_EQ(run_cli("mesh " + skel + " --method mc -o " + path("m.ply")).code, 0);
  ASSERT_EQ(run_cli("mesh " + skel + " --method mc -o " + path("m2.ply") + " --resolution " +
                    std::to_string(mc.resolution))
                .code,
            0);
  EXPECT_EQ(read_file(path("m.ply")), read_file(path("m2.ply")));

  BranchingTreeOptions tree;
  tree.segments = 40;
  ASSERT_EQ(run_cli("generate " + path("g.json") + " --segments 40").code, 0);
  write_skeleton(branching_tree(tree), path("g2.json"));
  EXPECT_EQ(read_file(path("g.json")), read_file(path("g2.json")));

  ASSERT_EQ(run_cli("lsystem monopodial -o " + path("l.json")).code, 0);
  const auto examples = lsystem_examples();
  const auto it = std::find_if(examples.begin(), examples.end(),
                               [](const auto& e) { return e.first == "monopodial"; });
  ASSERT_NE(it, examples.end());
  write_skeleton(lsystem_skeleton(it->second, "monopodial", LSystemOptions{}), path("l2.json"));
  EXPECT_EQ(read_file(path("l.json")), read_file(path("l2.json")));

  std::string points;
  for (int i = 0; i < 30; ++i) {
    const Vec3 p(0.3 * (i % 5) - 0.6, 0.25 * (i % 3) - 0.25, 4.0 + 0.2 * i);
    points +=
        std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  }
  const std::string pts = write("p.txt", points);
  ASSERT_EQ(run_cli("grow --points " + pts + " -o " + path("g.json")).code, 0);
  const PointSet read_back = read_points(pts);
  const ColonizationResult grown = grow_space_colonization(read_back.positions, {});
  write_skeleton(grown.skeleton, path("grown.json"));
  EXPECT_EQ(read_file(path("g.json")), read_file(path("grown.json")));
}

// The scene language's defaults are the structs': save_mesh reports what it used.
TEST_F(HelpDocsRunTest, SceneLanguageDefaultsAreTheStructs) {
  const std::string skel = y_fork();
  ScriptOptions options;
  options.out_dir = dir_.string();
  ScriptSession session(options);
  session.execute_line("skeleton t \"" + skel + "\" surface=convolution");
  const CommandResult tets = session.execute_line("save_mesh t t.ply method=tets");
  EXPECT_NE(
      tets.message.find("(tets to tolerance " + format_number(ToleranceOptions{}.tolerance) + ":"),
      std::string::npos)
      << tets.message;
  const CommandResult uniform = session.execute_line("save_mesh t u.ply method=tets levels=2");
  EXPECT_NE(uniform.message.find("(tets, 2 levels)"), std::string::npos) << uniform.message;
  session.execute_line("sphere s");
  const CommandResult mc = session.execute_line("save_mesh s s.ply");
  EXPECT_NE(
      mc.message.find("(mc, resolution " + std::to_string(MarchingCubesOptions{}.resolution) + ")"),
      std::string::npos)
      << mc.message;
  const CommandResult ls = session.execute_line("lsystem p monopodial");
  EXPECT_NE(ls.message.find(", " + std::to_string(LSystemOptions{}.iterations) + " iterations"),
            std::string::npos)
      << ls.message;
  session.discard();
}

}  // namespace
}  // namespace ramiform::test
