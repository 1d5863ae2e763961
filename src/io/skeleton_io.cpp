// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/skeleton_io.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/obj_format.h"
#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"
#include "ramiform/io/qsm_io.h"

namespace ramiform {
namespace {

using io_detail::append_double;
using io_detail::append_uint;
using json = nlohmann::json;

constexpr std::uint64_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

// Converts nlohmann's byte position (1-based, the character where parsing stopped) to a 1-based
// line and column.
void locate(std::string_view text, std::size_t byte, std::size_t& line, std::size_t& column) {
  const std::size_t stop = std::min(byte == 0 ? 0 : byte - 1, text.size());
  line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < stop; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  column = stop - line_start + 1;
}

// nlohmann's message without its "[json.exception.KIND.ID] " and "parse error at ...: "
// prefixes, as printable text (the "last read" part can hold any bytes of the file).
std::string json_detail(const char* what) {
  std::string s(what);
  if (s.rfind("[json.exception.", 0) == 0) {
    const std::size_t p = s.find("] ");
    if (p != std::string::npos) s.erase(0, p + 2);
  }
  if (s.rfind("parse error", 0) == 0) {
    const std::size_t p = s.find(": ");
    if (p != std::string::npos) s.erase(0, p + 2);
  }
  return io_detail::printable(s);
}

// Where the parser stopped on an error that nlohmann reports without a position (a number too
// large for a double, out_of_range 406): the byte position from a second, SAX-only parse.
class ErrorPosition : public json::json_sax_t {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception&) override {
    position_ = position;
    return false;
  }
  [[nodiscard]] std::size_t position() const { return position_; }

 private:
  std::size_t position_ = 0;
};

// A JSON value for a message: a scalar as JSON text (non-ASCII escaped), shortened when long;
// an array or object by its kind and size only. (Dumping a deeply nested value recurses once
// per level: 100,000 levels overflow the stack.)
std::string shown(const json& value) {
  if (value.is_array()) return "an array of " + std::to_string(value.size()) + " element(s)";
  if (value.is_object()) return "an object of " + std::to_string(value.size()) + " member(s)";
  std::string text = value.dump(-1, ' ', true);
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

double json_number(const json& value, const std::string& source, const char* element,
                   std::size_t index, const std::string& what) {
  if (!value.is_number()) {
    throw InputError(source, element, index, what + " must be a number, got " + shown(value));
  }
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw InputError(source, element, index, what + " is not finite");
  return v;
}

std::uint32_t json_index(const json& value, const std::string& source, std::size_t edge) {
  if (value.is_number_unsigned() && value.get<std::uint64_t>() <= kMaxIndex) {
    return static_cast<std::uint32_t>(value.get<std::uint64_t>());
  }
  if (value.is_number_integer() && !value.is_number_unsigned()) {
    throw InputError(source, "edge", edge, "negative node index " + shown(value));
  }
  throw InputError(source, "edge", edge,
                   "node indices must be integers in [0, 4294967295], got " + shown(value));
}

EdgeCurve parse_edge_curve(const json& item, const std::string& source, std::size_t e) {
  EdgeCurve curve;
  const auto controls = item.find("controls");
  if (controls != item.end()) {
    if (!controls->is_array()) {
      throw InputError(source, "edge", e, "\"controls\" must be an array of [x, y, z] points");
    }
    for (std::size_t k = 0; k < controls->size(); ++k) {
      const json& c = (*controls)[k];
      const std::string what = "control point " + std::to_string(k);
      if (!c.is_array() || c.size() != 3) {
        throw InputError(source, "edge", e, what + " must be an array of 3 numbers, got " + shown(c));
      }
      Vec3 p;
      for (std::size_t d = 0; d < 3; ++d) p[static_cast<int>(d)] = json_number(c[d], source, "edge", e, what);
      curve.controls.push_back(p);
    }
  }
  const auto radii = item.find("radii");
  if (radii != item.end()) {
    if (!radii->is_array()) {
      throw InputError(source, "edge", e, "\"radii\" must be an array of numbers");
    }
    for (std::size_t k = 0; k < radii->size(); ++k) {
      curve.radii.push_back(
          json_number((*radii)[k], source, "edge", e, "radius " + std::to_string(k)));
    }
  }
  return curve;
}

Skeleton validated(Skeleton s, const std::string& source) {
  validate(s, source);
  return s;
}

void check_writable(const Skeleton& skeleton) {
  try {
    validate(skeleton, "");
  } catch (const InputError& e) {
    throw InvalidArgument("cannot write an invalid skeleton: " + e.problem());
  }
}

void append_json_double(std::string& out, double v) {
  const std::size_t start = out.size();
  append_double(out, v);
  // "1" would read back as an integer and "-0" would lose its sign: keep a fraction part.
  if (out.find_first_of(".e", start) == std::string::npos) out += ".0";
}

}  // namespace

Skeleton parse_skeleton_json(std::string_view text, const std::string& source_name) {
  const std::string& source = source_name;
  if (io_detail::is_blank(text)) throw InputError(source, 0, "file is empty");
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    std::size_t line = 0;
    std::size_t column = 0;
    locate(text, e.byte, line, column);
    throw InputError(
        source, line,
        "JSON syntax error at column " + std::to_string(column) + ": " + json_detail(e.what()));
  } catch (const json::exception& e) {
    ErrorPosition where;
    json::sax_parse(text.begin(), text.end(), &where);
    std::size_t line = 0;
    std::size_t column = 0;
    if (where.position() > 0) locate(text, where.position(), line, column);
    throw InputError(source, line,
                     (line > 0 ? "invalid JSON at column " + std::to_string(column) + ": "
                               : std::string("invalid JSON: ")) +
                         json_detail(e.what()));
  }
  if (!doc.is_object()) {
    throw InputError(source, 0, "the top level must be an object with a \"nodes\" array");
  }
  const auto nodes = doc.find("nodes");
  if (nodes == doc.end()) throw InputError(source, 0, "missing \"nodes\" array");
  if (!nodes->is_array()) throw InputError(source, 0, "\"nodes\" must be an array");

