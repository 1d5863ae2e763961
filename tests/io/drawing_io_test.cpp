// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/drawing_io.h"

#include <gtest/gtest.h>

#include <cairo/cairo.h>

#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"

namespace ramiform {
namespace {

using io_test::TempDir;

// ---- a tiny XML reader: enough to check that the SVG is well formed and to read it back ----

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::vector<Element> children;
};

// Parses `text` (one root element after an optional <?xml ...?> declaration); fails the test on
// unbalanced or malformed tags.
Element parse_xml(const std::string& text) {
  std::size_t pos = 0;
  auto skip_space = [&] {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos])) != 0) ++pos;
  };
  skip_space();
  if (text.compare(pos, 5, "<?xml") == 0) {
    pos = text.find("?>", pos);
    EXPECT_NE(pos, std::string::npos);
    pos += 2;
  }
  std::vector<Element> stack;
  Element root;
  bool have_root = false;
  while (true) {
    skip_space();
    if (pos >= text.size()) break;
    if (text[pos] != '<') {
      ADD_FAILURE() << "text outside tags at " << pos;
      return root;
    }
    const std::size_t close = text.find('>', pos);
    if (close == std::string::npos) {
      ADD_FAILURE() << "unclosed tag at " << pos;
      return root;
    }
    std::string tag = text.substr(pos + 1, close - pos - 1);
    pos = close + 1;
    if (!tag.empty() && tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back().name != name) {
        ADD_FAILURE() << "end tag </" << name << "> does not match";
        return root;
      }
      Element done = std::move(stack.back());
      stack.pop_back();
      if (stack.empty()) {
        EXPECT_FALSE(have_root) << "two root elements";
        root = std::move(done);
        have_root = true;
      } else {
        stack.back().children.push_back(std::move(done));
      }
      continue;
    }
    const bool self_closing = !tag.empty() && tag.back() == '/';
    if (self_closing) tag.pop_back();
    Element e;
    std::size_t k = 0;
    while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k])) == 0) ++k;
    e.name = tag.substr(0, k);
    while (true) {
      while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k])) != 0) ++k;
      if (k >= tag.size()) break;
      const std::size_t eq = tag.find('=', k);
      if (eq == std::string::npos || eq + 1 >= tag.size() || tag[eq + 1] != '"') {
        ADD_FAILURE() << "malformed attribute in <" << tag << ">";
        return root;
      }
      const std::size_t end = tag.find('"', eq + 2);
      if (end == std::string::npos) {
        ADD_FAILURE() << "unterminated attribute in <" << tag << ">";
        return root;
      }
      const std::string name = tag.substr(k, eq - k);
      EXPECT_EQ(e.attributes.count(name), 0u) << "attribute " << name << " twice";
      e.attributes[name] = tag.substr(eq + 2, end - eq - 2);
      k = end + 1;
    }
    if (self_closing) {
      if (stack.empty()) {
        root = std::move(e);
        have_root = true;
      } else {
        stack.back().children.push_back(std::move(e));
      }
    } else {
      stack.push_back(std::move(e));
    }
  }
  EXPECT_TRUE(stack.empty()) << "unclosed elements";
  EXPECT_TRUE(have_root);
  return root;
}

// The vertices of a path's d attribute "M x y L x y x y ... [Z]", SVG y turned back up.
std::vector<Vec2> path_points(const std::string& d, bool& closed) {
  std::vector<Vec2> out;
  std::vector<double> numbers;
  closed = false;
  std::size_t pos = 0;
  while (pos < d.size()) {
    const std::size_t end = std::min(d.find(' ', pos), d.size());
    const std::string token = d.substr(pos, end - pos);
    pos = end + 1;
    if (token.empty()) continue;
    if (token == "M" || token == "L") continue;
    if (token == "Z") {
      closed = true;
      continue;
    }
    double v = 0;
    EXPECT_EQ(parse_number(token, v), NumberStatus::kOk) << token;
    numbers.push_back(v);
  }
  EXPECT_EQ(numbers.size() % 2, 0u);
  for (std::size_t i = 0; i + 1 < numbers.size(); i += 2)
    out.emplace_back(numbers[i], -numbers[i + 1]);
  return out;
}

std::string read_text(const std::string& path) { return io_test::read_bytes(path); }

