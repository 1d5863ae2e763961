// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Hostile scripts (issue 15): each asks for unbounded stack, time or memory and must instead be
// refused with a located script error, or run within fixed bounds.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"
#include "ramiform/script/script.h"
#include "script/script_fixture.h"
#include "script/session.h"
#include "support/fixtures.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

class HostileScripts : public ScriptDirTest {};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(HostileScripts, FiftyThousandDeepUnionChainIsAScriptError) {
  // `union a b c1`, `union c1 b c2`, ...: c_k is nested k + 1 deep, so the line making
  // c_kMaxFieldDepth is refused and nothing later runs (the chain once crashed the evaluation).
  std::string text = "sphere a\nsphere b 0.5 center=0.3,0,0\nunion a b c1\n";
  for (int k = 2; k <= 50000; ++k) {
    text += "union c" + std::to_string(k - 1) + " b c" + std::to_string(k) + "\n";
  }
  const InputError e = error_of(text);
  EXPECT_EQ(e.file(), "t.rf");
  EXPECT_EQ(e.line(), 2 + kMaxFieldDepth);
  EXPECT_EQ(e.column(), 1U);
  EXPECT_EQ(e.problem().rfind("union: the fields would be nested", 0), 0U) << e.problem();
  EXPECT_TRUE(contains(e.problem(), "maximum depth " + std::to_string(kMaxFieldDepth)))
      << e.problem();
}

TEST_F(HostileScripts, DeepestAllowedChainEvaluatesAndDescribes) {
  std::string text = "sphere a\nsphere b 0.5 center=0.3,0,0\nunion a b c1\n";
  for (std::size_t k = 2; k + 1 < kMaxFieldDepth; ++k) {
    text += "union c" + std::to_string(k - 1) + " b c" + std::to_string(k) + "\n";
  }
  const std::string top = "c" + std::to_string(kMaxFieldDepth - 2);
  text += "translate " + top + " 0 0 0.5\n";  // one level more would be refused
  text += "eval " + top + " 0.1 0 0.5\ninfo " + top + "\n";
  ScriptSession s(options_);
  const auto results = s.run_text(text, "t.rf");
  EXPECT_TRUE(contains(results[results.size() - 2].message, "(inside")) << results.back().message;
  // A second move composes with the first (one transform), but a union on top is one too deep.
  EXPECT_NO_THROW(
      ScriptSession(options_).run_text(text + "translate " + top + " 0 0 1\n", "t.rf"));
  const InputError e = error_of(text + "union " + top + " b over\n");
  EXPECT_EQ(e.line(), kMaxFieldDepth + 4);
  EXPECT_EQ(e.problem().rfind("union: the fields would be nested", 0), 0U) << e.problem();
}

// Runs script lines the way ScriptSession::execute_line does, on a session state the test can
// look into (the objects' fields and their evaluation counters).
void run_lines(ScriptSession::Impl& session, const std::vector<std::string>& lines) {
  std::size_t line = 0;
  for (const std::string& text : lines) {
    std::vector<script::Token> tokens = script::tokenize(text, "t.rf", ++line);
    const script::CommandSpec& spec = *script::command_table().at(tokens.front().text);
    script::Call call(session, spec, std::move(tokens), "t.rf", line);
    (void)spec.run(call);
  }
}

TEST_F(HostileScripts, SharedSubExpressionsAreEvaluatedOnce) {
  // Ten lines of `union x x x x x x x x y`: each result used 8 times by the next. Every path
  // through the DAG would make 8^10 (about 10^9) evaluations of x0 per point; each distinct
  // child is evaluated once per batch.
  ScriptSession::Impl session;
  session.options = options_;
  std::vector<std::string> lines = {"sphere x0", "line y"};
  for (int k = 1; k <= 10; ++k) {
    const std::string x = "x" + std::to_string(k - 1);
    std::string line = "union";
    for (int i = 0; i < 8; ++i) line += " " + x;
    lines.push_back(line + " y x" + std::to_string(k));
  }
  lines.push_back("union x0 y plain");  // the same shape without sharing: max(v, v) = v
  run_lines(session, lines);
  const Field& x0 = *session.objects.at("x0").field;
  const Field& y = *session.objects.at("y").field;
  const Field& top = *session.objects.at("x10").field;
  const Field& plain = *session.objects.at("plain").field;
  const std::vector<Vec3> points = {Vec3(0.1, 0.2, 0), Vec3(0.5, 0, 1.2), Vec3(0, 0, 1.6),
                                    Vec3(0.9, 0.5, 0.1), Vec3(3, 0, 0)};
  x0.reset_evaluations();
  y.reset_evaluations();
  std::vector<double> v(points.size()), pv(points.size());
  std::vector<Vec3> g(points.size()), pg(points.size());
  top.evaluate(points, v, g);
  EXPECT_EQ(x0.evaluations(), points.size());
  EXPECT_EQ(y.evaluations(), 10 * points.size());
  plain.evaluate(points, pv, pg);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(v[i], pv[i]) << i;
    EXPECT_TRUE(g[i] == pg[i]) << i;
  }
  // info bounds the shape, save_mesh restricts it: both visit each distinct child once too.
  x0.reset_evaluations();
  run_lines(session, {"info x10", "save_mesh x10 m.ply resolution=16"});
  EXPECT_LT(x0.evaluations(), 100000U);
}

