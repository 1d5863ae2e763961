// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/particles_io.h"

#include <cmath>

#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"

namespace ramiform {
namespace {

using namespace io_detail;

constexpr std::string_view kVertex[] = {"x", "y", "z", "nx", "ny", "nz", "delta", "cell"};
constexpr std::string_view kSeed[] = {"sx", "sy", "sz", "snx", "sny", "snz"};
constexpr std::string_view kCell[] = {"xmin", "ymin", "zmin", "xmax", "ymax", "zmax", "depth"};

void check_writable(const ParticleSystem& s) {
  if (!std::isfinite(s.iso)) throw InvalidArgument("write_particles: iso is not finite");
  if ((!s.seed_positions.empty() || !s.seed_normals.empty()) && !has_seed_state(s)) {
    throw InvalidArgument("write_particles: " + std::to_string(s.seed_positions.size()) +
                          " seed positions and " + std::to_string(s.seed_normals.size()) +
                          " seed normals for " + std::to_string(s.particles.size()) +
                          " particles (none, or one of each per particle)");
  }
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const SurfaceParticle& p = s.particles[i];
    if (!is_finite(p.position) || !is_finite(p.normal) || !std::isfinite(p.delta)) {
      throw InvalidArgument("write_particles: particle " + std::to_string(i) + " is not finite");
    }
    if (has_seed_state(s) && (!is_finite(s.seed_positions[i]) || !is_finite(s.seed_normals[i]))) {
      throw InvalidArgument("write_particles: particle " + std::to_string(i) +
                            "'s seeding state is not finite");
    }
    if (p.cell >= s.cells.size()) {
      throw InvalidArgument("write_particles: particle " + std::to_string(i) + " refers to cell " +
                            std::to_string(p.cell) + " of " + std::to_string(s.cells.size()));
    }
  }
  if (!s.root.isEmpty() && (!is_finite(s.root.min()) || !is_finite(s.root.max()))) {
    throw InvalidArgument("write_particles: the root cube is not finite");
  }
  for (std::size_t c = 0; c < s.cells.size(); ++c) {
    if (!is_finite(s.cells[c].box.min()) || !is_finite(s.cells[c].box.max())) {
      throw InvalidArgument("write_particles: cell " + std::to_string(c) + " is not finite");
    }
  }
}

// The header lines "comment iso V" (required) and "comment root X0 Y0 Z0 X1 Y1 Z1" (optional);
// the last of each wins.
void header_comments(std::string_view bytes, const PlyHeader& header, const std::string& source,
                     ParticleSystem& s) {
  std::size_t line = 0, pos = 0;
  std::optional<double> iso;
  while (pos < header.body_offset) {
    const std::size_t end = std::min(bytes.find('\n', pos), header.body_offset);
    std::string_view l = bytes.substr(pos, end - pos);
    ++line;
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l.starts_with("comment iso ")) {
      iso = to_double(l.substr(12), source, line, "iso");
    } else if (l.starts_with("comment root ")) {
      std::vector<std::string_view> f;
      split_fields(l.substr(13), f);
      if (f.size() != 6) {
        throw InputError(source, line,
                         "comment root: expected 6 numbers (the root cube's min and max), got " +
                             std::to_string(f.size()));
      }
      double v[6];
      for (int k = 0; k < 6; ++k) v[k] = to_double(f[k], source, line, "root");
      s.root = Aabb(Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]));
      if (s.root.isEmpty()) throw InputError(source, line, "comment root: min exceeds max");
    }
    pos = end + 1;
  }
  if (!iso) {
    throw InputError(source, 0,
                     "no 'comment iso <value>' line in the header (not a particle file?)");
  }
  s.iso = *iso;
}

PlyRequest request_for(const PlyHeader& header, std::string_view element,
                       std::span<const std::string_view> names, std::span<const PlyType> types,
                       const std::string& source) {
  const auto e = header.find(element);
  if (!e)
    throw InputError(source, header.end_header_line, "no element '" + std::string(element) + "'");
  const PlyElement& el = header.elements[*e];
  PlyRequest r;
  r.element = *e;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::size_t idx = require_scalar(el, names[k], source);
    if (el.properties[idx].type != types[k]) {
      throw InputError(source, el.header_line,
                       "element '" + std::string(element) + "': property '" +
                           std::string(names[k]) + "' has the wrong type (expected " +
                           (types[k] == PlyType::kFloat64  ? "double"
                            : types[k] == PlyType::kUInt32 ? "uint"
                                                           : "int") +
                           ")");
    }
    r.scalars.push_back(idx);
  }
  return r;
}

}  // namespace

