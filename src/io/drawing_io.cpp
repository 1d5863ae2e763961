// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Line drawings to SVG, PNG and JSON (io/drawing_io.h): the pictures of Proença, Jorge & Costa
// Sousa 2008, "Suggestive Contours over Point-Set Implicits" (GRAPP), §6–§7, where silhouettes,
// suggestive contours and feature lines are drawn as strokes over the view and hidden lines are
// left out (§3).
//
// Strokes: the polylines become runs of one visibility, projected (a perspective projection
// keeps straight segments straight, so projecting the points and joining them draws the 3-D
// polyline), and runs that meet end to end join into longer paths so that dashes, round caps and
// antialiasing run on along a line instead of restarting at every run. The PNG is drawn by
// cairo on the same strokes, clipped to a margin around the frame first (cairo's fixed-point
// device coordinates overflow far outside it).

#include "ramiform/io/drawing_io.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <utility>

#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/io/atomic_file.h"

namespace ramiform {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr int kMaxPixels = 16384;

// ---- strokes -------------------------------------------------------------------------------

struct Run {
  LineKind kind = LineKind::kSilhouette;
  bool hidden = false;
  bool closed = false;
  std::vector<Vec2> points;
  double length = 0;
};

double length_of(const std::vector<Vec2>& p) {
  double l = 0;
  for (std::size_t i = 1; i < p.size(); ++i) l += (p[i] - p[i - 1]).norm();
  return l;
}

void check_line(const Polyline& line, std::size_t index) {
  if (!line.visible.empty() && line.visible.size() != line.points.size()) {
    throw InvalidArgument("line " + std::to_string(index) + ": " +
                          std::to_string(line.visible.size()) + " visibility flags for " +
                          std::to_string(line.points.size()) + " points");
  }
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    if (!is_finite(line.points[i])) {
      throw InvalidArgument("line " + std::to_string(index) + ": point " + std::to_string(i) +
                            " is not finite");
    }
  }
}

// The runs of one polyline (see join_strokes in the header).
void cut_runs(const Camera& camera, const CameraFrame& frame, const Polyline& line,
              std::vector<Run>& runs) {
  const std::size_t n = line.points.size();
  if (n < 2) return;
  auto flag = [&](std::size_t i) { return line.visible.empty() || line.visible[i] != 0; };
  std::vector<Projected> pr(n);
  std::vector<std::uint8_t> ok(n);
  bool all_ok = true, one_flag = true;
  for (std::size_t i = 0; i < n; ++i) {
    pr[i] = project(camera, frame, line.points[i]);
    ok[i] = pr[i].depth > 0 && std::isfinite(pr[i].x) && std::isfinite(pr[i].y);
    all_ok = all_ok && ok[i] != 0;
    one_flag = one_flag && flag(i) == flag(0);
  }
  auto at = [&](std::size_t i) { return Vec2(pr[i].x, pr[i].y); };
  auto midpoint = [&](std::size_t a, std::size_t b) {
    const Projected m = project(camera, frame, 0.5 * (line.points[a] + line.points[b]));
    return Vec2(m.x, m.y);
  };
  if (line.closed && all_ok && one_flag) {
    Run r{line.kind, !flag(0), true, {}, 0};
    for (std::size_t i = 0; i < n; ++i) r.points.push_back(at(i));
    runs.push_back(std::move(r));
    return;
  }
  Run cur;
  bool open = false;
  auto finish = [&] {
    if (open && cur.points.size() >= 2) runs.push_back(cur);
    open = false;
    cur.points.clear();
  };
  // A closed line is walked once around from a break (a point not drawn, or a change of
  // visibility on the segment before it), back to that break, so no run crosses the seam.
  std::size_t begin = 0;
  if (line.closed) {
    while (begin < n) {
      const std::size_t prev = (begin + n - 1) % n;
      if (ok[prev] == 0 || ok[begin] == 0 || flag(prev) != flag(begin)) break;
      ++begin;
    }
  }
  const std::size_t end = line.closed ? begin + n : n;
  for (std::size_t s = begin; s <= end; ++s) {
    if (s == end && !line.closed) break;
    const std::size_t i = s % n;
    if (ok[i] == 0) {
      finish();
      continue;
    }
    if (!open) {
      if (s == end) break;
      cur = Run{line.kind, !flag(i), false, {at(i)}, 0};
      const std::size_t prev = (i + n - 1) % n;
      if (line.closed && s == begin && ok[prev] != 0 && flag(prev) != flag(i)) {
        cur.points.insert(cur.points.begin(), midpoint(prev, i));  // the break's midpoint
      }
      open = true;
      continue;
    }
    if (flag(i) == !cur.hidden) {
      cur.points.push_back(at(i));
      continue;
    }
    const Vec2 m = midpoint((s + n - 1) % n, i);
    cur.points.push_back(m);
    finish();
    if (s == end) break;
    cur = Run{line.kind, !flag(i), false, {m, at(i)}, 0};
    open = true;
  }
  finish();
}

