// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/lsystem.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

std::string derive(const std::string& text, int n) {
  return lsystem_string(lsystem_derive(text, "test.ls", n));
}

TEST(LSystem, AlgaeDerivation) {
  const std::string algae = "# Lindenmayer's algae\naxiom: A\nA -> AB\nB -> A\n";
  const char* expected[] = {"A", "AB", "ABA", "ABAAB", "ABAABABA", "ABAABABAABAAB"};
  for (int n = 0; n < 6; ++n) EXPECT_EQ(derive(algae, n), expected[n]) << n;
  // Lengths are Fibonacci numbers.
  std::size_t a = 1, b = 1;
  for (int n = 0; n < 15; ++n) {
    EXPECT_EQ(derive(algae, n).size(), b) << n;
    const std::size_t c = a + b;
    a = b;
    b = c;
  }
}

TEST(LSystem, BracketedPlantCounts) {
  // F -> F[+F]F[-F]F: 5^n segments, one tree (branches start at shared nodes).
  const std::string text = "axiom: F\nF -> F[+F]F[-F]F\n";
  for (int n = 0; n <= 4; ++n) {
    LSystemOptions o;
    o.iterations = n;
    const Skeleton s = lsystem_skeleton(text, "p", o);
    const auto fives = static_cast<std::size_t>(std::pow(5, n));
    EXPECT_EQ(s.edge_count(), fives);
    EXPECT_EQ(s.node_count(), fives + 1);
    EXPECT_EQ(connected_components(s).count, 1u);
    EXPECT_NO_THROW(validate(s));
  }
  // Independent count for a node-rewriting system: edges = number of F in the string.
  const auto ex = lsystem_examples();
  const auto it = std::find_if(ex.begin(), ex.end(), [](const auto& e) { return e.first == "plant-2d"; });
  ASSERT_NE(it, ex.end());
  const std::string str = derive(it->second, 4);
  const auto fs = static_cast<std::size_t>(std::count(str.begin(), str.end(), 'F'));
  LSystemOptions o;
  o.iterations = 4;
  const Skeleton s = lsystem_skeleton(it->second, "plant-2d", o);
  EXPECT_EQ(s.edge_count(), fs);
  EXPECT_EQ(s.node_count(), fs + 1);
  EXPECT_EQ(connected_components(s).count, 1u);
}

TEST(LSystem, TurtleExactRightAngles) {
  LSystemOptions o;
  o.iterations = 0;
  o.angle_deg = 90;
  // Heading +z, + turns toward left (-x).
  Skeleton s = lsystem_skeleton("axiom: F+F", "t", o);
  ASSERT_EQ(s.node_count(), 3u);
  EXPECT_EQ(s.nodes[0].position, Vec3(0, 0, 0));
  EXPECT_EQ(s.nodes[1].position, Vec3(0, 0, 1));
  EXPECT_EQ(s.nodes[2].position, Vec3(-1, 0, 1));
  // A square closes exactly.
  s = lsystem_skeleton("axiom: F+F+F+F", "t", o);
  EXPECT_EQ(s.nodes[4].position, Vec3(0, 0, 0));
  // Explicit angles, pitch and turn-around; f moves without drawing (a second tree).
  o.angle_deg = 25;
  s = lsystem_skeleton("axiom: F(2)-(90)F(3)&(90)F|F(0.5)f(4)F", "t", o);
  ASSERT_EQ(s.node_count(), 7u);
  EXPECT_EQ(s.nodes[1].position, Vec3(0, 0, 2));
  EXPECT_EQ(s.nodes[2].position, Vec3(3, 0, 2));   // - turns right (+x)
  EXPECT_EQ(s.nodes[3].position, Vec3(3, 1, 2));   // & pitches toward -U = +y
  EXPECT_EQ(s.nodes[4].position, Vec3(3, 0.5, 2)); // | turns around
  EXPECT_EQ(s.nodes[5].position, Vec3(3, -3.5, 2));
  EXPECT_EQ(s.nodes[6].position, Vec3(3, -4.5, 2));
  EXPECT_EQ(connected_components(s).count, 2u);
}