TEST_F(HostileScripts, NestedParamsAreCappedBeforeTheyAllocate) {
  // Each parameter ten times the last: 10^k bytes on line k; 10^6 fits in
  // kMaxSubstitutedLine (1 MiB), 10^7 does not (this script once asked for 17 GB).
  std::string text = "param p1 0123456789\n";
  for (int k = 2; k <= 11; ++k) {
    const std::string prev = "$p" + std::to_string(k - 1);
    std::string value;
    for (int i = 0; i < 10; ++i) value += prev;
    text += "param p" + std::to_string(k) + " " + value + "\n";
  }
  ASSERT_LT(text.size(), 500U);
  const InputError e = error_of(text);
  EXPECT_EQ(e.line(), 7U);
  EXPECT_TRUE(contains(e.problem(), "param: line 7 grows beyond the limit of " +
                                        std::to_string(script::kMaxSubstitutedLine) + " bytes"))
      << e.problem();

  // Many lines that each stay within the line limit cannot pile up more than
  // kMaxParameterBytes.
  std::string many = text.substr(0, text.find("param p7"));
  for (int k = 0; k < 40; ++k) many += "param q" + std::to_string(k) + " $p6\n";
  const InputError total = error_of(many);
  EXPECT_EQ(total.line(), 6 + script::kMaxParameterBytes / 1000000);
  EXPECT_TRUE(contains(total.problem(), "kMaxParameterBytes")) << total.problem();
  // A long value is shown cut short in the result that is kept.
  ScriptSession s(options_);
  const auto results = s.run_text(text.substr(0, text.find("param p7")), "t.rf");
  for (const CommandResult& r : results) EXPECT_LT(r.message.size(), 300U);
}

TEST_F(HostileScripts, TwentyThousandTranslatesKeepBoundedText) {
  // Every transform used to append to its object's summary and every result copied it: the
  // text kept grew with the square of the chain's length (8 GB for 200,000 lines).
  std::string text;
  for (int s = 0; s < 20; ++s) text += "sphere s" + std::to_string(s) + "\n";
  for (int k = 0; k < 1000; ++k) {
    for (int s = 0; s < 20; ++s) text += "translate s" + std::to_string(s) + " 0 0 0.001\n";
  }
  text += "info s0\nlist\n";
  ScriptSession session(options_);
  const auto results = session.run_text(text, "t.rf");
  ASSERT_EQ(results.size(), 20U + 20000U + 2U);
  std::size_t total = 0;
  for (std::size_t i = 0; i + 1 < results.size(); ++i) {
    ASSERT_LE(results[i].message.size(), script::kMaxSummary + 80) << i;
    total += results[i].message.size();
  }
  EXPECT_LT(total, 20022U * (script::kMaxSummary + 80));
  const std::string& info = results[results.size() - 2].message;
  EXPECT_EQ(info.rfind("s0: sphere, radius 1 at 0,0,0, translated by 0,0,0.001", 0), 0U) << info;
  EXPECT_TRUE(contains(info, " more transforms)")) << info;
  EXPECT_LT(results.back().message.size(), 20 * (script::kMaxSummary + 80));
}

TEST_F(HostileScripts, ListNamesAtMostKMaxListedObjects) {
  std::string text;
  for (std::size_t k = 0; k < script::kMaxListed + 5; ++k)
    text += "sphere s" + std::to_string(k) + "\n";
  ScriptSession session(options_);
  session.run_text(text, "t.rf");
  const std::string list = session.execute_line("list").message;
  EXPECT_EQ(static_cast<std::size_t>(std::count(list.begin(), list.end(), '\n')),
            script::kMaxListed);
  EXPECT_TRUE(list.ends_with("\n... and 5 more")) << list.substr(list.size() - 40);
}

TEST_F(HostileScripts, LongNamesAndSummariesAreRefusedOrCut) {
  const std::string name(script::kMaxNameLength + 1, 'n');
  const InputError e = error_of("sphere " + name + "\n");
  EXPECT_TRUE(contains(e.problem(), "at most " + std::to_string(script::kMaxNameLength)))
      << e.problem();
  // A union of many inputs names them all in its summary: cut to kMaxSummary.
  std::string text = "sphere a\n";
  std::string line = "union";
  for (int i = 0; i < 200; ++i) line += " a";
  text += line + " u\ninfo u\n";
  ScriptSession session(options_);
  const auto results = session.run_text(text, "t.rf");
  EXPECT_LE(results[1].message.size(), script::kMaxSummary + 3);
  EXPECT_TRUE(results[1].message.ends_with("...")) << results[1].message;
}