// Cell of a point in the end grid (indices clamped so that far points stay representable).
std::pair<std::int64_t, std::int64_t> cell_of(const Vec2& p, double cell) {
  auto index = [&](double v) {
    return static_cast<std::int64_t>(std::clamp(std::floor(v / cell), -1e18, 1e18));
  };
  return {index(p.x()), index(p.y())};
}

// Joins the open runs of one kind and visibility (indices into `runs`), appends the paths.
void join_group(const std::vector<Run>& runs, const std::vector<std::size_t>& group,
                double tolerance, std::vector<Run>& out) {
  std::vector<Run> paths;
  std::vector<std::size_t> open;
  for (std::size_t r : group) {
    if (runs[r].closed) {
      paths.push_back(runs[r]);
    } else {
      open.push_back(r);
    }
  }
  // Ends in a grid of cells at least `tolerance` wide: a neighbour within tolerance is in one
  // of the 3×3 cells around.
  const double cell = tolerance > 0 ? tolerance : 1.0;
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::size_t>> grid;  // end ids
  auto end_point = [&](std::size_t id) -> const Vec2& {
    const Run& r = runs[open[id / 2]];
    return id % 2 == 0 ? r.points.front() : r.points.back();
  };
  for (std::size_t id = 0; id < 2 * open.size(); ++id)
    grid[cell_of(end_point(id), cell)].push_back(id);
  std::vector<std::size_t> order(open.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return runs[open[a]].length > runs[open[b]].length;
  });
  std::vector<std::uint8_t> used(open.size(), 0);
  // The unused end within tolerance of p on the longest run (ties: the earlier run, its head).
  auto best_end = [&](const Vec2& p) -> std::ptrdiff_t {
    const auto [cx, cy] = cell_of(p, cell);
    std::ptrdiff_t best = -1;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({cx + dx, cy + dy});
        if (it == grid.end()) continue;
        for (std::size_t id : it->second) {
          if (used[id / 2] != 0 || (end_point(id) - p).norm() > tolerance) continue;
          if (best < 0) {
            best = static_cast<std::ptrdiff_t>(id);
            continue;
          }
          const std::size_t b = static_cast<std::size_t>(best);
          const double la = runs[open[id / 2]].length, lb = runs[open[b / 2]].length;
          if (la > lb || (la == lb && id < b)) best = static_cast<std::ptrdiff_t>(id);
        }
      }
    }
    return best;
  };
  auto extend_tail = [&](std::vector<Vec2>& path) {
    while (true) {
      const std::ptrdiff_t id = best_end(path.back());
      if (id < 0) return;
      const std::size_t k = static_cast<std::size_t>(id) / 2;
      used[k] = 1;
      const std::vector<Vec2>& p = runs[open[k]].points;
      if (id % 2 == 0) {
        path.insert(path.end(), p.begin() + 1, p.end());
      } else {
        path.insert(path.end(), p.rbegin() + 1, p.rend());
      }
    }
  };
  for (std::size_t k : order) {
    if (used[k] != 0) continue;
    used[k] = 1;
    const Run& start = runs[open[k]];
    Run path{start.kind, start.hidden, false, start.points, 0};
    extend_tail(path.points);
    std::reverse(path.points.begin(), path.points.end());
    extend_tail(path.points);
    std::reverse(path.points.begin(), path.points.end());
    if (path.points.size() >= 4 && (path.points.back() - path.points.front()).norm() <= tolerance) {
      path.points.pop_back();
      path.closed = true;
    }
    paths.push_back(std::move(path));
  }
  for (Run& p : paths)
    p.length = length_of(p.points) + (p.closed ? (p.points.back() - p.points.front()).norm() : 0.0);
  std::stable_sort(paths.begin(), paths.end(),
                   [](const Run& a, const Run& b) { return a.length > b.length; });
  for (Run& p : paths) out.push_back(std::move(p));
}

// ---- pictures ------------------------------------------------------------------------------

/// The picture's geometry: image size and the scale from camera units to pixels.
struct Canvas {
  int width = 0, height = 0;
  double half_w = 0, half_h = 0;  ///< the frame: |x| ≤ half_w, |y| ≤ half_h
  double scale = 0;               ///< pixels per camera unit
};