  Skeleton s;
  s.nodes.resize(nodes->size());
  for (std::size_t i = 0; i < nodes->size(); ++i) {
    const json& n = (*nodes)[i];
    if (!n.is_object()) {
      throw InputError(source, "node", i, "must be an object with \"position\" and \"radius\"");
    }
    const auto pos = n.find("position");
    if (pos == n.end()) throw InputError(source, "node", i, "missing \"position\"");
    if (!pos->is_array() || pos->size() != 3) {
      throw InputError(source, "node", i, "\"position\" must be an array of 3 numbers");
    }
    for (int c = 0; c < 3; ++c) {
      s.nodes[i].position[c] =
          json_number((*pos)[static_cast<std::size_t>(c)], source, "node", i, "\"position\"");
    }
    const auto radius = n.find("radius");
    if (radius == n.end()) throw InputError(source, "node", i, "missing \"radius\"");
    s.nodes[i].radius = json_number(*radius, source, "node", i, "\"radius\"");
    const auto type = n.find("type");
    if (i == 0 && type != n.end()) s.node_types.resize(nodes->size());
    if ((type != n.end()) != !s.node_types.empty()) {
      throw InputError(source, "node", i,
                       s.node_types.empty()
                           ? "has a \"type\" but node 0 has none (all nodes or none)"
                           : "missing \"type\" (node 0 has one: all nodes or none)");
    }
    if (type != n.end()) {
      bool in_range = type->is_number_integer();
      if (in_range && type->is_number_unsigned()) {
        in_range = type->get<std::uint64_t>() <=
                   static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
      } else if (in_range) {
        in_range = type->get<std::int64_t>() >= std::numeric_limits<std::int32_t>::min() &&
                   type->get<std::int64_t>() <= std::numeric_limits<std::int32_t>::max();
      }
      if (!in_range) {
        throw InputError(source, "node", i,
                         "\"type\" must be a 32-bit integer, got " + shown(*type));
      }
      s.node_types[i] = static_cast<std::int32_t>(type->get<std::int64_t>());
    }
    const auto end = n.find("end");
    if (end != n.end()) {
      if (!end->is_string() || (*end != "open" && *end != "closed")) {
        throw InputError(source, "node", i,
                         "\"end\" must be \"open\" or \"closed\", got " + shown(*end));
      }
      if (s.open_ends.empty()) s.open_ends.assign(nodes->size(), 0);
      s.open_ends[i] = *end == "open" ? 1 : 0;
    }
  }