Polyline circle(LineKind kind, const Vec3& c, double r, int n) {
  Polyline line;
  line.kind = kind;
  line.closed = true;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    line.points.push_back(c + r * Vec3(std::cos(a), std::sin(a), 0.1 * std::sin(3 * a)));
  }
  return line;
}

Polyline segment(LineKind kind, const Vec3& a, const Vec3& b, int n) {
  Polyline line;
  line.kind = kind;
  for (int k = 0; k <= n; ++k) line.points.push_back(a + (b - a) * (static_cast<double>(k) / n));
  return line;
}

// A drawing of every kind: a closed silhouette, a suggestive contour with its middle hidden and
// a feature line, all classified.
LineDrawing sample_drawing() {
  LineDrawing d;
  d.camera.eye = Vec3(0.3, 0.2, 5);
  d.camera.target = Vec3(0, 0, 0);
  d.camera.fov_deg = 30;
  d.lines.push_back(circle(LineKind::kSilhouette, Vec3::Zero(), 0.8, 120));
  d.lines.push_back(
      segment(LineKind::kSuggestive, Vec3(-0.5, -0.3, 0.2), Vec3(0.5, -0.2, 0.1), 30));
  d.lines.push_back(segment(LineKind::kFeature, Vec3(-0.2, 0.4, 0.3), Vec3(0.3, 0.5, -0.2), 20));
  for (Polyline& line : d.lines) line.visible.assign(line.points.size(), 1);
  for (std::size_t i = 10; i < 20; ++i) d.lines[1].visible[i] = 0;
  return d;
}

std::size_t count_strokes(const std::vector<Stroke>& strokes, LineKind kind, bool hidden) {
  std::size_t n = 0;
  for (const Stroke& s : strokes) n += s.kind == kind && s.hidden == hidden ? 1 : 0;
  return n;
}

TEST(DrawingIo, SvgIsWellFormedWithOneGroupPerKind) {
  TempDir dir;
  const LineDrawing d = sample_drawing();
  const std::vector<Stroke> strokes = join_strokes(d, 0.0);
  for (bool show_hidden : {false, true}) {
    DrawingStyle style;
    style.show_hidden = show_hidden;
    style.white_background = show_hidden;
    const std::string path = dir.file("d.svg");
    write_drawing_svg(path, d, style);
    const Element svg = parse_xml(read_text(path));
    EXPECT_EQ(svg.name, "svg");
    EXPECT_EQ(svg.attributes.at("xmlns"), "http://www.w3.org/2000/svg");
    EXPECT_EQ(svg.attributes.at("version"), "1.1");
    EXPECT_EQ(svg.attributes.at("width"), "800");
    EXPECT_EQ(svg.attributes.at("height"), "800");
    std::vector<std::string> ids;
    for (const Element& g : svg.children) {
      if (g.name == "rect") {
        EXPECT_TRUE(show_hidden);
        continue;
      }
      ASSERT_EQ(g.name, "g");
      ids.push_back(g.attributes.at("id"));
      EXPECT_EQ(g.attributes.at("fill"), "none");
      EXPECT_EQ(g.attributes.at("stroke-linecap"), "round");
      EXPECT_EQ(g.attributes.at("stroke-linejoin"), "round");
      const bool hidden = ids.back() == "hidden";
      EXPECT_EQ(g.attributes.count("stroke-dasharray"), hidden ? 1u : 0u);
      std::size_t expected = 0;
      for (const Stroke& s : strokes) {
        expected += hidden ? (s.hidden ? 1 : 0)
                           : (!s.hidden && line_kind_name(s.kind) == ids.back() ? 1 : 0);
      }
      EXPECT_EQ(g.children.size(), expected) << ids.back();
      for (const Element& p : g.children) EXPECT_EQ(p.name, "path");
    }
    const std::vector<std::string> want =
        show_hidden ? std::vector<std::string>{"hidden", "silhouette", "suggestive", "feature"}
                    : std::vector<std::string>{"silhouette", "suggestive", "feature"};
    EXPECT_EQ(ids, want);
  }
  // The strokes: the closed silhouette whole, the suggestive contour in two visible runs and
  // one hidden run, the feature line whole.
  EXPECT_EQ(count_strokes(strokes, LineKind::kSilhouette, false), 1u);
  EXPECT_EQ(count_strokes(strokes, LineKind::kSuggestive, false), 2u);
  EXPECT_EQ(count_strokes(strokes, LineKind::kSuggestive, true), 1u);
  EXPECT_EQ(count_strokes(strokes, LineKind::kFeature, false), 1u);
}

