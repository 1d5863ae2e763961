// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/mesh_io.h"

#include "io/gltf_format.h"
#include "io/obj_format.h"
#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"

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

void check_writable(const TriMesh& mesh) {
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
    throw InvalidArgument("write_mesh: " + std::to_string(mesh.normals.size()) + " normals for " +
                          std::to_string(mesh.positions.size()) + " vertices");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!is_finite(mesh.positions[i])) {
      throw InvalidArgument("write_mesh: vertex " + std::to_string(i) + " is not finite");
    }
  }
  for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
    if (!is_finite(mesh.normals[i])) {
      throw InvalidArgument("write_mesh: normal " + std::to_string(i) + " is not finite");
    }
  }
  const std::size_t n = mesh.positions.size();
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

void append_vec(std::string& t, const Vec3& p) {
  append_double(t, p.x());
  t += ' ';
  append_double(t, p.y());
  t += ' ';
  append_double(t, p.z());
}

void write_ply(const TriMesh& mesh, std::ostream& out) {
  PlyWriter ply(out);
  ply.begin("ramiform mesh");
  std::vector<PlyColumn> columns = {
      {"x", PlyType::kFloat64}, {"y", PlyType::kFloat64}, {"z", PlyType::kFloat64}};
  const bool normals = !mesh.normals.empty();
  if (normals) {
    columns.push_back({"nx", PlyType::kFloat64});
    columns.push_back({"ny", PlyType::kFloat64});
    columns.push_back({"nz", PlyType::kFloat64});
  }
  ply.element("vertex", mesh.positions.size(), columns);
  ply.list_element("face", mesh.triangles.size(), PlyType::kUInt8, PlyType::kUInt32,
                   "vertex_indices");
  ply.end_header();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, mesh.positions[i][c]);
    if (normals) {
      for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, mesh.normals[i][c]);
    }
  }
  for (const auto& t : mesh.triangles) {
    ply.put_index(PlyType::kUInt8, 3);
    for (const std::uint32_t v : t) ply.put_index(PlyType::kUInt32, v);
  }
  ply.flush(true);
}

void write_obj(const TriMesh& mesh, std::ostream& out) {
  TextSink sink(out);
  sink.text() += "# ramiform mesh\n";
  for (const Vec3& p : mesh.positions) {
    sink.text() += "v ";
    append_vec(sink.text(), p);
    sink.text() += '\n';
    sink.line_done();
  }
  for (const Vec3& n : mesh.normals) {
    sink.text() += "vn ";
    append_vec(sink.text(), n);
    sink.text() += '\n';
    sink.line_done();
  }
  const bool normals = !mesh.normals.empty();
  for (const auto& tri : mesh.triangles) {
    std::string& t = sink.text();
    t += 'f';
    for (const std::uint32_t v : tri) {
      t += ' ';
      append_uint(t, std::uint64_t{v} + 1);
      if (normals) {
        t += "//";
        append_uint(t, std::uint64_t{v} + 1);
      }
    }
    t += '\n';
    sink.line_done();
  }
  sink.flush();
}

void write_off(const TriMesh& mesh, std::ostream& out) {
  TextSink sink(out);
  std::string& head = sink.text();
  head += "OFF\n";
  append_uint(head, mesh.positions.size());
  head += ' ';
  append_uint(head, mesh.triangles.size());
  head += " 0\n";
  for (const Vec3& p : mesh.positions) {
    append_vec(sink.text(), p);
    sink.text() += '\n';
    sink.line_done();
  }
  for (const auto& tri : mesh.triangles) {
    std::string& t = sink.text();
    t += '3';
    for (const std::uint32_t v : tri) {
      t += ' ';
      append_uint(t, v);
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
  for (std::size_t i = 0; i < nv; ++i) {
    const double* row = &data[0].scalars[i * cols];
    mesh.positions[i] = Vec3(row[0], row[1], row[2]);
    if (has_normals) mesh.normals[i] = Vec3(row[3], row[4], row[5]);
  }
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

void write_mesh(const TriMesh& mesh, const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".obj" && ext != ".off" && ext != ".glb") {
    throw InvalidArgument("write_mesh: unknown format '" + ext + "' for '" + path +
                          "' (supported: .ply, .obj, .off, .glb)");
  }
  check_writable(mesh);
  if (ext == ".glb") {
    write_file_atomically(
        path, [&](std::ostream& out) { io::write_glb(mesh, out); }, FileMode::kBinary);
  } else if (ext == ".ply") {
    write_file_atomically(
        path, [&](std::ostream& out) { write_ply(mesh, out); }, FileMode::kBinary);
  } else if (ext == ".obj") {
    write_file_atomically(path, [&](std::ostream& out) { write_obj(mesh, out); });
  } else {
    write_file_atomically(path, [&](std::ostream& out) { write_off(mesh, out); });
  }
}

}  // namespace ramiform