  const auto edges = doc.find("edges");
  if (edges != doc.end()) {
    if (!edges->is_array()) throw InputError(source, 0, "\"edges\" must be an array");
    s.edges.resize(edges->size());
    for (std::size_t e = 0; e < edges->size(); ++e) {
      const json& item = (*edges)[e];
      const json* pair = &item;
      if (item.is_object()) {
        // A curved edge: {"nodes": [i, j], "controls": [[x, y, z], ...], "radii": [...]}.
        const auto nodes_of = item.find("nodes");
        if (nodes_of == item.end()) {
          throw InputError(source, "edge", e, "an edge object needs \"nodes\": [i, j]");
        }
        pair = &*nodes_of;
        for (const auto& [key, value] : item.items()) {
          if (key != "nodes" && key != "controls" && key != "radii") {
            throw InputError(source, "edge", e,
                             "unknown key \"" + key + "\" (expected nodes, controls, radii)");
          }
        }
        EdgeCurve curve = parse_edge_curve(item, source, e);
        if (!curve.controls.empty() || !curve.radii.empty()) {
          if (s.curves.empty()) s.curves.resize(edges->size());
          s.curves[e] = std::move(curve);
        }
      }
      if (!pair->is_array() || pair->size() != 2) {
        throw InputError(source, "edge", e,
                         "must be an array of 2 node indices (or an object with \"nodes\")");
      }
      s.edges[e] = {json_index((*pair)[0], source, e), json_index((*pair)[1], source, e)};
    }
  }
  return validated(std::move(s), source);
}

Skeleton parse_skeleton_ply(std::string_view bytes, const std::string& source_name) {
  using namespace io_detail;
  const std::string& source = source_name;
  const PlyHeader header = parse_ply_header(bytes, source);
  std::vector<PlyRequest> requests{vertex_request(header, {"x", "y", "z", "radius"}, source)};
  const auto edge = header.find("edge");
  if (edge) {
    const PlyElement& e = header.elements[*edge];
    PlyRequest r;
    r.element = *edge;
    r.scalars = {require_scalar(e, "vertex1", source), require_scalar(e, "vertex2", source)};
    requests.push_back(r);
  }
  const std::vector<PlyElementData> data = read_ply_body(bytes, header, requests, source);

  Skeleton s;
  s.nodes.resize(data[0].count);
  for (std::size_t i = 0; i < data[0].count; ++i) {
    const double* row = &data[0].scalars[i * 4];
    s.nodes[i].position = Vec3(row[0], row[1], row[2]);
    s.nodes[i].radius = row[3];
  }
  if (edge) {
    s.edges.resize(data[1].count);
    for (std::size_t k = 0; k < data[1].count; ++k) {
      for (int c = 0; c < 2; ++c) {
        const double idx = data[1].scalars[k * 2 + static_cast<std::size_t>(c)];
        if (idx < 0.0 || idx > static_cast<double>(kMaxIndex) || idx != std::floor(idx)) {
          throw InputError(source, "edge", k, "invalid node index " + format_number(idx));
        }
        s.edges[k][static_cast<std::size_t>(c)] = static_cast<std::uint32_t>(idx);
      }
    }
  }
  return validated(std::move(s), source);
}