TEST(DrawingIo, SvgCoordinatesAreTheProjectedPoints) {
  TempDir dir;
  const LineDrawing d = sample_drawing();
  const std::string path = dir.file("d.svg");
  write_drawing_svg(path, d);
  const Element svg = parse_xml(read_text(path));
  // viewBox: the frame, y flipped.
  const double t = std::tan(15 * std::numbers::pi / 180);
  double box[4];
  {
    const std::string& vb = svg.attributes.at("viewBox");
    std::size_t pos = 0;
    for (double& v : box) {
      const std::size_t end = std::min(vb.find(' ', pos), vb.size());
      ASSERT_EQ(parse_number(vb.substr(pos, end - pos), v), NumberStatus::kOk);
      pos = end + 1;
    }
  }
  EXPECT_DOUBLE_EQ(box[0], -t);
  EXPECT_DOUBLE_EQ(box[1], -t);
  EXPECT_DOUBLE_EQ(box[2], 2 * t);
  EXPECT_DOUBLE_EQ(box[3], 2 * t);
  // The stroke widths: pixels converted to camera units (800 pixels across 2 t).
  EXPECT_NEAR(std::stod(svg.children[0].attributes.at("stroke-width")), 2.0 * 2 * t / 800, 1e-12);
  // The silhouette's path is the circle, point by point: 5e-7 is half the coordinates' step
  // (1e-6, the largest power of ten at most 1e-5 of the frame's height 2 t = 0.54).
  const CameraFrame frame = camera_frame(d.camera);
  const Element& sil = svg.children[0];
  ASSERT_EQ(sil.attributes.at("id"), "silhouette");
  ASSERT_EQ(sil.children.size(), 1u);
  bool closed = false;
  const std::vector<Vec2> pts = path_points(sil.children[0].attributes.at("d"), closed);
  EXPECT_TRUE(closed);
  ASSERT_EQ(pts.size(), d.lines[0].points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Projected p = project(d.camera, frame, d.lines[0].points[i]);
    EXPECT_NEAR(pts[i].x(), p.x, 5e-7 + 1e-15);
    EXPECT_NEAR(pts[i].y(), p.y, 5e-7 + 1e-15);
  }
  // Every number is short: at most 6 decimals.
  const std::string& text = sil.children[0].attributes.at("d");
  std::size_t pos = 0;
  while ((pos = text.find('.', pos)) != std::string::npos) {
    std::size_t digits = 0;
    while (++pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos])) != 0)
      ++digits;
    EXPECT_LE(digits, 6u);
  }
  // The suggestive contour's visible runs end at the midpoints of the segments where the
  // visibility changes.
  const Element& sug = svg.children[1];
  ASSERT_EQ(sug.children.size(), 2u);
  const Polyline& line = d.lines[1];
  const Projected m0 = project(d.camera, frame, 0.5 * (line.points[9] + line.points[10]));
  const Projected m1 = project(d.camera, frame, 0.5 * (line.points[19] + line.points[20]));
  std::vector<Vec2> ends;
  for (const Element& p : sug.children) {
    const std::vector<Vec2> q = path_points(p.attributes.at("d"), closed);
    EXPECT_FALSE(closed);
    ends.push_back(q.front());
    ends.push_back(q.back());
  }
  auto near_any = [&](const Projected& m) {
    for (const Vec2& e : ends) {
      if ((e - Vec2(m.x, m.y)).norm() < 1e-6) return true;
    }
    return false;
  };
  EXPECT_TRUE(near_any(m0));
  EXPECT_TRUE(near_any(m1));
}

