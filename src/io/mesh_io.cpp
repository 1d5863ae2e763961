// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/mesh_io.h"

#include <cmath>
#include <cstdio>
#include <span>

#include "io/gltf_format.h"
#include "io/obj_format.h"
#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"
#include "ramiform/mesh/checks.h"

namespace ramiform {
namespace {

using namespace io_detail;

// Appends the fan v0 v1 v2, v0 v2 v3, ... of one polygon.
template <typename Index>
void add_fan(TriMesh& mesh, const Index* corners, std::size_t n) {
  for (std::size_t i = 1; i + 1 < n; ++i) {
    mesh.triangles.push_back({static_cast<std::uint32_t>(corners[0]),
                              static_cast<std::uint32_t>(corners[i]),
                              static_cast<std::uint32_t>(corners[i + 1])});
  }
}

template <class V>
void check_attribute(const std::vector<V>& values, std::size_t n, const char* what) {
  if (!values.empty() && values.size() != n) {
    throw InvalidArgument("write_mesh: " + std::to_string(values.size()) + " " + what + " for " +
                          std::to_string(n) + " vertices");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values[i].allFinite()) {
      throw InvalidArgument("write_mesh: " + std::string(what) + " " + std::to_string(i) +
                            " is not finite");
    }
  }
}

void check_writable(const TriMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  check_attribute(mesh.positions, n, "vertex");
  check_attribute(mesh.normals, n, "normals");
  check_attribute(mesh.uvs, n, "uvs");
  check_attribute(mesh.tangents, n, "tangents");
  if (!mesh.vertex_labels.empty() && mesh.vertex_labels.size() != n) {
    throw InvalidArgument("write_mesh: " + std::to_string(mesh.vertex_labels.size()) +
                          " vertex labels for " + std::to_string(n) + " vertices");
  }
  if (!mesh.tangents.empty() && mesh.uvs.empty()) {
    throw InvalidArgument("write_mesh: tangents without uvs");
  }
  if (!mesh.welded.empty()) {
    if (mesh.welded.size() != n) {
      throw InvalidArgument("write_mesh: " + std::to_string(mesh.welded.size()) +
                            " welded entries for " + std::to_string(n) + " vertices");
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (mesh.welded[i] > i || mesh.welded[mesh.welded[i]] != mesh.welded[i]) {
        throw InvalidArgument("write_mesh: vertex " + std::to_string(i) + " is welded to " +
                              std::to_string(mesh.welded[i]) +
                              ", which is not an original vertex before it");
      }
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= n) {
        throw InvalidArgument("write_mesh: triangle " + std::to_string(t) + " has vertex index " +
                              std::to_string(v) + " out of range (" + std::to_string(n) +
                              " vertices)");
      }
    }
  }
}

// For each vertex, the 0-based index of its surface point when only the original of each seam
// copy is written (the identity for a mesh without `welded`).
std::vector<std::uint32_t> surface_points(const TriMesh& mesh) {
  std::vector<std::uint32_t> point(mesh.positions.size());
  std::uint32_t points = 0;
  for (std::size_t i = 0; i < point.size(); ++i) {
    const std::uint32_t w = mesh.welded.empty() ? static_cast<std::uint32_t>(i) : mesh.welded[i];
    point[i] = w == i ? points++ : point[w];
  }
  return point;
}

// The file's coordinates of a library point or direction (+Z up) for `up`.
Vec3 oriented(const Vec3& v, UpAxis up) {
  return up == UpAxis::kY ? Vec3(v.x(), v.z(), -v.y()) : v;
}

void append_vec(std::string& t, const Vec3& p) {
  append_double(t, p.x());
  t += ' ';
  append_double(t, p.y());
  t += ' ';
  append_double(t, p.z());
}

