// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/points_io.h"

#include <cmath>

#include "core/extent_check.h"
#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"

namespace ramiform {
namespace {

// A normal must have a direction: MPU and the normal orientation need one.
constexpr const char* kZeroNormal =
    "zero normal (0 0 0): a normal needs a direction; leave the normals out to have them "
    "estimated";

using namespace io_detail;

void check_writable(const PointSet& points) {
  if (!points.normals.empty() && points.normals.size() != points.positions.size()) {
    throw InvalidArgument("write_points: " + std::to_string(points.normals.size()) +
                          " normals for " + std::to_string(points.positions.size()) + " points");
  }
  for (std::size_t i = 0; i < points.positions.size(); ++i) {
    if (!is_finite(points.positions[i])) {
      throw InvalidArgument("write_points: point " + std::to_string(i) + " is not finite");
    }
  }
  for (std::size_t i = 0; i < points.normals.size(); ++i) {
    if (!is_finite(points.normals[i])) {
      throw InvalidArgument("write_points: normal " + std::to_string(i) + " is not finite");
    }
  }
}

constexpr std::string_view kNames[] = {"x", "y", "z", "nx", "ny", "nz"};

}  // namespace

PointSet parse_points_text(std::string_view text, const std::string& source_name) {
  const std::string& source = source_name;
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = skip_bom(text);
  if (is_blank(text)) throw InputError(source, 0, "file is empty");
  PointSet points;
  points.positions.reserve(text.size() / 24);
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> f;
  std::size_t columns = 0;
  std::size_t first_line = 0;
  detail::ExtentCheck extent;
  while (cursor.next(line)) {
    const std::size_t ln = cursor.line_number();
    if (!split_fields(strip_comment(line), f, true)) {
      throw InputError(source, ln, "empty field between commas");
    }
    if (f.empty()) continue;
    if (columns == 0) {
      if (f.size() != 3 && f.size() != 6) {
        // A file with lone '\r' line breaks arrives here as one line of many points.
        const bool has_cr = strip_comment(line).find('\r') != std::string_view::npos;
        throw InputError(source, ln,
                         "expected 3 numbers (x y z) or 6 (x y z nx ny nz), got " +
                             std::to_string(f.size()) + " fields" +
                             (has_cr ? " (the line holds carriage returns: lines must end in "
                                       "'\\n' or '\\r\\n', not '\\r' alone)"
                                     : ""));
      }
      columns = f.size();
      first_line = ln;
    } else if (f.size() != columns) {
      throw InputError(source, ln,
                       "expected " + std::to_string(columns) + " numbers like line " +
                           std::to_string(first_line) + ", got " + std::to_string(f.size()) +
                           " fields");
    }
    double v[6];
    for (std::size_t c = 0; c < columns; ++c) v[c] = to_double(f[c], source, ln, kNames[c]);
    points.positions.emplace_back(v[0], v[1], v[2]);
    if (!extent.add(points.positions.back()))
      throw InputError(source, ln, extent.problem("this point"));
    if (columns == 6) {
      points.normals.emplace_back(v[3], v[4], v[5]);
      if (points.normals.back() == Vec3::Zero()) throw InputError(source, ln, kZeroNormal);
    }
  }
  if (points.positions.empty()) throw InputError(source, 0, "no points");
  return points;
}

PointSet parse_points_ply(std::string_view bytes, const std::string& source_name) {
  const std::string& source = source_name;
  const PlyHeader header = parse_ply_header(bytes, source);
  PlyRequest request = vertex_request(header, {"x", "y", "z"}, source);
  add_vertex_normals(header, request, source);
  const std::vector<PlyElementData> data = read_ply_body(bytes, header, {request}, source);
  if (data[0].count == 0) {
    // As in the text reader: an empty point set is refused, not returned.
    throw InputError(source, header.elements[request.element].header_line,
                     "no points (element 'vertex' has count 0)");
  }
  const std::size_t cols = request.scalars.size();
  PointSet points;
  points.positions.resize(data[0].count);
  if (cols == 6) points.normals.resize(data[0].count);
  detail::ExtentCheck extent;
  for (std::size_t i = 0; i < data[0].count; ++i) {
    const double* row = &data[0].scalars[i * cols];
    points.positions[i] = Vec3(row[0], row[1], row[2]);
    if (!extent.add(points.positions[i]))
      throw InputError(source, "vertex", i, extent.problem("this point"));
    if (cols == 6) {
      points.normals[i] = Vec3(row[3], row[4], row[5]);
      if (points.normals[i] == Vec3::Zero()) throw InputError(source, "vertex", i, kZeroNormal);
    }
  }
  return points;
}

PointSet read_points(const std::string& path) {
  if (lower_extension(path) == ".ply") return parse_points_ply(read_whole_file(path), path);
  return parse_points_text(read_whole_file(path), path);
}

void write_points(const PointSet& points, const std::string& path) {
  check_writable(points);
  const bool normals = points.has_normals();
  if (lower_extension(path) == ".ply") {
    write_file_atomically(
        path,
        [&](std::ostream& out) {
          PlyWriter ply(out);
          ply.begin("ramiform points");
          std::vector<PlyColumn> columns;
          for (std::size_t c = 0; c < (normals ? 6U : 3U); ++c) {
            columns.push_back({std::string(kNames[c]), PlyType::kFloat64});
          }
          ply.element("vertex", points.size(), columns);
          ply.end_header();
          for (std::size_t i = 0; i < points.size(); ++i) {
            for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, points.positions[i][c]);
            if (normals) {
              for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, points.normals[i][c]);
            }
          }
          ply.flush(true);
        },
        FileMode::kBinary);
    return;
  }
  write_file_atomically(path, [&](std::ostream& out) {
    TextSink sink(out);
    for (std::size_t i = 0; i < points.size(); ++i) {
      std::string& t = sink.text();
      for (int c = 0; c < 3; ++c) {
        if (c > 0) t += ' ';
        append_double(t, points.positions[i][c]);
      }
      if (normals) {
        for (int c = 0; c < 3; ++c) {
          t += ' ';
          append_double(t, points.normals[i][c]);
        }
      }
      t += '\n';
      sink.line_done();
    }
    sink.flush();
  });
}

}  // namespace ramiform