// A UTF-8 byte order mark that an editor wrote before the first command is skipped (in a file,
// and on the first line given to execute_line, as the shell does).
TEST_F(HostileScripts, ByteOrderMarkBeforeTheFirstCommandIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  ScriptSession session(options_);
  const auto results = session.run_text(bom + "sphere s 1\r\ninfo s\n", "t.rf");
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].command, "sphere");
  ScriptSession shell(options_);
  EXPECT_EQ(shell.execute_line(bom + "sphere s 1", "<shell>", 1).command, "sphere");
  // Elsewhere it is part of a token, and shown escaped.
  const InputError e = error_of("sphere s 1\n" + bom + "sphere t 1\n");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_TRUE(
      contains(e.problem(), "unknown command '\\xef\\xbb\\xbfsphere' (did you mean 'sphere'?)"))
      << e.problem();
}

// Every byte outside printable ASCII in a token a message quotes appears as \xNN: UTF-8 letters
// (bytes >= 0x80) as well as control bytes.
TEST_F(HostileScripts, MessagesShowNonAsciiBytesEscaped) {
  EXPECT_EQ(script::shown("a\xC3\xA9\x1b\x7f~"), "a\\xc3\\xa9\\x1b\\x7f~");
  EXPECT_EQ(script::shown(std::string(60, 'x')), std::string(48, 'x') + "...");
  std::ofstream(dir_ / "c.txt", std::ios::binary) << "0 0 0 1\n1 1 \xC3\xA9 1\n";
  const struct {
    std::string script;
    std::string part;  // of the problem
  } cases[] = {
      {"sph\xC3\xA8re s\n", "unknown command 'sph\\xc3\\xa8re'"},
      {"sphere s 1 c\xC3\xA9nter=0,0,0\n", "unknown option 'c\\xc3\\xa9nter'"},
      {"sphere s\xC3\xA9 1\n", "'s\\xc3\\xa9' is not a valid object name"},
      {"sphere s 1\ntranslate s\xC3\xA9 1 0 0\n", "unknown shape 's\\xc3\\xa9'"},
      {"sphere s 1\ntranslate s 1 \xC3\xA9 0\n", "got '\\xc3\\xa9'"},
      {"sphere s 1 \xC3\xA9\n", "unexpected argument '\\xc3\\xa9'"},
      // A message of a command that quotes its token unescaped is escaped as a whole.
      {"sphere s 1\nsave_mesh s a.\xC3\xA9\n", "got 'a.\\xc3\\xa9'"},
      {"rbf b c.txt\n", "got '\\xc3\\xa9'"},
      {"sphere s 1\ngrow t fr\xC3\xB6m s\n", "got 'fr\\xc3\\xb6m'"},
      {"sphere s 1\nlsystem t \xC3\xA9\n", "no L-system example '\\xc3\\xa9'"},
  };
  for (const auto& c : cases) {
    const InputError e = error_of(c.script);
    EXPECT_TRUE(contains(e.problem(), c.part)) << e.problem();
    const std::string what = e.what();
    EXPECT_TRUE(std::all_of(what.begin(), what.end(), [](char ch) {
      return ch >= 0x20 && ch < 0x7f;
    })) << what;
  }
}

// grow explains a growth that reached every point from the root, with numbers and the options
// to change.
TEST_F(HostileScripts, GrowExplainsPointsWithinKillOfTheRoot) {
  std::ofstream(dir_ / "p.xyz", std::ios::binary) << "0 0 0\n1 1 1\n";
  const InputError e = error_of("load_point_set p.xyz\ngrow t from points\n");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.problem(),
            "grow: grew no branch from points: all 2 attraction points lie within the kill "
            "distance d_k = 2 of the root (0,0,0) (the farthest at distance 1.73205), so they were "
            "reached before any branch grew; move root= away from the points or use a smaller "
            "kill=");
  // A stalled growth keeps its own reason, without that advice.
  const InputError stalled = error_of(
      "load_point_set p.xyz\ngrow t from points max_iterations=0 "
      "root=0,0,-10\n");
  EXPECT_TRUE(contains(stalled.problem(), "grew no branch from points: max_iterations (0)"))
      << stalled.problem();
  EXPECT_FALSE(contains(stalled.problem(), "smaller kill=")) << stalled.problem();
}

TEST_F(HostileScripts, AnEmptyMeshIsALocatedErrorNotAnEmptyFile) {
  // A cone a 1e300 high: marching cubes' cells dwarf its width and find no surface. The script
  // once wrote an empty mesh and succeeded.
  const InputError e = error_of("cone c 1 1e300 top=0\nsave_mesh c m.ply\n");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(e.column(), 11u);  // the shape's name
  EXPECT_TRUE(contains(e.problem(), "save_mesh: the mesh of 'c' (mc, resolution 96) is empty"))
      << e.problem();
  EXPECT_TRUE(contains(e.problem(), "smaller cell=")) << e.problem();
  EXPECT_FALSE(fs::exists(dir_ / "m.ply"));
}

}  // namespace
}  // namespace ramiform::test