Canvas canvas_of(const Camera& camera, const DrawingStyle& style) {
  validate(camera);
  validate(style);
  Canvas c;
  c.half_h = std::tan(0.5 * camera.fov_deg * kDeg);
  c.half_w = camera.aspect * c.half_h;
  c.width = style.width;
  c.height = style.height > 0 ? style.height
                              : static_cast<int>(std::clamp(std::round(style.width / camera.aspect),
                                                            1.0, static_cast<double>(kMaxPixels)));
  c.scale = std::min(c.width / (2 * c.half_w), c.height / (2 * c.half_h));
  return c;
}

const StrokeStyle& style_of(const DrawingStyle& style, LineKind kind) {
  switch (kind) {
    case LineKind::kSilhouette:
      return style.silhouette;
    case LineKind::kSuggestive:
      return style.suggestive;
    case LineKind::kFeature:
      return style.feature;
  }
  return style.silhouette;
}

std::vector<Stroke> strokes_for(const LineDrawing& drawing, const DrawingStyle& style,
                                const Canvas& canvas) {
  for (std::size_t l = 0; l < drawing.lines.size(); ++l) check_line(drawing.lines[l], l);
  std::vector<Stroke> strokes = join_strokes(drawing, style.join_tolerance / canvas.scale);
  if (!style.show_hidden) {
    std::erase_if(strokes, [](const Stroke& s) { return s.hidden; });
  }
  return strokes;
}

std::string colour_text(const Rgb& c) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s = "#";
  for (std::uint8_t v : {c.r, c.g, c.b}) {
    s += kHex[v >> 4];
    s += kHex[v & 15];
  }
  return s;
}

/// Coordinates of the SVG: multiples of 10^-digits, the largest power of ten at most 1e-5 of
/// the frame's height.
class SvgNumbers {
 public:
  explicit SvgNumbers(double frame_height)
      : digits_(static_cast<int>(std::ceil(-std::log10(frame_height * 1e-5)))),
        power_(std::pow(10.0, digits_)),
        limit_(1e9 * frame_height) {}

  void append(std::string& out, double v) const {
    v = std::clamp(v, -limit_, limit_);
    double r = std::round(v * power_) / power_;
    if (r == 0) r = 0;  // no "-0"
    append_shortest(out, r);
  }

 private:
  int digits_;
  double power_;
  double limit_;
};

void append_style(std::string& svg, const StrokeStyle& s, double scale) {
  svg += " fill=\"none\" stroke=\"" + colour_text(s.colour) + "\" stroke-width=\"";
  append_shortest(svg, s.width / scale);
  svg += '"';
  if (s.dash > 0) {
    svg += " stroke-dasharray=\"";
    append_shortest(svg, s.dash / scale);
    svg += ' ';
    append_shortest(svg, s.dash / scale);
    svg += '"';
  }
  svg += " stroke-linecap=\"round\" stroke-linejoin=\"round\"";
}

// Clips the segment a → b to the box |x| ≤ hx, |y| ≤ hy (Liang–Barsky); false when outside.
bool clip_segment(Vec2& a, Vec2& b, double hx, double hy) {
  double t0 = 0, t1 = 1;
  const Vec2 d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() + hx, hx - a.x(), a.y() + hy, hy - a.y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
  }
  if (t0 > t1) return false;
  const Vec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

using CairoSurface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using CairoContext = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

