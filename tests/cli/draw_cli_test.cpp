// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform draw` and the scene command `draw` as a user runs them: a sphere's silhouette on its
// analytic contour, hidden parts of one sphere behind another, the SVG's structure, turntables,
// byte-identical output on any thread count, and the bad inputs a user feeds them.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli/cli_run.h"

namespace ramiform {
namespace {

using test::CliRun;
using test::read_file;
using test::read_json;
using test::run_cli;

class DrawCliTest : public test::CliDirTest {};

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST_F(DrawCliTest, SphereSilhouetteLiesOnTheContourCircle) {
  const std::string scene = write("scene.rf", "sphere ball 1\n");
  const std::string svg = path("ball.svg");
  const std::string lines = path("ball.json");
  const std::string stats = path("s.json");
  const CliRun r = run_cli("draw " + scene + ":ball -o " + svg + " --count 3000 --polylines " +
                           lines + " --camera 'eye=0,0,6;target=0,0,0' --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.out;
  // The polylines: one closed silhouette on the sphere where the view grazes it, all visible.
  const nlohmann::json j = read_json(lines);
  EXPECT_EQ(j["camera"]["eye"], nlohmann::json({0, 0, 6}));
  std::size_t silhouettes = 0;
  for (const auto& line : j["lines"]) {
    if (line["kind"] != "silhouette") continue;
    ++silhouettes;
    EXPECT_TRUE(line["closed"].get<bool>());
    for (std::size_t i = 0; i < line["points"].size(); ++i) {
      const auto& q = line["points"][i];
      const Eigen::Vector3d p(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
      EXPECT_NEAR(p.norm(), 1.0, 1e-3);
      // The contour of a unit sphere seen from (0,0,6): z = 1/6.
      EXPECT_NEAR(p.z(), 1.0 / 6.0, 2e-3);
      EXPECT_TRUE(line["visible"][i].get<bool>());
    }
  }
  EXPECT_EQ(silhouettes, 1u);
  // A sphere has no suggestive contours and no creases.
  const nlohmann::json s = read_json(stats);
  EXPECT_EQ(s["views"][0]["lines"]["silhouette"], 1);
  EXPECT_EQ(s["views"][0]["lines"]["suggestive"], 0);
  EXPECT_EQ(s["views"][0]["lines"]["feature"], 0);
  EXPECT_NEAR(s["particles"].get<double>(), 3000, 300);
  EXPECT_GT(s["seconds"]["lines"].get<double>(), 0);
  // The SVG: the three groups, one closed path for the silhouette, a viewBox in camera units
  // (fov 30: the frame is ±tan 15°).
  const std::string text = read_file(svg);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("<g id=\"silhouette\""), std::string::npos);
  EXPECT_NE(text.find("<g id=\"suggestive\""), std::string::npos);
  EXPECT_NE(text.find("<g id=\"feature\""), std::string::npos);
  EXPECT_EQ(text.find("<g id=\"hidden\""), std::string::npos);
  EXPECT_EQ(count(text, "<path"), 1u);
  EXPECT_EQ(count(text, "Z\""), 1u);
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(text, m, std::regex("viewBox=\"([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)")));
  EXPECT_NEAR(std::stod(m[1]), -std::tan(15 * M_PI / 180), 1e-4);
  EXPECT_NEAR(std::stod(m[3]), 2 * std::tan(15 * M_PI / 180), 1e-4);
  // One thread or two: the same bytes.
  const std::string one = path("one.svg");
  ASSERT_EQ(run_cli("draw " + scene + ":ball -o " + one +
                    " --count 3000 --camera 'eye=0,0,6;target=0,0,0' --polylines " +
                    path("one.json") + " --threads 1")
                .code,
            0);
  EXPECT_EQ(read_file(one), text);
  EXPECT_EQ(read_file(path("one.json")), read_file(lines));
}

TEST_F(DrawCliTest, TheBackSpheresContourBehindTheFrontOneIsHidden) {
  // Two spheres apart along the view: the back one's contour circle (radius 0.99 around the
  // axis) passes behind the front sphere where it overlaps it in the image.
  const std::string scene =
      write("scene.rf", "sphere a 1\nsphere b 1 center=0.9,0,-3\nunion a b ab\n");
  const std::string lines = path("ab.json");
  const CliRun r = run_cli("draw " + scene + ":ab -o " + path("ab.svg") +
                           " --count 4000 --lines silhouette --hidden --camera "
                           "'eye=0,0,8;target=0,0,-1.5' --polylines " +
                           lines);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = read_json(lines);
  std::size_t checked = 0, wrong = 0;
  const Eigen::Vector3d eye(0, 0, 8);
  for (const auto& line : j["lines"]) {
    for (std::size_t i = 0; i < line["points"].size(); ++i) {
      const auto& q = line["points"][i];
      const Eigen::Vector3d p(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
      if (p.z() > -1.5) continue;  // the front sphere's own contour
      // Hidden exactly when the segment from the eye to p enters the front unit sphere.
      const Eigen::Vector3d d = (p - eye).normalized();
      const double b = eye.dot(d), c = eye.squaredNorm() - 1;
      const double disc = b * b - c;
      const bool hidden = disc > 0 && -b - std::sqrt(disc) < (p - eye).norm();
      // Rays grazing the front sphere's outline (closest approach within 1 % of its radius)
      // are ambiguous at the lines' resolution: skip them.
      if (std::abs(disc) < 0.02) continue;
      ++checked;
      wrong += (line["visible"][i].get<bool>() == hidden) ? 1 : 0;
    }
  }
  EXPECT_GT(checked, 50u);
  EXPECT_EQ(wrong, 0u);
  const std::string svg = read_file(path("ab.svg"));
  EXPECT_NE(svg.find("<g id=\"hidden\""), std::string::npos);
}

TEST_F(DrawCliTest, TurntableWritesOneFilePerViewAndTheSceneCommandDraws) {
  const std::string scene = write("scene.rf",
                                  "torus t 1 thickness=0.35 normal=0,1,0\ndraw t t.svg count=2000 "
                                  "elevation=40 polylines=t.json\n");
  const std::string out = path("turn.svg");
  CliRun r = run_cli("draw " + scene + ":t -o " + out + " --count 2000 --views 3 --elevation 40");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"turn-000.svg", "turn-001.svg", "turn-002.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(path(f))) << f;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  r = run_cli("run " + scene + " --out " + dir_.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(read_file(path("t.svg")).find("<g id=\"suggestive\""), std::string::npos);
  EXPECT_FALSE(read_json(path("t.json"))["lines"].empty());
  // A PNG.
  r = run_cli("draw " + scene + ":t -o " + path("t.png") + " --count 2000 --width 200");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(read_file(path("t.png")).substr(1, 3), "PNG");
}

// A dome (a sphere cut by a plane) has one crease, its rim: one closed feature line from
// either straddle test, the stats saying which found the pairs.
TEST_F(DrawCliTest, StraddleChoosesTheFeatureTest) {
  const std::string scene =
      write("scene.rf", "sphere ball 1\nplane cut 0 0 1 point=0,0,0.3\nintersect ball cut dome\n");
  for (const std::string test : {"auto", "movement", "search"}) {
    const std::string stats = path(test + ".json");
    const CliRun r = run_cli("draw " + scene + ":dome -o " + path(test + ".svg") +
                             " --count 3000 --lines feature --visibility none --straddle " + test +
                             " --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json s = read_json(stats);
    const std::size_t movement = s["straddle_pairs_movement"], search = s["straddle_pairs_search"];
    EXPECT_EQ(s["straddle_pairs"].get<std::size_t>(), movement + search) << test;
    EXPECT_EQ(movement > 0, test != "search") << test;
    EXPECT_EQ(search > 0, test == "search") << test;
    EXPECT_EQ(s["views"][0]["lines"]["feature"].get<std::size_t>(), 1u) << test;
  }
  const CliRun r = run_cli("draw " + scene + ":dome -o " + path("x.svg") + " --straddle best");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("--straddle"), std::string::npos) << r.out;
}

TEST_F(DrawCliTest, BadInputsExitTwoNamingTheProblemAndWriteNothing) {
  const std::string scene = write("scene.rf", "sphere ball 1\n");
  // Bad values of the data exit 2; option values out of range are usage errors (exit 1, as
  // every command's).
  struct Case {
    std::string args, message;
    int code = 2;
  };
  const Case cases[] = {
      {"--lines silhouette,contour", "unknown line kind 'contour'"},
      {"--camera eye=1,2", "'eye': expects three numbers"},
      {"--camera zoom=2", "'zoom': unknown key"},
      {"--camera 'eye=0,0,0;target=0,0,0'", "coincide"},
      {"--k-c 2", "--k-c", 1},
      {"--visibility xray", "--visibility", 1},
  };
  for (const Case& c : cases) {
    const CliRun r =
        run_cli("draw " + scene + ":ball -o " + path("x.svg") + " --count 500 " + c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_FALSE(std::filesystem::exists(path("x.svg"))) << c.args;
  }
  const CliRun r = run_cli("draw " + scene + ":ball -o " + path("x.pdf"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(".svg"), std::string::npos) << r.out;
}

TEST_F(DrawCliTest, SceneDrawReusesSavedParticlesAsTheCommandDoes) {
  // The scene saves its particles, draws from them (state=), and the command drawing from the
  // same saved particles with the same camera finds exactly the same lines.
  const std::string scene = write("scene.rf",
                                  "torus t 1 thickness=0.35 normal=0,1,0\n"
                                  "particles t count=1500 iterations=10 state=t_state.ply\n"
                                  "draw t scene.svg state=t_state.ply elevation=40 "
                                  "polylines=scene.json\n");
  CliRun r = run_cli("run " + scene + " --out " + dir_.string());
  ASSERT_EQ(r.code, 0) << r.out;
  r = run_cli("draw " + scene + ":t -o " + path("cli.svg") + " --particle-state " +
              path("t_state.ply") + " --elevation 40 --polylines " + path("cli.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json a = read_json(path("scene.json"));
  const nlohmann::json b = read_json(path("cli.json"));
  ASSERT_FALSE(a["lines"].empty());
  EXPECT_EQ(a, b);
  EXPECT_EQ(read_file(path("scene.svg")), read_file(path("cli.svg")));

  // Spreading options beside state= are refused at their token; so is a missing state file.
  const std::string bad = write("bad.rf",
                                "torus t 1 thickness=0.35\n"
                                "particles t count=500 state=s.ply\n"
                                "draw t x.svg state=s.ply count=200\n");
  r = run_cli("run " + bad + " --out " + dir_.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("count= spreads new particles"), std::string::npos) << r.out;
  const std::string missing = write("missing.rf", "torus t 1\ndraw t x.svg state=none.ply\n");
  r = run_cli("run " + missing + " --out " + dir_.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("missing.rf:2:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no such file"), std::string::npos) << r.out;
  EXPECT_EQ(count(r.out, "draw:"), 1U) << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("x.svg")));
}

}  // namespace
}  // namespace ramiform