TEST(LSystem, BranchesShareNodesAndWidths) {
  LSystemOptions o;
  o.iterations = 0;
  o.width = 0.4;
  const Skeleton s = lsystem_skeleton("axiom: F[+F][-F]!(0.2)F", "t", o);
  ASSERT_EQ(s.edge_count(), 4u);
  ASSERT_EQ(s.node_count(), 5u);
  EXPECT_EQ(degrees(s)[1], 4u);
  EXPECT_EQ(s.nodes[0].radius, 0.2);
  EXPECT_EQ(s.nodes[2].radius, 0.2);
  EXPECT_EQ(s.nodes[4].radius, 0.1);
  const Skeleton w = lsystem_skeleton("axiom: F(1,0.6)!F", "t", o);
  EXPECT_DOUBLE_EQ(w.nodes[1].radius, 0.3);
  EXPECT_DOUBLE_EQ(w.nodes[2].radius, 0.3 * 0.7);
}

TEST(LSystem, PipeRadii) {
  LSystemOptions o;
  o.iterations = 3;
  o.radius = LSystemRadius::kPipe;
  o.tip_radius = 0.01;
  o.pipe_exponent = 2;
  const Skeleton s = lsystem_skeleton("axiom: F\nF -> F[+F][-F]", "t", o);
  // 3^3 segments: root radius^2 = number of tips * tip^2; tips = 1 + 2 + 4 + ... per level.
  std::size_t tips = 0;
  for (auto d : degrees(s)) tips += d == 1 ? 1 : 0;
  tips -= 1;  // the root has degree 1 too
  EXPECT_NEAR(s.nodes[0].radius * s.nodes[0].radius, static_cast<double>(tips) * 1e-4, 1e-15);
}

TEST(LSystem, ParametricConditions) {
  const std::string text =
      "#define k 3   # limit\n"
      "axiom: A(1)\n"
      "A(x) : x < k -> F(x)A(x+1)\n"
      "A(x) : * -> B(x*2, -x)\n";
  EXPECT_EQ(derive(text, 1), "F(1)A(2)");
  EXPECT_EQ(derive(text, 2), "F(1)F(2)A(3)");
  EXPECT_EQ(derive(text, 3), "F(1)F(2)B(6,-3)");
  EXPECT_EQ(derive(text, 4), "F(1)F(2)B(6,-3)");
  // Operators, functions and precedence.
  EXPECT_EQ(derive("axiom: A(2)\nA(x) : x >= 2 && !(x == 3) || 0 -> C(2^3^2, -x^2, 1+2*3, sqrt(16), max(1,x), cos(90)<1e-9)", 1),
            "C(512,-4,7,4,2,1)");
  // Arity must match: A() with one parameter does not use a zero-parameter production.
  EXPECT_EQ(derive("axiom: A(1)A\nA -> X", 1), "A(1)X");
}

TEST(LSystem, IssueExampleTerminates) {
  const std::string text =
      "axiom: A(1,0.1)\n"
      "A(l,w) : l > 0.1 -> F(l,w)[+(30)A(l*0.7,w*0.7)][-(30)A(l*0.7,w*0.7)]\n";
  LSystemOptions o;
  o.iterations = 20;
  const Skeleton s = lsystem_skeleton(text, "t", o);
  // l = 0.7^k > 0.1 for k <= 6: 2^7 - 1 segments.
  EXPECT_EQ(s.edge_count(), 127u);
  EXPECT_EQ(s.node_count(), 128u);
  EXPECT_NO_THROW(validate(s));
}

using Pos = std::pair<std::size_t, std::size_t>;