void write_ply(const TriMesh& mesh, const MeshWriteOptions& o, std::ostream& out) {
  PlyWriter ply(out);
  ply.begin("ramiform mesh");
  std::vector<PlyColumn> columns = {
      {"x", PlyType::kFloat64}, {"y", PlyType::kFloat64}, {"z", PlyType::kFloat64}};
  const bool normals = o.normals && !mesh.normals.empty();
  const bool uvs = o.uvs && !mesh.uvs.empty();
  if (normals) {
    columns.push_back({"nx", PlyType::kFloat64});
    columns.push_back({"ny", PlyType::kFloat64});
    columns.push_back({"nz", PlyType::kFloat64});
  }
  if (uvs) {
    columns.push_back({"u", PlyType::kFloat64});
    columns.push_back({"v", PlyType::kFloat64});
  }
  const bool labels = !mesh.vertex_labels.empty();
  if (labels) columns.push_back({"swc_type", PlyType::kInt32});
  ply.element("vertex", mesh.positions.size(), columns);
  ply.list_element("face", mesh.triangles.size(), PlyType::kUInt8, PlyType::kUInt32,
                   "vertex_indices");
  ply.end_header();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3 p = oriented(mesh.positions[i], o.up);
    for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, p[c]);
    if (normals) {
      const Vec3 n = oriented(mesh.normals[i], o.up);
      for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, n[c]);
    }
    if (uvs) {
      ply.put(PlyType::kFloat64, mesh.uvs[i].x());
      ply.put(PlyType::kFloat64, mesh.uvs[i].y());
    }
    if (labels) ply.put(PlyType::kInt32, mesh.vertex_labels[i]);
  }
  for (const auto& t : mesh.triangles) {
    ply.put_index(PlyType::kUInt8, 3);
    for (const std::uint32_t v : t) ply.put_index(PlyType::kUInt32, v);
  }
  ply.flush(true);
}

// OBJ keeps one `v` (and `vn`) per point of the surface and one `vt` per seam copy, so a
// textured mesh stays closed by its vertex indices: corners are v/vt/vn.
void write_obj(const TriMesh& mesh, const MeshWriteOptions& o, std::ostream& out) {
  TextSink sink(out);
  sink.text() += "# ramiform mesh\n";
  const std::size_t n = mesh.positions.size();
  const bool normals = o.normals && !mesh.normals.empty();
  const bool uvs = o.uvs && !mesh.uvs.empty();
  const std::vector<std::uint32_t> point = surface_points(mesh);
  const auto lines = [&](const char* tag, auto&& value) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!mesh.welded.empty() && mesh.welded[i] != i) continue;
      sink.text() += tag;
      append_vec(sink.text(), oriented(value(i), o.up));
      sink.text() += '\n';
      sink.line_done();
    }
  };
  lines("v ", [&](std::size_t i) { return mesh.positions[i]; });
  if (normals) lines("vn ", [&](std::size_t i) { return mesh.normals[i]; });
  if (uvs) {
    for (const Vec2& uv : mesh.uvs) {
      std::string& t = sink.text();
      t += "vt ";
      append_double(t, uv.x());
      t += ' ';
      append_double(t, uv.y());
      t += '\n';
      sink.line_done();
    }
  }
  for (const auto& tri : mesh.triangles) {
    std::string& t = sink.text();
    t += 'f';
    for (const std::uint32_t v : tri) {
      t += ' ';
      append_uint(t, std::uint64_t{point[v]} + 1);
      if (uvs) {
        t += '/';
        append_uint(t, std::uint64_t{v} + 1);
      }
      if (normals) {
        t += uvs ? "/" : "//";
        append_uint(t, std::uint64_t{point[v]} + 1);
      }
    }
    t += '\n';
    sink.line_done();
  }
  sink.flush();
}

void write_off(const TriMesh& mesh, const MeshWriteOptions& o, std::ostream& out) {
  TextSink sink(out);
  const std::vector<std::uint32_t> point = surface_points(mesh);
  std::size_t points = 0;
  for (std::size_t i = 0; i < point.size(); ++i) {
    if (mesh.welded.empty() || mesh.welded[i] == i) ++points;
  }
  std::string& head = sink.text();
  head += "OFF\n";
  append_uint(head, points);
  head += ' ';
  append_uint(head, mesh.triangles.size());
  head += " 0\n";
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!mesh.welded.empty() && mesh.welded[i] != i) continue;
    append_vec(sink.text(), oriented(mesh.positions[i], o.up));
    sink.text() += '\n';
    sink.line_done();
  }
  for (const auto& tri : mesh.triangles) {
    std::string& t = sink.text();
    t += '3';
    for (const std::uint32_t v : tri) {
      t += ' ';
      append_uint(t, point[v]);
    }
    t += '\n';
    sink.line_done();
  }
  sink.flush();
}

}  // namespace