TEST(DrawingIo, JoinStrokesJoinsRunsThatShareAnEnd) {
  LineDrawing d;  // the default camera: eye (0, 0, 5) looking at the origin
  // A: x from 0 to 0.2; B: x from 0.4 back to 0.2 (reversed, sharing A's tail); C: x from -0.3
  // to 0, hidden at its start, its visible run ending at A's head; F: a feature line sharing
  // A's tail, a different kind.
  d.lines.push_back(segment(LineKind::kSilhouette, Vec3(0, 0, 0), Vec3(0.2, 0, 0), 2));
  d.lines.push_back(segment(LineKind::kSilhouette, Vec3(0.4, 0, 0), Vec3(0.2, 0, 0), 2));
  Polyline c = segment(LineKind::kSilhouette, Vec3(-0.3, 0, 0), Vec3(0, 0, 0), 3);
  c.visible = {0, 0, 1, 1};
  d.lines.push_back(c);
  d.lines.push_back(segment(LineKind::kFeature, Vec3(0.2, 0, 0), Vec3(0.2, 0.3, 0), 3));
  const std::vector<Stroke> strokes = join_strokes(d, 1e-9);
  ASSERT_EQ(strokes.size(), 3u);
  const Stroke& joined = strokes[0];
  EXPECT_EQ(joined.kind, LineKind::kSilhouette);
  EXPECT_FALSE(joined.hidden);
  EXPECT_FALSE(joined.closed);
  // x/5 in camera units: -0.15 (the midpoint where C turns visible) ... 0.4.
  const std::vector<double> xs = {-0.15, -0.1, 0, 0.1, 0.2, 0.3, 0.4};
  ASSERT_EQ(joined.points.size(), xs.size());
  const bool forward = joined.points.front().x() < joined.points.back().x();
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const Vec2& p = joined.points[forward ? i : xs.size() - 1 - i];
    EXPECT_NEAR(p.x(), xs[i] / 5, 1e-15);
    EXPECT_NEAR(p.y(), 0, 1e-15);
  }
  EXPECT_EQ(strokes[1].kind, LineKind::kSilhouette);
  EXPECT_TRUE(strokes[1].hidden);
  ASSERT_EQ(strokes[1].points.size(), 3u);
  EXPECT_EQ(strokes[2].kind, LineKind::kFeature);
  EXPECT_EQ(strokes[2].points.size(), 4u);
  // Same input, same output.
  const std::vector<Stroke> again = join_strokes(d, 1e-9);
  ASSERT_EQ(again.size(), strokes.size());
  for (std::size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].points, strokes[i].points);
  // Four open sides of a square joined into one closed path.
  LineDrawing sq;
  const Vec3 corner[4] = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0)};
  for (int k = 0; k < 4; ++k) {
    // Every other side reversed.
    sq.lines.push_back(k % 2 == 0 ? segment(LineKind::kFeature, corner[k], corner[(k + 1) % 4], 1)
                                  : segment(LineKind::kFeature, corner[(k + 1) % 4], corner[k], 1));
  }
  const std::vector<Stroke> square = join_strokes(sq, 1e-9);
  ASSERT_EQ(square.size(), 1u);
  EXPECT_TRUE(square[0].closed);
  EXPECT_EQ(square[0].points.size(), 4u);
  // Ends further apart than the tolerance stay apart: one corner opened by 0.01 (0.002 in
  // camera units) leaves one open path.
  sq.lines[1].points[0].x() += 0.01;
  const std::vector<Stroke> opened = join_strokes(sq, 1e-4);
  ASSERT_EQ(opened.size(), 1u);
  EXPECT_FALSE(opened[0].closed);
  EXPECT_EQ(opened[0].points.size(), 5u);
  const std::vector<Stroke> closed = join_strokes(sq, 0.01);
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_TRUE(closed[0].closed);
  EXPECT_EQ(closed[0].points.size(), 4u);
  // Two runs of different visibility never join.
  LineDrawing two;
  two.lines.push_back(segment(LineKind::kFeature, Vec3(0, 0, 0), Vec3(0.2, 0, 0), 2));
  two.lines.push_back(segment(LineKind::kFeature, Vec3(0.2, 0, 0), Vec3(0.4, 0, 0), 2));
  two.lines[1].visible = {0, 0, 0};
  EXPECT_EQ(join_strokes(two, 1e-9).size(), 2u);
  EXPECT_THROW((void)join_strokes(sq, -1), InvalidArgument);
}