TEST(LSystem, ParseErrorsNameLineAndColumn) {
  auto where = [](const std::string& text) -> std::pair<std::size_t, std::size_t> {
    try {
      (void)lsystem_derive(text, "bad.ls", 1);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.ls");
      EXPECT_NE(std::string(e.what()).find("bad.ls:"), std::string::npos);
      return {e.line(), e.column()};
    }
    ADD_FAILURE() << "no InputError for: " << text;
    return {0, 0};
  };
  EXPECT_EQ(where("axiom: A(x)"), Pos(1, 10));
  EXPECT_EQ(where("axiom: F\n\nF -> F(1,"), Pos(3, 10));
  EXPECT_EQ(where("# c\nhello"), Pos(2, 1));
  EXPECT_EQ(where("axiom: F\n  A(l : l > 1 -> F").first, 2u);
  EXPECT_EQ(where("axiom: F\naxiom: G").first, 2u);
  EXPECT_EQ(where("#define\naxiom: F").first, 1u);
  EXPECT_EQ(where("axiom: A(foo(1))").second, 10u);
  EXPECT_EQ(where("F -> FF").first, 1u);  // no axiom
}

// A UTF-8 byte order mark at the start is skipped (columns count from after it); bytes outside
// printable ASCII appear in messages as \xNN.
TEST(LSystem, ByteOrderMarkIsSkippedAndBytesAreEscaped) {
  const std::string bom = "\xEF\xBB\xBF";
  EXPECT_EQ(derive(bom + "axiom: F\r\nF -> FF\r\n", 2), "FFFF");
  try {
    (void)lsystem_derive(bom + "axiom: F(", "bad.ls", 1);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_EQ(e.column(), 10u);
  }
  // Only at the start: a byte order mark elsewhere is an unexpected byte, shown escaped.
  for (const auto& [text, problem] :
       {std::pair<std::string, std::string>{"axiom: F\xC3\xA8", "unexpected '\\xc3'"},
        {"axiom: F\n" + bom + "F -> FF", "expected a module symbol"},
        {"axiom: F\n" + bom + "F",
         "expected 'axiom: ...', '#define NAME VALUE' or a production "
         "'A -> ...'"},
        {"axiom: F\nF -> F(\x1b)", "unexpected '\\x1b' in expression"}}) {
    try {
      (void)lsystem_derive(text, "bad.ls", 1);
      ADD_FAILURE() << "no InputError for: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.problem(), problem);
    }
  }
}

TEST(LSystem, InterpretErrorsAndLimits) {
  LSystemOptions o;
  o.iterations = 0;
  EXPECT_THROW((void)lsystem_skeleton("axiom: F]", "t", o), InvalidArgument);
  EXPECT_THROW((void)lsystem_skeleton("axiom: [F", "t", o), InvalidArgument);
  EXPECT_THROW((void)lsystem_skeleton("axiom: X", "t", o), InvalidArgument);
  EXPECT_THROW((void)lsystem_derive("axiom: F\nF -> FF", "t", 30, 1000), InvalidArgument);
  o.iterations = -1;
  EXPECT_THROW((void)lsystem_skeleton("axiom: F", "t", o), InvalidArgument);
}

TEST(LSystem, ExamplesBuildValidTrees) {
  const auto ex = lsystem_examples();
  EXPECT_GE(ex.size(), 4u);
  for (const auto& [name, text] : ex) {
    LSystemOptions o;
    o.iterations = 4;
    const Skeleton s = lsystem_skeleton(text, name, o);
    EXPECT_NO_THROW(validate(s, name)) << name;
    EXPECT_EQ(connected_components(s).count, 1u) << name;
    EXPECT_EQ(s.edge_count() + 1, s.node_count()) << name;
    EXPECT_GT(s.edge_count(), 10u) << name;
    // Same text, same result.
    const Skeleton again = lsystem_skeleton(text, name, o);
    ASSERT_EQ(again.node_count(), s.node_count());
    for (std::size_t i = 0; i < s.node_count(); ++i)
      EXPECT_EQ(again.nodes[i].position, s.nodes[i].position);
  }
}

}  // namespace
}  // namespace ramiform