cairo_status_t png_sink(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return out->good() ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

void validate(const DrawingStyle& style) {
  auto fail = [](const std::string& what, double value, const std::string& range) {
    throw InvalidArgument("drawing style: " + what + " must be " + range + ", got " +
                          format_shortest(value));
  };
  if (style.width < 1 || style.width > kMaxPixels) {
    fail("width", style.width, "in 1.." + std::to_string(kMaxPixels));
  }
  if (style.height < 0 || style.height > kMaxPixels) {
    fail("height", style.height, "in 0.." + std::to_string(kMaxPixels));
  }
  const std::pair<const char*, const StrokeStyle*> strokes[] = {{"silhouette", &style.silhouette},
                                                                {"suggestive", &style.suggestive},
                                                                {"feature", &style.feature},
                                                                {"hidden", &style.hidden}};
  for (const auto& [name, s] : strokes) {
    if (!(std::isfinite(s->width) && s->width > 0)) {
      fail(std::string(name) + " width", s->width, "> 0 pixels");
    }
    if (!(std::isfinite(s->dash) && s->dash >= 0)) {
      fail(std::string(name) + " dash", s->dash, ">= 0 pixels");
    }
  }
  if (!(std::isfinite(style.join_tolerance) && style.join_tolerance >= 0)) {
    fail("join_tolerance", style.join_tolerance, ">= 0 pixels");
  }
}

std::vector<Stroke> join_strokes(const LineDrawing& drawing, double tolerance) {
  if (!(std::isfinite(tolerance) && tolerance >= 0)) {
    throw InvalidArgument("join_strokes: the tolerance must be >= 0, got " +
                          format_shortest(tolerance));
  }
  validate(drawing.camera);
  const CameraFrame frame = camera_frame(drawing.camera);
  std::vector<Run> runs;
  for (std::size_t l = 0; l < drawing.lines.size(); ++l) {
    check_line(drawing.lines[l], l);
    cut_runs(drawing.camera, frame, drawing.lines[l], runs);
  }
  for (Run& r : runs) r.length = length_of(r.points);
  std::vector<Run> joined;
  for (LineKind kind : {LineKind::kSilhouette, LineKind::kSuggestive, LineKind::kFeature}) {
    for (bool hidden : {false, true}) {
      std::vector<std::size_t> group;
      for (std::size_t r = 0; r < runs.size(); ++r) {
        if (runs[r].kind == kind && runs[r].hidden == hidden) group.push_back(r);
      }
      join_group(runs, group, tolerance, joined);
    }
  }
  std::vector<Stroke> strokes;
  strokes.reserve(joined.size());
  for (Run& r : joined) strokes.push_back({r.kind, r.hidden, r.closed, std::move(r.points)});
  return strokes;
}

void write_drawing_svg(const std::string& path, const LineDrawing& drawing,
                       const DrawingStyle& style) {
  const Canvas canvas = canvas_of(drawing.camera, style);
  const std::vector<Stroke> strokes = strokes_for(drawing, style, canvas);
  const SvgNumbers numbers(2 * canvas.half_h);
  std::string svg =
      "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" +
      std::to_string(canvas.width) + "\" height=\"" + std::to_string(canvas.height) +
      "\" viewBox=\"";
  const double box[4] = {-canvas.half_w, -canvas.half_h, 2 * canvas.half_w, 2 * canvas.half_h};
  for (int k = 0; k < 4; ++k) {
    if (k > 0) svg += ' ';
    append_shortest(svg, box[k]);
  }
  svg += "\">\n";
  if (style.white_background) {
    svg += "<rect x=\"";
    append_shortest(svg, box[0]);
    svg += "\" y=\"";
    append_shortest(svg, box[1]);
    svg += "\" width=\"";
    append_shortest(svg, box[2]);
    svg += "\" height=\"";
    append_shortest(svg, box[3]);
    svg += "\" fill=\"#ffffff\"/>\n";
  }
  auto group = [&](const char* id, const StrokeStyle& s, auto&& wanted) {
    svg += "<g id=\"";
    svg += id;
    svg += '"';
    append_style(svg, s, canvas.scale);
    svg += ">\n";
    for (const Stroke& st : strokes) {
      if (!wanted(st)) continue;
      svg += "<path d=\"M ";
      for (std::size_t i = 0; i < st.points.size(); ++i) {
        if (i == 1) svg += " L ";
        if (i > 1) svg += ' ';
        numbers.append(svg, st.points[i].x());
        svg += ' ';
        numbers.append(svg, -st.points[i].y());  // SVG's y points down
      }
      if (st.closed) svg += " Z";
      svg += "\"/>\n";
    }
    svg += "</g>\n";
  };
  if (style.show_hidden) group("hidden", style.hidden, [](const Stroke& s) { return s.hidden; });
  for (LineKind kind : {LineKind::kSilhouette, LineKind::kSuggestive, LineKind::kFeature}) {
    group(std::string(line_kind_name(kind)).c_str(), style_of(style, kind),
          [kind](const Stroke& s) { return !s.hidden && s.kind == kind; });
  }
  svg += "</svg>\n";
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(svg.data(), static_cast<std::streamsize>(svg.size()));
  });
}