TEST(DrawingIo, ClosedLineHiddenAcrossItsSeam) {
  // A closed line whose first and last points are hidden: one hidden run across the seam.
  LineDrawing d;
  d.lines.push_back(circle(LineKind::kSilhouette, Vec3::Zero(), 0.5, 40));
  d.lines[0].visible.assign(40, 1);
  for (int i : {0, 1, 2, 37, 38, 39}) d.lines[0].visible[static_cast<std::size_t>(i)] = 0;
  const std::vector<Stroke> s = join_strokes(d, 0.0);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_FALSE(s[0].hidden);
  EXPECT_EQ(s[0].points.size(), 34u + 2);  // points 3..36 and the two midpoints
  EXPECT_TRUE(s[1].hidden);
  EXPECT_EQ(s[1].points.size(), 6u + 2);
  EXPECT_FALSE(s[0].closed);
  // The hidden run goes 37, 38, 39, 0, 1, 2 (with the midpoints at its ends).
  const CameraFrame f = camera_frame(d.camera);
  const Projected p39 = project(d.camera, f, d.lines[0].points[39]);
  const Projected p0 = project(d.camera, f, d.lines[0].points[0]);
  EXPECT_EQ(s[1].points[3], Vec2(p39.x, p39.y));
  EXPECT_EQ(s[1].points[4], Vec2(p0.x, p0.y));
}

TEST(DrawingIo, PointsBehindTheEyeCutTheirLine) {
  // The default eye is at z = 5 looking down -z: points at z >= 5 are not in front of it.
  LineDrawing d;
  d.lines.push_back(segment(LineKind::kFeature, Vec3(0.1, 0, 0), Vec3(0.1, 0, 9), 9));
  d.lines.push_back(segment(LineKind::kFeature, Vec3(0.7, 0, 9), Vec3(0.7, 0, 0), 9));
  const std::vector<Stroke> s = join_strokes(d, 0.0);
  ASSERT_EQ(s.size(), 2u);
  for (const Stroke& st : s) {
    EXPECT_EQ(st.points.size(), 5u);  // z = 0 .. 4
    for (const Vec2& p : st.points) EXPECT_TRUE(std::isfinite(p.x()) && std::isfinite(p.y()));
  }
}

// The colour of pixel (x, y) of an RGB24 cairo surface.
Rgb pixel(cairo_surface_t* s, int x, int y) {
  const unsigned char* row =
      cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s);
  std::uint32_t v = 0;
  std::memcpy(&v, row + 4 * x, 4);
  return {static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
          static_cast<std::uint8_t>(v)};
}

TEST(DrawingIo, PngHasItsSizeAndDarkPixelsOnTheLines) {
  TempDir dir;
  LineDrawing d;
  d.camera.aspect = 2;
  // A horizontal silhouette at y = 0.1 (camera units 0.02), visible; a feature line at
  // y = -0.3, hidden; both run out of the frame on either side (x = ±3: ±0.6 camera units,
  // the frame ends at ±0.54).
  d.lines.push_back(segment(LineKind::kSilhouette, Vec3(-3, 0.1, 0), Vec3(3, 0.1, 0), 10));
  d.lines.push_back(segment(LineKind::kFeature, Vec3(-3, -0.3, 0), Vec3(3, -0.3, 0), 10));
  d.lines[0].visible.assign(11, 1);
  d.lines[1].visible.assign(11, 0);
  DrawingStyle style;
  style.width = 300;
  style.silhouette.width = 3;
  style.hidden.dash = 0;
  style.hidden.width = 3;
  const double t = std::tan(15 * std::numbers::pi / 180);
  const double scale = 75 / t;  // pixels per camera unit: 75 pixels for tan(fov/2)
  auto row_of = [&](double y_model) {
    return static_cast<int>(std::floor(75 - scale * y_model / 5));
  };
  for (bool show_hidden : {false, true}) {
    style.show_hidden = show_hidden;
    const std::string path = dir.file("d.png");
    write_drawing_png(path, d, style);
    const std::string bytes = io_test::read_bytes(path);
    ASSERT_GT(bytes.size(), 33u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    auto be32 = [&](std::size_t at) {
      return (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at])) << 24) |
             (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
             (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 8) |
             static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 3]));
    };
    EXPECT_EQ(bytes.substr(12, 4), "IHDR");
    EXPECT_EQ(be32(16), 300u);
    EXPECT_EQ(be32(20), 150u);
    cairo_surface_t* img = cairo_image_surface_create_from_png(path.c_str());
    ASSERT_EQ(cairo_surface_status(img), CAIRO_STATUS_SUCCESS);
    ASSERT_EQ(cairo_image_surface_get_width(img), 300);
    ASSERT_EQ(cairo_image_surface_get_height(img), 150);
    cairo_surface_flush(img);
    const int on = row_of(0.1), hidden_row = row_of(-0.3);
    for (int x : {2, 40, 150, 260, 297}) {
      const Rgb p = pixel(img, x, on);
      EXPECT_LT(p.r + p.g + p.b, 3 * 60) << x;
      const Rgb blank = pixel(img, x, on + 12);
      EXPECT_EQ(blank.r + blank.g + blank.b, 3 * 255) << x;
      const Rgb h = pixel(img, x, hidden_row);
      if (show_hidden) {
        EXPECT_LT(h.r, 200) << x;
        EXPECT_GT(h.r, 100) << x;  // grey, not black
      } else {
        EXPECT_EQ(h.r + h.g + h.b, 3 * 255) << x;
      }
    }
    cairo_surface_destroy(img);
  }
}