TriMesh parse_mesh_ply(std::string_view bytes, const std::string& source_name) {
  const std::string& source = source_name;
  const PlyHeader header = parse_ply_header(bytes, source);
  std::vector<PlyRequest> requests{vertex_request(header, {"x", "y", "z"}, source)};
  const bool has_normals = add_vertex_normals(header, requests[0], source);
  const std::size_t uv_col = requests[0].scalars.size();
  const bool has_uvs = add_vertex_uvs(header, requests[0], source);
  // Per-vertex labels as write_mesh stores them (the SWC type of the nearest node).
  const std::size_t label_col = requests[0].scalars.size();
  const auto label = optional_scalar(header.elements[requests[0].element], "swc_type", source);
  if (label) requests[0].scalars.push_back(*label);
  const auto face = header.find("face");
  if (face) {
    const PlyElement& f = header.elements[*face];
    auto list = f.find("vertex_indices");
    if (!list) list = f.find("vertex_index");
    if (!list) {
      throw InputError(source, f.header_line,
                       "element 'face' has no 'vertex_indices' (or 'vertex_index') list");
    }
    PlyRequest r;
    r.element = *face;
    r.list = *list;
    requests.push_back(r);
  }
  const std::vector<PlyElementData> data = read_ply_body(bytes, header, requests, source);

  TriMesh mesh;
  const std::size_t cols = requests[0].scalars.size();
  const std::size_t nv = data[0].count;
  mesh.positions.resize(nv);
  if (has_normals) mesh.normals.resize(nv);
  if (has_uvs) mesh.uvs.resize(nv);
  if (label) mesh.vertex_labels.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const double* row = &data[0].scalars[i * cols];
    mesh.positions[i] = Vec3(row[0], row[1], row[2]);
    if (has_normals) mesh.normals[i] = Vec3(row[3], row[4], row[5]);
    if (has_uvs) mesh.uvs[i] = Vec2(row[uv_col], row[uv_col + 1]);
    if (label) {
      const double t = row[label_col];
      if (!(t == std::floor(t) && std::abs(t) <= 2147483647.0)) {
        throw InputError(source, "vertex", i,
                         "swc_type " + format_number(t) + " is not a 32-bit whole number");
      }
      mesh.vertex_labels[i] = static_cast<std::int32_t>(t);
    }
  }
  // A textured PLY mesh has its vertices split along the texture's seams; the copies sit at
  // identical positions, which give the seams back.
  if (has_uvs) weld_coincident(mesh);
  if (face) {
    const PlyElementData& f = data[1];
    mesh.triangles.reserve(f.list_values.size() >= 2 * f.count ? f.list_values.size() - 2 * f.count
                                                               : 0);
    for (std::size_t k = 0; k < f.count; ++k) {
      const std::size_t begin = f.list_offsets[k];
      const std::size_t n = f.list_offsets[k + 1] - begin;
      if (n < 3) {
        throw InputError(source, "face", k,
                         "has " + std::to_string(n) + " vertices, needs at least 3");
      }
      for (std::size_t j = 0; j < n; ++j) {
        const std::int64_t idx = f.list_values[begin + j];
        if (idx < 0 || static_cast<std::uint64_t>(idx) >= nv) {
          throw InputError(source, "face", k,
                           "vertex index " + std::to_string(idx) + " out of range (" +
                               std::to_string(nv) + " vertices)");
        }
      }
      add_fan(mesh, &f.list_values[begin], n);
    }
  }
  return mesh;
}

