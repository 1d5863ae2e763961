// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform studio`'s server (apps/ramiform/studio, docs/studio_api.md), in process on a free
// loopback port, spoken to over raw sockets: authentication, Host/Origin checks, body limits,
// runs (objects, views, downloads, errors, the sandbox, cancel), param ranges, line drawings
// against the analytic silhouette of a sphere, and a seeded loop of hostile requests.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "studio/runs.h"
#include "studio/server.h"
#include "support/fixtures.h"
#include "support/glb_reader.h"

namespace ramiform::studio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

#ifdef RAMIFORM_TEST_SANITIZED
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

struct Reply {
  int status = 0;
  std::string head;  // status line and headers
  std::string body;
  [[nodiscard]] std::string header(const std::string& name) const {
    const std::regex re("\r\n" + name + ": ([^\r]*)", std::regex::icase);
    std::smatch m;
    return std::regex_search(head, m, re) ? m[1].str() : std::string();
  }
};

// Sends `raw` on a new connection and reads the answer (headers and Content-Length bytes, or
// until the server closes). `wait` false: closes right after sending (a cut-off request that
// the server would wait for).
Reply send_raw(int port, const std::string& raw, bool wait = true) {
  Reply reply;
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return reply;
  timeval tv{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return reply;
  }
  for (std::size_t at = 0; at < raw.size();) {
    const ssize_t n = ::send(fd, raw.data() + at, raw.size() - at, MSG_NOSIGNAL);
    if (n <= 0) break;
    at += static_cast<std::size_t>(n);
  }
  std::string in;
  char buf[65536];
  while (wait) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    in.append(buf, static_cast<std::size_t>(n));
    const std::size_t end = in.find("\r\n\r\n");
    if (end == std::string::npos) continue;
    static const std::regex length("\r\nContent-Length: (\\d+)", std::regex::icase);
    std::smatch m;
    const std::string head = in.substr(0, end);
    if (std::regex_search(head, m, length) && in.size() >= end + 4 + std::stoull(m[1].str())) {
      break;
    }
  }
  ::close(fd);
  const std::size_t end = in.find("\r\n\r\n");
  if (in.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) return reply;
  reply.status = std::stoi(in.substr(9, 3));
  reply.head = in.substr(0, end);
  reply.body = in.substr(end + 4);
  return reply;
}

class StudioTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = test::temp_dir("studio");
    out_ = root_ / "out";
    start();
  }
  // (Re)starts the server; `max_memory` is its --memory-budget (0: none).
  void start(std::uint64_t max_memory = 0) {
    if (server_) server_->stop();
    StudioOptions o;
    o.out_dir = out_;
    o.port = 0;
    o.threads = 2;
    o.demo_script = "sphere s 1\n";
    o.token = std::string(32, 'a');
    o.max_memory = max_memory;
    server_ = std::make_unique<StudioServer>(o);
    port_ = server_->start();
    host_ = "127.0.0.1:" + std::to_string(port_);
  }
  void TearDown() override {
    server_->stop();
    server_.reset();
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  // A request with the right Host and token (unless the headers say otherwise).
  Reply request(const std::string& method, const std::string& path, const std::string& body = "",
                const std::string& headers = "X-Ramiform-Token: " + std::string(32, 'a') +
                                             "\r\n") const {
    std::string raw = method + " " + path + " HTTP/1.1\r\nHost: " + host_ + "\r\n" + headers +
                      "Connection: close\r\n";
    if (!body.empty() || method == "POST") {
      raw += "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
             "\r\n";
    }
    return send_raw(port_, raw + "\r\n" + body);
  }

  std::string run(const std::string& script, const json& params = json::object()) const {
    const Reply r =
        request("POST", "/api/run", json{{"script", script}, {"params", params}}.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    return json::parse(r.body, nullptr, false).value("run", "");
  }

  // Polls the run until it is over (at most `seconds`).
  json wait(const std::string& id, double seconds = 60) const {
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
      const Reply r = request("GET", "/api/run/" + id);
      json j = json::parse(r.body, nullptr, false);
      if (r.status != 200 || j.is_discarded()) return j;
      if (j["state"] != "running") return j;
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > seconds) {
        return j;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  // Every file below root_ that is not below out_.
  std::vector<std::string> outside_out() const {
    std::vector<std::string> found;
    for (const auto& e : fs::recursive_directory_iterator(root_)) {
      const fs::path rel = e.path().lexically_relative(out_);
      if (!rel.empty() && *rel.begin() == "..") found.push_back(e.path().string());
    }
    return found;
  }

  fs::path root_, out_;
  std::unique_ptr<StudioServer> server_;
  int port_ = 0;
  std::string host_;
};

TEST_F(StudioTest, TokenHostAndOriginAreChecked) {
  EXPECT_EQ(request("GET", "/api/info", "", "").status, 403);
  EXPECT_EQ(
      request("GET", "/api/info", "", "X-Ramiform-Token: " + std::string(32, 'b') + "\r\n").status,
      403);
  const Reply info = request("GET", "/api/info");
  ASSERT_EQ(info.status, 200);
  const json j = json::parse(info.body);
  EXPECT_EQ(j["script"], "sphere s 1\n");
  EXPECT_EQ(j["script_name"], "studio.rf");
  bool has_param = false;
  for (const json& c : j["commands"]) {
    if (c["name"] == "param") {
      has_param = true;
      EXPECT_EQ(c["options"], json({"min", "max", "step"}));
    }
  }
  EXPECT_TRUE(has_param);
  // Another Host (DNS rebinding) or a foreign Origin: refused even with the token.
  const std::string token = "X-Ramiform-Token: " + std::string(32, 'a') + "\r\n";
  EXPECT_EQ(send_raw(port_, "GET /api/info HTTP/1.1\r\nHost: evil.example:" +
                                std::to_string(port_) + "\r\n" + token + "\r\n")
                .status,
            403);
  EXPECT_EQ(request("GET", "/api/info", "", token + "Origin: http://evil.example\r\n").status, 403);
  EXPECT_EQ(request("GET", "/api/info", "", token + "Origin: http://" + host_ + "\r\n").status,
            200);
  // The URL's token sets the cookie, which then authorizes alone.
  const Reply page = request("GET", "/?token=" + std::string(32, 'a'), "", "");
  ASSERT_EQ(page.status, 200);
  EXPECT_EQ(page.header("Set-Cookie"),
            "ramiform_studio=" + std::string(32, 'a') + "; HttpOnly; SameSite=Strict; Path=/");
  EXPECT_NE(page.body.find("<html"), std::string::npos);
  EXPECT_EQ(request("GET", "/?token=" + std::string(32, 'c'), "", "").status, 403);
  EXPECT_EQ(request("GET", "/index.html", "",
                    "Cookie: x=1; ramiform_studio=" + std::string(32, 'a') + "\r\n")
                .status,
            200);
  EXPECT_EQ(request("GET", "/index.html", "", "").status, 403);
  // No CORS header is ever sent.
  EXPECT_EQ(info.header("Access-Control-Allow-Origin"), "");
}

TEST_F(StudioTest, OversizedBodiesAre413) {
  EXPECT_EQ(request("POST", "/api/run", std::string((4 << 20) + 1, ' ')).status, 413);
  const std::string script(1 << 20, '#');
  EXPECT_EQ(request("POST", "/api/run", json{{"script", script + "#"}}.dump()).status, 413);
  EXPECT_EQ(request("GET", "/api/info").status, 200);
}

TEST_F(StudioTest, SphereRunGivesAWatertightMeshAndItsGlb) {
  const std::string id = run("sphere s 1\nsave_mesh s s.ply s.glb resolution=40\n");
  const json st = wait(id);
  ASSERT_EQ(st["state"], "done") << st.dump();
  EXPECT_EQ(st["shapes"], json({"s"}));
  ASSERT_EQ(st["objects"].size(), 1u) << st.dump();
  const json& o = st["objects"][0];
  EXPECT_EQ(o["kind"], "mesh");
  EXPECT_EQ(o["file"], "s.glb");
  EXPECT_EQ(o["preview"], false);
  EXPECT_EQ(o["stats"]["watertight"], true);
  const std::size_t vertices = o["stats"]["vertices"];
  EXPECT_GT(vertices, 100u);
  EXPECT_EQ(st["log"].size(), 2u);
  EXPECT_EQ(st["log"][1]["line"], 2);
  EXPECT_EQ(st["log"][1]["command"], "save_mesh");

  const Reply view = request("GET", o["view"].get<std::string>());
  ASSERT_EQ(view.status, 200);
  EXPECT_EQ(view.header("Content-Type"), "model/gltf-binary");
  ASSERT_GE(view.body.size(), 12u);
  EXPECT_EQ(view.body.substr(0, 4), "glTF");
  std::uint32_t length = 0;
  std::memcpy(&length, view.body.data() + 8, 4);
  EXPECT_EQ(length, view.body.size());
  const fs::path copy = root_ / "view.glb";
  std::ofstream(copy, std::ios::binary) << view.body;
  const test::Glb glb = test::read_glb(copy.string());
  const int position = glb.attribute(0, "POSITION");
  ASSERT_GE(position, 0);
  EXPECT_EQ(glb.json["accessors"][position]["count"], vertices);
  EXPECT_GE(glb.attribute(0, "NORMAL"), 0);

  // The download is the file in the run's directory, byte for byte.
  bool listed = false;
  for (const json& f : st["outputs"]) {
    if (f["path"] != "s.glb") continue;
    listed = true;
    const Reply file = request("GET", f["url"].get<std::string>());
    ASSERT_EQ(file.status, 200);
    EXPECT_NE(file.header("Content-Disposition").find("attachment"), std::string::npos);
    std::ifstream in(out_ / "runs" / id / "s.glb", std::ios::binary);
    const std::string disk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(file.body, disk);
    EXPECT_EQ(f["bytes"], disk.size());
  }
  EXPECT_TRUE(listed);
  EXPECT_EQ(request("GET", "/files/" + id + "/../../../etc/passwd").status, 404);
  EXPECT_EQ(request("GET", "/files/" + id + "/%2e%2e/%2e%2e/runs").status, 404);
  EXPECT_EQ(request("GET", "/files/" + id + "/nothere.ply").status, 404);
}

// A full run lists each mesh under "early" as soon as it is polygonized (before normals, bark
// UVs and files), with its script line, shape and counts, and serves it as a glb; the run's own
// objects hold the same surface. Drafts list none.
TEST_F(StudioTest, FullRunsListEachMeshEarlyDraftsDoNot) {
  const std::string script =
      "sphere s 1\nsave_mesh s s.glb resolution=40\nsphere t 0.5 center=3,0,0\n"
      "save_mesh t t.ply t.glb resolution=30\n";
  const json st = wait(run(script));
  ASSERT_EQ(st["state"], "done") << st.dump();
  ASSERT_EQ(st["early"].size(), 2u) << st.dump();
  ASSERT_EQ(st["objects"].size(), 2u) << st.dump();
  for (std::size_t k = 0; k < 2; ++k) {
    const json& e = st["early"][k];
    const json& o = st["objects"][k];
    EXPECT_EQ(e["id"], "e" + std::to_string(k));
    EXPECT_EQ(e["kind"], "mesh");
    EXPECT_EQ(e["shape"], k == 0 ? "s" : "t");
    EXPECT_EQ(e["line"], k == 0 ? 2 : 4);
    EXPECT_EQ(e["line"], o["line"]);
    EXPECT_EQ(e["stats"]["triangles"], o["stats"]["triangles"]);
    EXPECT_EQ(e["stats"]["vertices"], o["stats"]["vertices"]);
    const Reply view = request("GET", e["view"].get<std::string>());
    ASSERT_EQ(view.status, 200);
    EXPECT_EQ(view.header("Content-Type"), "model/gltf-binary");
    const fs::path copy = root_ / ("early" + std::to_string(k) + ".glb");
    std::ofstream(copy, std::ios::binary) << view.body;
    const test::Glb glb = test::read_glb(copy.string());
    const int position = glb.attribute(0, "POSITION");
    ASSERT_GE(position, 0);
    EXPECT_EQ(glb.json["accessors"][position]["count"], e["stats"]["vertices"]);
    EXPECT_GE(glb.attribute(0, "NORMAL"), 0);
    // The same surface as the run's object: the glb's bounds (+Y up) are the sphere's.
    const json& box = glb.json["accessors"][position];
    const double cx = k == 0 ? 0.0 : 3.0, r = k == 0 ? 1.0 : 0.5;
    EXPECT_NEAR(box["min"][0].get<double>(), cx - r, 0.05 * r);
    EXPECT_NEAR(box["max"][0].get<double>(), cx + r, 0.05 * r);
    EXPECT_NEAR(box["max"][1].get<double>(), r, 0.05 * r);
  }
  EXPECT_EQ(request("GET", "/api/run/" + st["run"].get<std::string>() + "/view/e2").status, 404);
  const Reply r = request("POST", "/api/run", json{{"script", script}, {"draft", true}}.dump());
  const json draft = wait(json::parse(r.body, nullptr, false).value("run", ""));
  ASSERT_EQ(draft["state"], "done") << draft.dump();
  EXPECT_TRUE(draft["early"].empty());
  // The next run freed the first one's early meshes: still listed, no longer served.
  const json first = wait(st["run"].get<std::string>());
  EXPECT_EQ(first["early"].size(), 2u);
  EXPECT_EQ(request("GET", st["early"][0]["view"].get<std::string>()).status, 404);
  EXPECT_FALSE(fs::exists(out_ / "cache" / st["run"].get<std::string>() / "e0.glb"));
}

TEST_F(StudioTest, NoSavedMeshGivesAPreviewOfTheLastShape) {
  const json st = wait(run("sphere a 1\nsphere b 0.5 center=2,0,0\n"));
  ASSERT_EQ(st["state"], "done") << st.dump();
  ASSERT_EQ(st["objects"].size(), 1u);
  EXPECT_EQ(st["objects"][0]["preview"], true);
  EXPECT_EQ(st["objects"][0]["name"], "b");
  EXPECT_EQ(st["objects"][0]["stats"]["watertight"], true);
}

// "draft": true runs the script as ScriptOptions::draft (the page's slider previews): the same
// sphere meshed at resolution 48 instead of 120, and a draw that writes nothing.
TEST_F(StudioTest, DraftRunsMeshCoarselyAndSayTheyAreDrafts) {
  const std::string script =
      "sphere s 1\nsave_mesh s s.glb resolution=120\ndraw s s.svg count=300\n";
  const auto triangles = [&](bool draft) {
    const Reply r = request("POST", "/api/run", json{{"script", script}, {"draft", draft}}.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    const json st = wait(json::parse(r.body, nullptr, false).value("run", ""));
    EXPECT_EQ(st["state"], "done") << st.dump();
    EXPECT_EQ(st["draft"], draft);
    std::size_t drawings = 0, mesh_triangles = 0;
    for (const json& o : st["objects"]) {
      if (o["kind"] == "drawing") ++drawings;
      if (o["kind"] == "mesh") {
        mesh_triangles = static_cast<std::size_t>(o["stats"]["triangles"].get<double>());
      }
    }
    EXPECT_EQ(drawings, draft ? 0u : 1u);
    return mesh_triangles;
  };
  const std::size_t full = triangles(false);
  const std::size_t draft = triangles(true);
  EXPECT_GT(draft, 0u);
  // Marching cubes triangle counts grow with the square of the resolution: (48 / 120)^2 = 0.16.
  EXPECT_LT(draft, full / 4);
  EXPECT_EQ(request("POST", "/api/run", R"({"script": "sphere s 1", "draft": "yes"})").status, 400);

  // Runs r1 (full) and r2 (draft) are on disk. Once RunManager::kMaxRuns newer runs came, both
  // are forgotten: the draft's directory is removed (a dragged slider makes many), the full
  // run's outputs stay.
  ASSERT_TRUE(fs::exists(out_ / "runs" / "r1" / "s.glb"));
  ASSERT_TRUE(fs::exists(out_ / "runs" / "r2" / "s.glb"));
  std::string last;
  for (std::size_t k = 0; k < RunManager::kMaxRuns; ++k) {
    const Reply r = request("POST", "/api/run", R"({"script": "sphere s 1", "draft": true})");
    ASSERT_EQ(r.status, 200) << r.body;
    last = json::parse(r.body, nullptr, false).value("run", "");
  }
  EXPECT_EQ(wait(last)["state"], "done");
  EXPECT_FALSE(fs::exists(out_ / "runs" / "r2"));
  EXPECT_TRUE(fs::exists(out_ / "runs" / "r1" / "s.glb"));
  EXPECT_EQ(request("GET", "/api/run/r2").status, 404);
}

TEST_F(StudioTest, ScriptErrorReportsLineAndColumn) {
  const json st = wait(run("sphere s 1\nblend s nothere u\n"));
  ASSERT_EQ(st["state"], "failed");
  EXPECT_EQ(st["error"]["line"], 2);
  EXPECT_EQ(st["error"]["column"], 9);
  EXPECT_NE(st["error"]["message"].get<std::string>().find("nothere"), std::string::npos);
}

TEST_F(StudioTest, OutputsOutsideTheRunDirectoryAreRefused) {
  const json st = wait(run("sphere s 1\nsave_mesh s ../outside.ply resolution=16\n"));
  ASSERT_EQ(st["state"], "failed");
  EXPECT_EQ(st["error"]["line"], 2);
  EXPECT_FALSE(fs::exists(out_ / "runs" / "outside.ply"));
  EXPECT_TRUE(outside_out().empty());
}

TEST_F(StudioTest, CancelStopsALongRunAndTheLatestRunWins) {
  std::string script = "sphere s 1\n";
  for (int i = 0; i < 3000; ++i) script += "save_mesh s s.ply resolution=48\n";
  const std::string id = run(script);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const Reply c = request("POST", "/api/run/" + id + "/cancel");
  ASSERT_EQ(c.status, 200);
  EXPECT_EQ(json::parse(c.body)["state"], "cancelled");
  const json st = wait(id, 5);
  EXPECT_EQ(st["state"], "cancelled");
  EXPECT_EQ(request("GET", "/api/info").status, 200);
  // A new run cancels the one still running.
  const std::string first = run(script);
  const std::string second = run("sphere s 1\nsave_mesh s s.ply resolution=16\n");
  EXPECT_EQ(wait(first, 5)["state"], "cancelled");
  EXPECT_EQ(wait(second)["state"], "done");
  EXPECT_EQ(request("POST", "/api/run/" + second + "/cancel").body, R"({"state":"done"})");
  EXPECT_EQ(request("GET", "/api/run/r999999").status, 404);
}

TEST_F(StudioTest, ParamsReportTheirRanges) {
  const std::string script =
      "param n 16 min=8 max=64 step=8\nparam r 0.5\nsphere s $r\nsave_mesh s s.ply resolution=$n\n";
  const json st = wait(run(script, {{"r", "0.7"}, {"n", 24}}));
  ASSERT_EQ(st["state"], "done") << st.dump();
  const json expected = json::parse(
      R"([{"name":"n","value":"24","min":8,"max":64,"step":8},{"name":"r","value":"0.7"}])");
  EXPECT_EQ(st["params"], expected);
  EXPECT_EQ(wait(run(script, {{"nope", "1"}}))["state"], "failed");
  const json bad = wait(run("param n 3 min=5 max=1\n"));
  EXPECT_EQ(bad["state"], "failed");
  EXPECT_EQ(bad["error"]["line"], 1);
  EXPECT_EQ(bad["error"]["column"], 21);  // the value of max=
}

// The silhouette of a sphere of radius 1 seen from distance d is the circle of angular radius
// asin(1/d): in the image plane at unit depth, radius 1/sqrt(d^2 - 1). The camera is given in
// the page's +Y-up frame, the sphere is centred at z = 1 of the library's +Z-up frame, so the
// circle lands in the frame's centre only when the server turns the camera into model axes.
TEST_F(StudioTest, LinesSilhouetteOfASphereIsTheAnalyticCircle) {
  const std::string id = run("sphere s 1 center=0,0,1\n");
  ASSERT_EQ(wait(id)["state"], "done");
  const int width = 480, height = 360;
  const double fov = 30, d = 5;
  const json body = {{"run", id},
                     {"shape", "s"},
                     {"camera",
                      {{"eye", {0, 1, d}},
                       {"target", {0, 1, 0}},
                       {"up", {0, 1, 0}},
                       {"fov", fov},
                       {"width", width},
                       {"height", height}}},
                     {"lines", {"silhouette"}},
                     {"count", 3000}};
  const Reply r = request("POST", "/api/lines", body.dump());
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.header("Content-Type"), "image/svg+xml");
  EXPECT_FALSE(r.header("X-Ramiform-Seconds").empty());
  const std::size_t g = r.body.find("<g id=\"silhouette\"");
  ASSERT_NE(g, std::string::npos);
  const std::string group = r.body.substr(g, r.body.find("</g>", g) - g);
  // Path coordinates are camera units (y up, written flipped); pixels = units * height / (2T).
  const double t = std::tan(fov * M_PI / 360);
  const double px = height / (2 * t);
  const double expected = px / std::sqrt(d * d - 1);
  const std::regex pair(R"(([-0-9.e]+) ([-0-9.e]+))");
  std::size_t points = 0;
  std::set<int> octants;
  double worst = 0;
  for (std::sregex_iterator it(group.begin(), group.end(), pair), end; it != end; ++it) {
    const double x = std::stod((*it)[1]) * px, y = std::stod((*it)[2]) * px;
    worst = std::max(worst, std::abs(std::hypot(x, y) - expected));
    octants.insert(static_cast<int>(std::floor((std::atan2(y, x) + M_PI) / (M_PI / 4))) % 8);
    ++points;
  }
  EXPECT_GT(points, 30u);
  EXPECT_EQ(octants.size(), 8u);
  EXPECT_LE(worst, 2.0) << "pixels off the circle of radius " << expected;
  // A second camera reuses the particles; unknown runs and shapes are 404, bad cameras 400.
  json moved = body;
  moved["camera"]["eye"] = {d, 1, 0};
  EXPECT_EQ(request("POST", "/api/lines", moved.dump()).status, 200);
  json unknown = body;
  unknown["shape"] = "t";
  EXPECT_EQ(request("POST", "/api/lines", unknown.dump()).status, 404);
  json bad = body;
  bad["camera"]["eye"] = {0, 1, 0};  // at the target
  EXPECT_EQ(request("POST", "/api/lines", bad.dump()).status, 400);
  // The quick drawing (hidden lines by the particles' disks) draws the same silhouette.
  json quick = body;
  quick["visibility"] = "surfels";
  const Reply q = request("POST", "/api/lines", quick.dump());
  ASSERT_EQ(q.status, 200) << q.body;
  EXPECT_NE(q.body.find("<g id=\"silhouette\""), std::string::npos);
  quick["visibility"] = "zbuffer";
  const Reply qb = request("POST", "/api/lines", quick.dump());
  EXPECT_EQ(qb.status, 400);
  EXPECT_EQ(json::parse(qb.body)["error"], "\"visibility\" must be \"rays\" or \"surfels\"");
  // The page's progress bar: no drawing under way, the last stage was the camera's lines.
  const Reply p = request("GET", "/api/lines/progress");
  ASSERT_EQ(p.status, 200) << p.body;
  const json progress = json::parse(p.body);
  EXPECT_EQ(progress["busy"], false) << p.body;
  EXPECT_EQ(progress["stage"], "lines: this camera") << p.body;
}

TEST_F(StudioTest, LineDrawingsKeepToTheMemoryBudget) {
  // `--memory-budget` 16 MB: 200,000 particles need at least 22.4 MB (state and seed state, 112
  // bytes each) and are refused before any work; 3,000 are drawn.
  start(16'000'000);
  const std::string id = run("sphere s 1\n");
  ASSERT_EQ(wait(id)["state"], "done");
  json body = {{"run", id},
               {"shape", "s"},
               {"camera", {{"eye", {0, 0, 5}}, {"target", {0, 0, 0}}}},
               {"lines", {"silhouette"}},
               {"count", 200000}};
  const Reply refused = request("POST", "/api/lines", body.dump());
  EXPECT_EQ(refused.status, 400);
  EXPECT_NE(refused.body.find("200000 surface particles need at least 22.4 MB of memory, more "
                              "than the budget of 16 MB"),
            std::string::npos)
      << refused.body;
  EXPECT_EQ(json::parse(request("GET", "/api/lines/progress").body)["busy"], false);
  body["count"] = 3000;
  const Reply drawn = request("POST", "/api/lines", body.dump());
  EXPECT_EQ(drawn.status, 200) << drawn.body;
  EXPECT_NE(drawn.body.find("<g id=\"silhouette\""), std::string::npos);
}

// Bounded, seeded garbage at every endpoint: random methods, paths, headers, bodies, JSON,
// huge Content-Lengths, cut-off requests. The server must keep answering and write nothing
// outside OUT.
TEST_F(StudioTest, HostileRequestsLeaveTheServerAnsweringAndNothingOutsideOut) {
  std::mt19937_64 rng(20261206);
  const auto pick = [&rng](const std::vector<std::string>& v) {
    return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
  };
  const auto chance = [&rng](double p) { return std::uniform_real_distribution<>(0, 1)(rng) < p; };
  const auto garbage = [&rng](std::size_t max) {
    std::string s(std::uniform_int_distribution<std::size_t>(0, max)(rng), ' ');
    for (char& c : s) c = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
    return s;
  };
  // One finished run that requests can name.
  const std::string id = run("sphere s 1\nsave_mesh s s.ply resolution=16\n");
  ASSERT_EQ(wait(id)["state"], "done");
  const std::vector<std::string> methods = {"GET",     "POST",  "PUT",  "DELETE", "HEAD",
                                            "OPTIONS", "PATCH", "GE T", "",       "\x01\x02"};
  const std::vector<std::string> paths = {"/",
                                          "/?token=" + std::string(32, 'a'),
                                          "/index.html",
                                          "/assets/x.js",
                                          "/api/info",
                                          "/api/run",
                                          "/api/run/" + id,
                                          "/api/run/" + id + "/cancel",
                                          "/api/run/" + id + "/view/o0",
                                          "/api/run/" + id + "/view/o9",
                                          "/files/" + id + "/s.ply",
                                          "/files/" + id + "/../../x",
                                          "/files/" + id + "/%2e%2e/%2e%2e/%2e%2e/x",
                                          "/api/lines",
                                          "/api/run/r0",
                                          "//",
                                          "*",
                                          "/api/run/" + std::string(3000, '9'),
                                          "/files/" + id + "/" + std::string(5000, 'a')};
  const std::vector<std::string> scripts = {
      "sphere s 1\nsave_mesh s ../escape.ply resolution=8\n",
      "sphere s 1\nsave_mesh s " + (root_ / "abs.ply").string() + " resolution=8\n",
      "sphere s 1\nsave_skeleton s ../../x.json\n",
      "param\n",
      "sphere s $nope\n",
      "sphere s 1e308\n",
      "\"unterminated\n",
      std::string("\xef\xbb\xbfsphere s 1\n"),
      "sphere s 1\nsave_mesh s s.ply resolution=8\n"};
  const std::vector<std::string> bodies = {
      "{",
      "[]",
      "null",
      "{\"script\": 5}",
      "{\"script\": \"sphere s 1\", \"params\": [1]}",
      "{\"run\": \"" + id + "\", \"shape\": \"s\", \"camera\": {\"eye\": [1e308, 0, 0]}}",
      "{\"run\": \"" + id + "\", \"shape\": \"s\", \"camera\": {}, \"count\": -1}",
      "{\"run\": \"" + id + "\", \"shape\": \"s\", \"camera\": {\"fov\": 0}, \"lines\": [\"x\"]}",
      "{\"run\": \"" + id + "\", \"shape\": \"s\", \"camera\": {\"width\": 1e9}}",
      "{\"params\": {\"a\": {\"b\": 1}}, \"script\": \"\"}",
      "\"\\ud800\"",
      "{\"a\":" + std::string(2000, '[')};
  const int rounds = kSanitized ? 300 : 1500;
  for (int i = 0; i < rounds; ++i) {
    std::string method = pick(methods);
    std::string path = pick(paths);
    if (chance(0.1)) path += garbage(20);
    std::string raw = method + " " + path + " HTTP/1.1\r\n";
    if (!chance(0.1))
      raw += "Host: " + (chance(0.9) ? host_ : std::string("evil.example")) + "\r\n";
    if (chance(0.85))
      raw += "X-Ramiform-Token: " + std::string(32, chance(0.9) ? 'a' : 'b') + "\r\n";
    if (chance(0.1)) raw += "Origin: http://" + (chance(0.5) ? host_ : "evil.example") + "\r\n";
    if (chance(0.1)) raw += "Cookie: ramiform_studio=" + garbage(40) + "\r\n";
    if (chance(0.1)) raw += garbage(60) + "\r\n";
    std::string body;
    const double kind = std::uniform_real_distribution<>(0, 1)(rng);
    if (kind < 0.3) {
      body = json{{"script", pick(scripts)}, {"params", json::object()}}.dump();
    } else if (kind < 0.6) {
      body = pick(bodies);
    } else if (kind < 0.8) {
      body = garbage(300);
    }
    const double length = std::uniform_real_distribution<>(0, 1)(rng);
    bool complete = true;  // the server has all it waits for
    if (length < 0.7) {
      raw += "Content-Length: " + std::to_string(body.size()) + "\r\n";
    } else if (length < 0.8) {
      raw += "Content-Length: 99999999999999999999\r\n";
    } else if (length < 0.9) {
      raw += "Content-Length: " + std::to_string(body.size() + 1000) + "\r\n";  // never sent
      complete = false;
    } else {
      raw += "Transfer-Encoding: chunked\r\n";
      complete = false;
    }
    raw += "Connection: close\r\n\r\n" + body;
    if (chance(0.15)) {
      raw.resize(std::uniform_int_distribution<std::size_t>(0, raw.size())(rng));
      complete = false;
    }
    const Reply r = send_raw(port_, raw, complete);
    if (r.status != 0) {
      EXPECT_TRUE(r.status < 500 || r.status == 501 || r.status == 505)
          << r.status << " " << r.body;
    }
  }
  const Reply info = request("GET", "/api/info");
  EXPECT_EQ(info.status, 200);
  EXPECT_EQ(request("GET", "/api/run/" + id).status, 200);
  EXPECT_TRUE(outside_out().empty());
}

}  // namespace
}  // namespace ramiform::studio
