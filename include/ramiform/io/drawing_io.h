// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Writing line drawings (lines/lines.h): SVG and PNG pictures of one view, and the polylines
/// themselves as JSON. Pen-and-ink drawings after Proença, Jorge & Costa Sousa 2008,
/// "Suggestive Contours over Point-Set Implicits" (GRAPP), §6–§7.
///
/// Pictures are in the camera units of lines/camera.h: a point projects to (x, y), x to the
/// right and y up, and the frame is |x| ≤ aspect·tan(fov/2), |y| ≤ tan(fov/2). The SVG viewBox
/// is that frame with y flipped (SVG's y points down): "−aT −T 2aT 2T", T = tan(fov/2), a =
/// aspect. Each polyline is cut into runs of equal visibility (a change of visibility between
/// two points falls at the midpoint of their segment), the runs are projected, and runs of one
/// kind and visibility are joined end to end into as few paths as possible (join_strokes).
/// Every writer writes atomically (io/atomic_file.h): a failure leaves no file.

#include <cstdint>
#include <string>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/lines/lines.h"

namespace ramiform {

/// An sRGB colour, 8 bits per channel.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

/// How one kind of line is drawn.
struct StrokeStyle {
  Rgb colour;          ///< stroke colour
  double width = 1.0;  ///< stroke width in pixels of the image, > 0
  double dash = 0;     ///< dash and gap length in pixels; 0 = a solid line, ≥ 0
};

/// How a drawing is rendered.
struct DrawingStyle {
  int width = 800;  ///< image width in pixels, 1..32768
  /// Image height in pixels, 0..32768; 0 = width / camera.aspect (rounded, at least 1). When
  /// width / height differs from the camera's aspect, the frame is centred and scaled to fit
  /// (SVG's default preserveAspectRatio, "xMidYMid meet").
  int height = 0;
  StrokeStyle silhouette{{0, 0, 0}, 2.0, 0};  ///< contours: the boldest
  StrokeStyle suggestive{{0, 0, 0}, 1.0, 0};  ///< suggestive contours: thin
  StrokeStyle feature{{0, 0, 0}, 1.25, 0};    ///< creases
  bool show_hidden = false;  ///< also draw the hidden runs (under the visible ones)
  StrokeStyle hidden{{150, 150, 150}, 0.75, 4};  ///< hidden runs of every kind: grey, thin, dashed
  bool white_background = false;  ///< SVG: a white rectangle under the lines (PNG: always white)
  /// Run ends closer than this (pixels) are joined into one path.
  double join_tolerance = 0.5;
};

/// Throws InvalidArgument naming the first value out of its documented range.
void validate(const DrawingStyle& style);

/// One continuous stroke of a picture.
struct Stroke {
  LineKind kind = LineKind::kSilhouette;
  bool hidden = false;
  bool closed = false;       ///< the last point joins the first ("Z")
  std::vector<Vec2> points;  ///< camera units: x right, y up
};

/// The drawing's polylines as strokes: each polyline cut into runs of equal visibility (a
/// polyline without flags counts as visible; the cut between a visible and a hidden point lies
/// at the projected midpoint of their segment), points not in front of the eye (depth ≤ 0) cut
/// runs too and are dropped, every run projected with project(). Runs of the same kind and
/// visibility are then joined end to end where their ends lie within `tolerance` (camera units,
/// ≥ 0), reversing runs as needed: the longest unused run (2-D length, ties by order) starts a
/// path, which takes at its tail, then at its head, the longest run whose end lies within
/// tolerance, until none does. A path whose two ends meet within tolerance (or a polyline that
/// is closed and wholly of one visibility) becomes closed. Deterministic. The result lists the
/// silhouettes' strokes, then the suggestive contours', then the feature lines'; visible before
/// hidden within a kind, each group longest first.
[[nodiscard]] std::vector<Stroke> join_strokes(const LineDrawing& drawing, double tolerance);

/// Writes the drawing as SVG 1.1: groups <g id="hidden"> (only with show_hidden; drawn first),
/// <g id="silhouette">, <g id="suggestive">, <g id="feature">, each always present and holding
/// one <path d="M x y L x y …"/> per stroke (closed ones end in "Z"), coordinates rounded to
/// multiples of the largest power of ten at most 1e-5 of the frame's height (5–6 digits); strokes
/// with round caps and joins, no fill. Throws InvalidArgument for a bad style or camera, a line
/// point that is not finite or flags whose count differs from the points'; Failure when the
/// file cannot be written.
void write_drawing_svg(const std::string& path, const LineDrawing& drawing,
                       const DrawingStyle& style = {});

/// Writes the same strokes as an RGB PNG (cairo, antialiased) on a white background. Throws as
/// write_drawing_svg.
void write_drawing_png(const std::string& path, const LineDrawing& drawing,
                       const DrawingStyle& style = {});

/// write_drawing_svg or write_drawing_png by the extension of `path` (.svg or .png, any case);
/// throws InvalidArgument naming the extension for another one, before anything is written.
void write_drawing(const std::string& path, const LineDrawing& drawing,
                   const DrawingStyle& style = {});

/// Writes the drawing's camera and polylines as JSON:
/// {"camera":{"eye":[x,y,z],"target":[..],"up":[..],"fov":degrees,"aspect":a},
///  "lines":[{"kind":"silhouette","closed":false,"points":[[x,y,z],…],"visible":[true,…]}]}
/// with every number in its shortest form that reads back exactly; "visible" is empty for a
/// line not classified. Throws InvalidArgument for a non-finite number or flags whose count
/// differs from the points'; Failure when the file cannot be written.
void write_polylines_json(const std::string& path, const LineDrawing& drawing);

}  // namespace ramiform