TriMesh parse_mesh_obj(std::string_view text, const std::string& source_name) {
  const std::string& source = source_name;
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = skip_bom(text);
  if (is_blank(text)) throw InputError(source, 0, "file is empty");
  TriMesh mesh;
  std::vector<Vec3> normals;
  std::size_t texcoords = 0;
  bool normals_match = true;
  LineCursor cursor(text);
  std::vector<std::string_view> f;
  std::vector<std::uint32_t> corners;
  std::string_view v;
  std::string_view vt;
  std::string_view vn;
  while (next_content(cursor, f)) {
    const std::size_t ln = cursor.line_number();
    const std::string_view key = f[0];
    if (key == "v") {
      mesh.positions.push_back(parse_obj_vertex(f, source, ln));
    } else if (key == "vn") {
      if (f.size() != 4) {
        throw InputError(source, ln, "'vn' needs 3 numbers, got " + std::to_string(f.size() - 1));
      }
      normals.emplace_back(to_double(f[1], source, ln, "nx"), to_double(f[2], source, ln, "ny"),
                           to_double(f[3], source, ln, "nz"));
    } else if (key == "vt") {
      ++texcoords;
    } else if (key == "f") {
      if (f.size() < 4) {
        throw InputError(source, ln,
                         "'f' needs at least 3 vertices, got " + std::to_string(f.size() - 1));
      }
      corners.clear();
      for (std::size_t i = 1; i < f.size(); ++i) {
        split_obj_corner(f[i], v, vt, vn, source, ln);
        const std::uint32_t vi = resolve_obj_index(v, mesh.positions.size(), source, ln, "vertex");
        if (!vt.empty()) resolve_obj_index(vt, texcoords, source, ln, "texture coordinate");
        if (!vn.empty()) {
          const std::uint32_t ni = resolve_obj_index(vn, normals.size(), source, ln, "normal");
          normals_match = normals_match && ni == vi;
        }
        corners.push_back(vi);
      }
      add_fan(mesh, corners.data(), corners.size());
    }
  }
  if (mesh.positions.empty()) throw InputError(source, 0, "no vertices ('v' lines)");
  if (normals_match && normals.size() == mesh.positions.size()) mesh.normals = std::move(normals);
  return mesh;
}