TEST(DrawingIo, JsonRoundTripsExactly) {
  TempDir dir;
  LineDrawing d = sample_drawing();
  d.camera.fov_deg = 1.0 / 3.0 * 100;
  d.camera.aspect = 4.0 / 3.0;
  d.lines[2].points[3] = Vec3(1.0 / 3.0, 1e-300, std::numbers::pi);
  d.lines[2].visible.clear();  // not classified
  const std::string path = dir.file("lines.json");
  write_polylines_json(path, d);
  const nlohmann::json j = nlohmann::json::parse(read_text(path));
  auto vec = [](const nlohmann::json& a) {
    return Vec3(a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>());
  };
  EXPECT_EQ(vec(j["camera"]["eye"]), d.camera.eye);
  EXPECT_EQ(vec(j["camera"]["target"]), d.camera.target);
  EXPECT_EQ(vec(j["camera"]["up"]), d.camera.up);
  EXPECT_EQ(j["camera"]["fov"].get<double>(), d.camera.fov_deg);
  EXPECT_EQ(j["camera"]["aspect"].get<double>(), d.camera.aspect);
  ASSERT_EQ(j["lines"].size(), d.lines.size());
  for (std::size_t l = 0; l < d.lines.size(); ++l) {
    const nlohmann::json& line = j["lines"][l];
    EXPECT_EQ(line["kind"].get<std::string>(), line_kind_name(d.lines[l].kind));
    EXPECT_EQ(line["closed"].get<bool>(), d.lines[l].closed);
    ASSERT_EQ(line["points"].size(), d.lines[l].points.size());
    for (std::size_t i = 0; i < d.lines[l].points.size(); ++i) {
      EXPECT_EQ(vec(line["points"][i]), d.lines[l].points[i]);
    }
    ASSERT_EQ(line["visible"].size(), d.lines[l].visible.size());
    for (std::size_t i = 0; i < d.lines[l].visible.size(); ++i) {
      EXPECT_EQ(line["visible"][i].get<bool>(), d.lines[l].visible[i] != 0);
    }
  }
  // Non-finite points and mismatched flags are refused, and nothing is written.
  const std::string bad = dir.file("bad.json");
  LineDrawing nan = d;
  nan.lines[0].points[0].x() = std::nan("");
  EXPECT_THROW(write_polylines_json(bad, nan), InvalidArgument);
  LineDrawing flags = d;
  flags.lines[0].visible.pop_back();
  EXPECT_THROW(write_polylines_json(bad, flags), InvalidArgument);
  EXPECT_THROW(write_drawing_svg(bad, flags), InvalidArgument);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"lines.json"});
}

TEST(DrawingIo, MissingDirectoryThrowsAndLeavesNoFile) {
  TempDir dir;
  const LineDrawing d = sample_drawing();
  const std::string missing = (dir.path() / "missing" / "x").string();
  EXPECT_THROW(write_drawing_svg(missing + ".svg", d), Failure);
  EXPECT_THROW(write_drawing_png(missing + ".png", d), Failure);
  EXPECT_THROW(write_polylines_json(missing + ".json", d), Failure);
  EXPECT_TRUE(dir.entries().empty());
  // A bad style is refused before anything is written.
  DrawingStyle style;
  style.silhouette.width = 0;
  EXPECT_THROW(write_drawing_svg(dir.file("x.svg"), d, style), InvalidArgument);
  style = {};
  style.width = 0;
  EXPECT_THROW(write_drawing_png(dir.file("x.png"), d, style), InvalidArgument);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace ramiform