Skeleton parse_skeleton_obj(std::string_view text, const std::string& source_name,
                            const SkeletonReadOptions& options) {
  using namespace io_detail;
  const std::string& source = source_name;
  if (!(std::isfinite(options.obj_radius) && options.obj_radius > 0.0)) {
    throw InvalidArgument(
        "SkeletonReadOptions::obj_radius must be finite and > 0 to read an OBJ "
        "skeleton (OBJ stores no radii), got " +
        std::to_string(options.obj_radius));
  }
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = skip_bom(text);
  if (is_blank(text)) throw InputError(source, 0, "file is empty");
  Skeleton s;
  LineCursor cursor(text);
  std::vector<std::string_view> f;
  std::string_view v;
  std::string_view vt;
  std::string_view vn;
  while (next_content(cursor, f)) {
    const std::size_t ln = cursor.line_number();
    if (f[0] == "v") {
      s.nodes.push_back({parse_obj_vertex(f, source, ln), options.obj_radius});
    } else if (f[0] == "l") {
      if (f.size() < 3) {
        throw InputError(
            source, ln, "'l' needs at least 2 vertex indices, got " + std::to_string(f.size() - 1));
      }
      std::uint32_t prev = 0;
      for (std::size_t i = 1; i < f.size(); ++i) {
        split_obj_corner(f[i], v, vt, vn, source, ln);
        const std::uint32_t cur = resolve_obj_index(v, s.nodes.size(), source, ln, "vertex");
        if (i > 1) s.edges.push_back({prev, cur});
        prev = cur;
      }
    }
  }
  if (s.nodes.empty()) throw InputError(source, 0, "no vertices ('v' lines)");
  return validated(std::move(s), source);
}

Skeleton read_skeleton(const std::string& path, const SkeletonReadOptions& options) {
  const std::string ext = io_detail::lower_extension(path);
  if (ext == ".json") {
    Skeleton s = parse_skeleton_json(io_detail::read_whole_file(path), path);
    if (options.keep_curves || !s.has_curves()) return s;
    try {
      return straighten_curves(s);
    } catch (const InvalidArgument& e) {
      throw InputError(path, 0, e.what());
    }
  }
  if (ext == ".ply") return parse_skeleton_ply(io_detail::read_whole_file(path), path);
  if (ext == ".obj") {
    if (!(std::isfinite(options.obj_radius) && options.obj_radius > 0.0)) {
      // Checked before reading so the message does not depend on the file's content.
      return parse_skeleton_obj({}, path, options);
    }
    return parse_skeleton_obj(io_detail::read_whole_file(path), path, options);
  }
  if (ext == ".swc") return read_swc(path, options.swc);
  if (ext == ".csv") return read_simpleforest(path, options.qsm_report);
  if (ext == ".txt") {
    const std::string text = io_detail::read_whole_file(path);
    if (looks_like_simpleforest(text)) return parse_simpleforest(text, path, options.qsm_report);
    return parse_treeqsm(text, path, options.qsm_report);
  }
  throw InputError(path, 0,
                   "unknown skeleton format '" + ext +
                       "' (supported: .json, .ply, .obj, .swc, .csv SimpleForest, .txt TreeQSM)");
}