TriMesh parse_mesh_off(std::string_view text, const std::string& source_name) {
  const std::string& source = source_name;
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = skip_bom(text);
  if (is_blank(text)) throw InputError(source, 0, "file is empty");
  LineCursor cursor(text);
  std::vector<std::string_view> f;
  if (!next_content(cursor, f) || f[0] != "OFF") {
    throw InputError(source, cursor.line_number(), "not an OFF file: expected 'OFF'");
  }
  if (f.size() == 1) {
    if (!next_content(cursor, f)) {
      throw InputError(source, cursor.line_number(), "missing the vertex and face counts");
    }
  } else {
    f.erase(f.begin());
  }
  std::size_t ln = cursor.line_number();
  if (f.size() != 2 && f.size() != 3) {
    throw InputError(source, ln,
                     "expected 'vertex_count face_count [edge_count]', got " +
                         std::to_string(f.size()) + " values");
  }
  const std::int64_t nv = to_int64(f[0], source, ln, "vertex count");
  const std::int64_t nf = to_int64(f[1], source, ln, "face count");
  if (f.size() == 3) to_int64(f[2], source, ln, "edge count");
  if (nv < 0 || nf < 0 || nv > std::int64_t{UINT32_MAX}) {
    throw InputError(source, ln, "invalid vertex or face count");
  }
  TriMesh mesh;
  // A vertex line takes at least 6 bytes ("0 0 0\n"): a header that promises more vertices than
  // the file can hold reserves no more than it can (a 20-byte file may claim 4 billion).
  mesh.positions.reserve(static_cast<std::size_t>(
      std::min<std::int64_t>(nv, static_cast<std::int64_t>(text.size() / 6))));
  for (std::int64_t i = 0; i < nv; ++i) {
    if (!next_content(cursor, f)) {
      throw InputError(
          source, cursor.line_number(),
          "the file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    }
    ln = cursor.line_number();
    if (f.size() != 3) {
      throw InputError(source, ln, "a vertex needs 3 numbers, got " + std::to_string(f.size()));
    }
    mesh.positions.emplace_back(to_double(f[0], source, ln, "x"), to_double(f[1], source, ln, "y"),
                                to_double(f[2], source, ln, "z"));
  }
  std::vector<std::int64_t> corners;
  for (std::int64_t k = 0; k < nf; ++k) {
    if (!next_content(cursor, f)) {
      throw InputError(
          source, cursor.line_number(),
          "the file ends after " + std::to_string(k) + " of " + std::to_string(nf) + " faces");
    }
    ln = cursor.line_number();
    const std::int64_t n = to_int64(f[0], source, ln, "face vertex count");
    if (n < 3) {
      throw InputError(source, ln, "a face needs at least 3 vertices, got " + std::to_string(n));
    }
    const auto un = static_cast<std::size_t>(n);
    if (f.size() < un + 1 || f.size() > un + 5) {
      throw InputError(source, ln,
                       "a face of " + std::to_string(n) + " vertices needs " + std::to_string(n) +
                           " indices (and at most 4 colour values), got " +
                           std::to_string(f.size() - 1) + " values");
    }
    corners.clear();
    for (std::size_t j = 1; j <= un; ++j) {
      const std::int64_t idx = to_int64(f[j], source, ln, "vertex index");
      if (idx < 0 || idx >= nv) {
        throw InputError(source, ln,
                         "vertex index " + std::to_string(idx) + " out of range (" +
                             std::to_string(nv) + " vertices)");
      }
      corners.push_back(idx);
    }
    for (std::size_t j = un + 1; j < f.size(); ++j) to_double(f[j], source, ln, "colour");
    add_fan(mesh, corners.data(), corners.size());
  }
  if (next_content(cursor, f)) {
    throw InputError(source, cursor.line_number(), "extra data after the last face");
  }
  return mesh;
}

TriMesh read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return parse_mesh_ply(read_whole_file(path), path);
  if (ext == ".obj") return parse_mesh_obj(read_whole_file(path), path);
  if (ext == ".off") return parse_mesh_off(read_whole_file(path), path);
  throw InputError(path, 0, "unknown mesh format '" + ext + "' (supported: .ply, .obj, .off)");
}

namespace {

void check_mesh_extension(const std::string& ext, const std::string& path) {
  if (ext != ".ply" && ext != ".obj" && ext != ".off" && ext != ".glb") {
    throw InvalidArgument("write_mesh: unknown format '" + ext + "' for '" + path +
                          "' (supported: .ply, .obj, .off, .glb)");
  }
}

void write_one(const TriMesh& mesh, const std::string& path, const std::string& ext,
               const MeshWriteOptions& options) {
  if (ext == ".glb") {
    write_file_atomically(
        path,
        [&](std::ostream& out) {
          io::write_glb(std::span(&mesh, 1), options.normals, options.uvs, out);
        },
        FileMode::kBinary);
  } else if (ext == ".ply") {
    write_file_atomically(
        path, [&](std::ostream& out) { write_ply(mesh, options, out); }, FileMode::kBinary);
  } else if (ext == ".obj") {
    write_file_atomically(path, [&](std::ostream& out) { write_obj(mesh, options, out); });
  } else {
    write_file_atomically(path, [&](std::ostream& out) { write_off(mesh, options, out); });
  }
}

}  // namespace

void write_mesh(const TriMesh& mesh, const std::string& path, const MeshWriteOptions& options) {
  const std::string ext = lower_extension(path);
  check_mesh_extension(ext, path);
  check_writable(mesh);
  write_one(mesh, path, ext, options);
}

std::vector<std::string> lod_paths(const std::string& path, std::size_t levels) {
  const std::string ext = lower_extension(path);
  if (levels <= 1 || ext == ".glb") return {path};
  const std::size_t dot = path.size() - ext.size();
  std::vector<std::string> paths;
  for (std::size_t k = 0; k < levels; ++k) {
    paths.push_back(path.substr(0, dot) + ".lod" + std::to_string(k) + path.substr(dot));
  }
  return paths;
}

std::vector<std::string> write_mesh_lods(std::span<const TriMesh> levels, const std::string& path,
                                         const MeshWriteOptions& options) {
  const std::string ext = lower_extension(path);
  check_mesh_extension(ext, path);
  if (levels.empty()) throw InvalidArgument("write_mesh_lods: no level to write");
  for (const TriMesh& m : levels) check_writable(m);
  const std::vector<std::string> paths = lod_paths(path, levels.size());
  if (ext == ".glb") {
    write_file_atomically(
        path,
        [&](std::ostream& out) { io::write_glb(levels, options.normals, options.uvs, out); },
        FileMode::kBinary);
    return paths;
  }
  // One file per level; a level that cannot be written removes the levels written before it,
  // so that a failure leaves no partial set.
  for (std::size_t k = 0; k < levels.size(); ++k) {
    try {
      write_one(levels[k], paths[k], ext, options);
    } catch (...) {
      for (std::size_t j = 0; j < k; ++j) std::remove(paths[j].c_str());
      throw;
    }
  }
  return paths;
}

}  // namespace ramiform