void write_particles(const ParticleSystem& s, const std::string& path) {
  check_writable(s);
  const bool seeded = has_seed_state(s);
  std::string iso_text;
  append_double(iso_text, s.iso);
  std::string root_text;
  if (!s.root.isEmpty()) {
    root_text = "\ncomment root";
    for (int k = 0; k < 6; ++k) {
      root_text += ' ';
      append_double(root_text, k < 3 ? s.root.min()[k] : s.root.max()[k - 3]);
    }
  }
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        PlyWriter ply(out);
        ply.begin("ramiform particles\ncomment iso " + iso_text + root_text);
        std::vector<PlyColumn> vertex;
        vertex.reserve(8);
        for (int k = 0; k < 7; ++k) vertex.push_back({std::string(kVertex[k]), PlyType::kFloat64});
        vertex.push_back({"cell", PlyType::kUInt32});
        if (seeded) {
          for (std::string_view name : kSeed)
            vertex.push_back({std::string(name), PlyType::kFloat64});
        }
        ply.element("vertex", s.particles.size(), vertex);
        std::vector<PlyColumn> cell;
        cell.reserve(7);
        for (int k = 0; k < 6; ++k) cell.push_back({std::string(kCell[k]), PlyType::kFloat64});
        cell.push_back({"depth", PlyType::kInt32});
        ply.element("cell", s.cells.size(), cell);
        ply.end_header();
        for (const SurfaceParticle& p : s.particles) {
          for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, p.position[c]);
          for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, p.normal[c]);
          ply.put(PlyType::kFloat64, p.delta);
          ply.put_index(PlyType::kUInt32, p.cell);
          if (seeded) {
            const auto i = static_cast<std::size_t>(&p - s.particles.data());
            for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, s.seed_positions[i][c]);
            for (int c = 0; c < 3; ++c) ply.put(PlyType::kFloat64, s.seed_normals[i][c]);
          }
          ply.flush();
        }
        for (const ParticleCell& c : s.cells) {
          for (int a = 0; a < 3; ++a) ply.put(PlyType::kFloat64, c.box.min()[a]);
          for (int a = 0; a < 3; ++a) ply.put(PlyType::kFloat64, c.box.max()[a]);
          ply.put(PlyType::kInt32, static_cast<double>(c.depth));
          ply.flush();
        }
        ply.flush(true);
      },
      FileMode::kBinary);
}

ParticleSystem parse_particles(std::string_view bytes, const std::string& source) {
  const PlyHeader header = parse_ply_header(bytes, source);
  if (header.encoding != PlyEncoding::kBinaryLittleEndian) {
    throw InputError(source, 2, "particle files are binary little-endian PLY");
  }
  ParticleSystem s;
  header_comments(bytes, header, source, s);
  constexpr PlyType kV[] = {PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64,
                            PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64,
                            PlyType::kFloat64, PlyType::kUInt32};
  constexpr PlyType kC[] = {PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64,
                            PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64,
                            PlyType::kInt32};
  PlyRequest rv = request_for(header, "vertex", kVertex, kV, source);
  // The seeding state (sx sy sz snx sny snz): all six or none.
  const PlyElement& vertex = header.elements[rv.element];
  std::size_t seed_props = 0;
  for (std::string_view name : kSeed) seed_props += optional_scalar(vertex, name, source) ? 1 : 0;
  const bool seeded = seed_props == std::size(kSeed);
  if (seed_props != 0 && !seeded) {
    throw InputError(source, vertex.header_line,
                     "element 'vertex': the seeding state needs all of sx sy sz snx sny snz, got " +
                         std::to_string(seed_props) + " of them");
  }
  if (seeded) {
    constexpr PlyType kS[] = {PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64,
                              PlyType::kFloat64, PlyType::kFloat64, PlyType::kFloat64};
    const PlyRequest more = request_for(header, "vertex", kSeed, kS, source);
    rv.scalars.insert(rv.scalars.end(), more.scalars.begin(), more.scalars.end());
  }
  const std::size_t row_size = rv.scalars.size();
  const PlyRequest rc = request_for(header, "cell", kCell, kC, source);
  const std::vector<PlyElementData> data = read_ply_body(bytes, header, {rv, rc}, source);
  s.cells.resize(data[1].count);
  for (std::size_t c = 0; c < data[1].count; ++c) {
    const double* row = &data[1].scalars[c * 7];
    s.cells[c].box = Aabb(Vec3(row[0], row[1], row[2]), Vec3(row[3], row[4], row[5]));
    if (s.cells[c].box.isEmpty())
      throw InputError(source, "cell", c, "the box's min exceeds its max");
    if (row[6] < 0 || row[6] > ParticleOptions::kMaxDepth) {
      throw InputError(source, "cell", c,
                       "depth " + format_number(row[6]) + " outside [0, " +
                           std::to_string(ParticleOptions::kMaxDepth) + "]");
    }
    s.cells[c].depth = static_cast<int>(row[6]);
  }
  s.particles.resize(data[0].count);
  if (seeded) {
    s.seed_positions.resize(data[0].count);
    s.seed_normals.resize(data[0].count);
  }
  for (std::size_t i = 0; i < data[0].count; ++i) {
    const double* row = &data[0].scalars[i * row_size];
    SurfaceParticle& p = s.particles[i];
    p.position = Vec3(row[0], row[1], row[2]);
    p.normal = Vec3(row[3], row[4], row[5]);
    p.delta = row[6];
    if (!(p.delta > 0)) {
      throw InputError(source, "vertex", i,
                       "delta " + format_number(p.delta) + ": a repulsion radius must be > 0");
    }
    if (row[7] >= static_cast<double>(s.cells.size())) {
      throw InputError(source, "vertex", i,
                       "cell index " + format_number(row[7]) + " out of range (" +
                           std::to_string(s.cells.size()) + " cells)");
    }
    p.cell = static_cast<std::uint32_t>(row[7]);
    if (seeded) {
      s.seed_positions[i] = Vec3(row[8], row[9], row[10]);
      s.seed_normals[i] = Vec3(row[11], row[12], row[13]);
    }
  }
  return s;
}

ParticleSystem read_particles(const std::string& path) {
  return parse_particles(read_whole_file(path), path);
}

}  // namespace ramiform