std::string skeleton_to_json(const Skeleton& skeleton) {
  check_writable(skeleton);
  std::string out;
  out.reserve(64 * skeleton.nodes.size() + 24 * skeleton.edges.size() + 32);
  out += "{\n  \"nodes\": [";
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    const SkeletonNode& n = skeleton.nodes[i];
    out += i == 0 ? "\n    " : ",\n    ";
    out += "{\"position\": [";
    append_json_double(out, n.position.x());
    out += ", ";
    append_json_double(out, n.position.y());
    out += ", ";
    append_json_double(out, n.position.z());
    out += "], \"radius\": ";
    append_json_double(out, n.radius);
    if (!skeleton.node_types.empty()) {
      out += ", \"type\": ";
      out += std::to_string(skeleton.node_types[i]);
    }
    if (!skeleton.open_ends.empty() && skeleton.open_ends[i] != 0) out += ", \"end\": \"open\"";
    out += "}";
  }
  out += "\n  ],\n  \"edges\": [";
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const EdgeCurve* curve = skeleton.curves.empty() ? nullptr : &skeleton.curves[e];
    const bool curved = curve != nullptr && !curve->controls.empty();
    out += e == 0 ? "\n    " : ",\n    ";
    out += curved ? "{\"nodes\": [" : "[";
    append_uint(out, skeleton.edges[e][0]);
    out += ", ";
    append_uint(out, skeleton.edges[e][1]);
    out += "]";
    if (curved) {
      out += ", \"controls\": [";
      for (std::size_t k = 0; k < curve->controls.size(); ++k) {
        out += k == 0 ? "[" : ", [";
        for (int c = 0; c < 3; ++c) {
          if (c > 0) out += ", ";
          append_json_double(out, curve->controls[k][c]);
        }
        out += "]";
      }
      out += "]";
      if (!curve->radii.empty()) {
        out += ", \"radii\": [";
        for (std::size_t k = 0; k < curve->radii.size(); ++k) {
          if (k > 0) out += ", ";
          append_json_double(out, curve->radii[k]);
        }
        out += "]";
      }
      out += "}";
    }
  }
  out += skeleton.edges.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

void write_skeleton_json(const Skeleton& skeleton, const std::string& path) {
  const std::string text = skeleton_to_json(skeleton);
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

void write_skeleton(const Skeleton& skeleton, const std::string& path) {
  using namespace io_detail;
  const std::string ext = lower_extension(path);
  if (ext == ".json") return write_skeleton_json(skeleton, path);
  if (ext != ".ply" && ext != ".obj") {
    throw InvalidArgument("write_skeleton: unknown format '" + ext + "' for '" + path +
                          "' (supported: .json, .ply, .obj)");
  }
  check_writable(skeleton);
  if (skeleton.has_curves()) return write_skeleton(straighten_curves(skeleton), path);
  if (ext == ".ply") {
    write_file_atomically(
        path,
        [&](std::ostream& out) {
          PlyWriter ply(out);
          ply.begin("ramiform skeleton");
          ply.element("vertex", skeleton.nodes.size(),
                      {{"x", PlyType::kFloat64},
                       {"y", PlyType::kFloat64},
                       {"z", PlyType::kFloat64},
                       {"radius", PlyType::kFloat64}});
          ply.element("edge", skeleton.edges.size(),
                      {{"vertex1", PlyType::kUInt32}, {"vertex2", PlyType::kUInt32}});
          ply.end_header();
          for (const SkeletonNode& n : skeleton.nodes) {
            for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, n.position[c]);
            ply.put(PlyType::kFloat64, n.radius);
          }
          for (const auto& e : skeleton.edges) {
            ply.put_index(PlyType::kUInt32, e[0]);
            ply.put_index(PlyType::kUInt32, e[1]);
          }
          ply.flush(true);
        },
        FileMode::kBinary);
    return;
  }
  write_file_atomically(path, [&](std::ostream& out) {
    TextSink sink(out);
    sink.text() += "# ramiform skeleton (OBJ stores no radii)\n";
    for (const SkeletonNode& n : skeleton.nodes) {
      std::string& t = sink.text();
      t += "v ";
      append_double(t, n.position.x());
      t += ' ';
      append_double(t, n.position.y());
      t += ' ';
      append_double(t, n.position.z());
      t += '\n';
      sink.line_done();
    }
    for (const auto& e : skeleton.edges) {
      std::string& t = sink.text();
      t += "l ";
      append_uint(t, std::uint64_t{e[0]} + 1);
      t += ' ';
      append_uint(t, std::uint64_t{e[1]} + 1);
      t += '\n';
      sink.line_done();
    }
    sink.flush();
  });
}

}  // namespace ramiform