void write_drawing_png(const std::string& path, const LineDrawing& drawing,
                       const DrawingStyle& style) {
  const Canvas canvas = canvas_of(drawing.camera, style);
  const std::vector<Stroke> strokes = strokes_for(drawing, style, canvas);
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, canvas.width, canvas.height),
                       &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) {
    throw Failure(path + ": cannot create a " + std::to_string(canvas.width) + "x" +
                  std::to_string(canvas.height) +
                  " image: " + cairo_status_to_string(cairo_surface_status(surface.get())));
  }
  CairoContext cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  cairo_translate(cr.get(), 0.5 * canvas.width, 0.5 * canvas.height);
  cairo_scale(cr.get(), canvas.scale, -canvas.scale);
  cairo_set_line_cap(cr.get(), CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr.get(), CAIRO_LINE_JOIN_ROUND);
  // Segments are clipped to the frame grown by a margin wider than any stroke.
  const double margin = 0.1 * canvas.half_h;
  const double hx = canvas.half_w + margin, hy = canvas.half_h + margin;
  auto draw = [&](const StrokeStyle& s, auto&& wanted) {
    cairo_set_source_rgb(cr.get(), s.colour.r / 255.0, s.colour.g / 255.0, s.colour.b / 255.0);
    cairo_set_line_width(cr.get(), s.width / canvas.scale);
    const double dash = s.dash / canvas.scale;
    cairo_set_dash(cr.get(), &dash, s.dash > 0 ? 1 : 0, 0);
    for (const Stroke& st : strokes) {
      if (!wanted(st)) continue;
      const std::size_t n = st.points.size();
      const std::size_t segments = st.closed ? n : n - 1;
      bool whole = true;  // no segment was clipped: the path may close
      bool pen_down = false;
      Vec2 pen;
      for (std::size_t k = 0; k < segments; ++k) {
        Vec2 a = st.points[k], b = st.points[(k + 1) % n];
        const Vec2 a0 = a, b0 = b;
        if (!clip_segment(a, b, hx, hy)) {
          whole = false;
          pen_down = false;
          continue;
        }
        if (a != a0 || b != b0) whole = false;
        if (!pen_down || a != pen) cairo_move_to(cr.get(), a.x(), a.y());
        if (st.closed && whole && k + 1 == segments) {
          cairo_close_path(cr.get());
        } else {
          cairo_line_to(cr.get(), b.x(), b.y());
        }
        pen = b;
        pen_down = true;
      }
      cairo_stroke(cr.get());
    }
  };
  if (style.show_hidden) draw(style.hidden, [](const Stroke& s) { return s.hidden; });
  for (LineKind kind : {LineKind::kSilhouette, LineKind::kSuggestive, LineKind::kFeature}) {
    draw(style_of(style, kind), [kind](const Stroke& s) { return !s.hidden && s.kind == kind; });
  }
  cairo_surface_flush(surface.get());
  if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS) {
    throw Failure(path + ": drawing failed: " + cairo_status_to_string(cairo_status(cr.get())));
  }
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        const cairo_status_t status =
            cairo_surface_write_to_png_stream(surface.get(), &png_sink, &out);
        if (status != CAIRO_STATUS_SUCCESS) {
          throw Failure(path + ": writing the PNG failed: " + cairo_status_to_string(status));
        }
      },
      FileMode::kBinary);
}

void write_drawing(const std::string& path, const LineDrawing& drawing, const DrawingStyle& style) {
  const std::string ext = io_detail::lower_extension(path);
  if (ext == ".svg") {
    write_drawing_svg(path, drawing, style);
  } else if (ext == ".png") {
    write_drawing_png(path, drawing, style);
  } else {
    throw InvalidArgument("unknown drawing format '" + ext + "' (supported: .svg, .png)");
  }
}

void write_polylines_json(const std::string& path, const LineDrawing& drawing) {
  using nlohmann::ordered_json;
  const Camera& c = drawing.camera;
  auto vec = [](const Vec3& v) { return ordered_json::array({v.x(), v.y(), v.z()}); };
  if (!is_finite(c.eye) || !is_finite(c.target) || !is_finite(c.up) || !std::isfinite(c.fov_deg) ||
      !std::isfinite(c.aspect)) {
    throw InvalidArgument("write_polylines_json: the camera is not finite");
  }
  ordered_json j;
  j["camera"] = {{"eye", vec(c.eye)},
                 {"target", vec(c.target)},
                 {"up", vec(c.up)},
                 {"fov", c.fov_deg},
                 {"aspect", c.aspect}};
  ordered_json lines = ordered_json::array();
  for (std::size_t l = 0; l < drawing.lines.size(); ++l) {
    const Polyline& line = drawing.lines[l];
    check_line(line, l);
    ordered_json points = ordered_json::array();
    for (const Vec3& p : line.points) points.push_back(vec(p));
    ordered_json visible = ordered_json::array();
    for (std::uint8_t v : line.visible) visible.push_back(v != 0);
    lines.push_back({{"kind", std::string(line_kind_name(line.kind))},
                     {"closed", line.closed},
                     {"points", std::move(points)},
                     {"visible", std::move(visible)}});
  }
  j["lines"] = std::move(lines);
  const std::string text = j.dump() + "\n";
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

}  // namespace ramiform
