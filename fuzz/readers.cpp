// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The readers' fuzz harness, compiled once per harness with one of the defines below
// (fuzz/CMakeLists.txt). Each writes the input to a file with the harness's extension (one file
// per process, reused) and reads it through the public reader, since the readers take paths. An
// InputError is the documented answer to a bad file; a file that is read must keep the reader's
// documented guarantees (finite values, indices in range, a skeleton that passes validate() and
// reads back identically from its JSON).

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.h"
#include "ramiform/io/curve_io.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/qsm_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/sample/props.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::fuzz {
namespace {

enum class Reader {
  kSkeletonJson,
  kSkeletonPly,
  kSkeletonObj,
  kTreeQsm,
  kSimpleForest,
  kMeshPly,
  kMeshObj,
  kMeshOff,
  kPointsText,
  kPointsPly,
  kProps,
  kCurve2,
  kCurve3,
  kSwc,
  kParticlesPly,
};

#if defined(RAMIFORM_FUZZ_SKELETON_JSON)
constexpr Reader kReader = Reader::kSkeletonJson;
constexpr const char* kExtension = ".json";
#elif defined(RAMIFORM_FUZZ_SKELETON_PLY)
constexpr Reader kReader = Reader::kSkeletonPly;
constexpr const char* kExtension = ".ply";
#elif defined(RAMIFORM_FUZZ_SKELETON_OBJ)
constexpr Reader kReader = Reader::kSkeletonObj;
constexpr const char* kExtension = ".obj";
#elif defined(RAMIFORM_FUZZ_TREEQSM)
constexpr Reader kReader = Reader::kTreeQsm;
constexpr const char* kExtension = ".txt";  // read_skeleton: TreeQSM unless a SimpleForest header
#elif defined(RAMIFORM_FUZZ_SIMPLEFOREST)
constexpr Reader kReader = Reader::kSimpleForest;
constexpr const char* kExtension = ".csv";
#elif defined(RAMIFORM_FUZZ_MESH_PLY)
constexpr Reader kReader = Reader::kMeshPly;
constexpr const char* kExtension = ".ply";
#elif defined(RAMIFORM_FUZZ_MESH_OBJ)
constexpr Reader kReader = Reader::kMeshObj;
constexpr const char* kExtension = ".obj";
#elif defined(RAMIFORM_FUZZ_MESH_OFF)
constexpr Reader kReader = Reader::kMeshOff;
constexpr const char* kExtension = ".off";
#elif defined(RAMIFORM_FUZZ_POINTS_TEXT)
constexpr Reader kReader = Reader::kPointsText;
constexpr const char* kExtension = ".xyz";
#elif defined(RAMIFORM_FUZZ_POINTS_PLY)
constexpr Reader kReader = Reader::kPointsPly;
constexpr const char* kExtension = ".ply";
#elif defined(RAMIFORM_FUZZ_PROPS)
constexpr Reader kReader = Reader::kProps;
constexpr const char* kExtension = ".props";
#elif defined(RAMIFORM_FUZZ_CURVE2)
constexpr Reader kReader = Reader::kCurve2;
constexpr const char* kExtension = ".txt";
#elif defined(RAMIFORM_FUZZ_CURVE3)
constexpr Reader kReader = Reader::kCurve3;
constexpr const char* kExtension = ".txt";
#elif defined(RAMIFORM_FUZZ_SWC)
constexpr Reader kReader = Reader::kSwc;
constexpr const char* kExtension = ".swc";
#elif defined(RAMIFORM_FUZZ_PARTICLES_PLY)
constexpr Reader kReader = Reader::kParticlesPly;
constexpr const char* kExtension = ".ply";
#else
#error "compile with one RAMIFORM_FUZZ_<HARNESS> define (fuzz/CMakeLists.txt)"
#endif

bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

// A returned skeleton passes validate() and its JSON reads back to the same nodes and edges.
void check_skeleton(const Skeleton& s) {
  validate(s, "fuzz");
  require(s.node_types.empty() || s.node_types.size() == s.nodes.size(),
          "node types: none or one per node");
  const Skeleton back = parse_skeleton_json(skeleton_to_json(s), "round-trip");
  require(back.nodes.size() == s.nodes.size() && back.edges == s.edges,
          "skeleton JSON round trip keeps nodes and edges");
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    require(
        back.nodes[i].position == s.nodes[i].position && back.nodes[i].radius == s.nodes[i].radius,
        "skeleton JSON round trip keeps positions and radii bit for bit");
  }
  require(back.has_curves() == s.has_curves(), "skeleton JSON round trip keeps curved edges");
  for (std::size_t e = 0; e < s.curves.size() && back.has_curves(); ++e) {
    require(back.curves[e].controls == s.curves[e].controls &&
                back.curves[e].radii == s.curves[e].radii,
            "skeleton JSON round trip keeps control points and radii bit for bit");
  }
}

void check_mesh(const TriMesh& m) {
  for (const Vec3& p : m.positions) require(finite(p), "mesh positions are finite");
  for (const auto& t : m.triangles) {
    for (std::uint32_t v : t) require(v < m.positions.size(), "triangle indices are in range");
  }
  require(m.normals.empty() || m.normals.size() == m.positions.size(),
          "mesh normals: none or one per vertex");
  for (const Vec3& n : m.normals) require(finite(n), "mesh normals are finite");
  require(m.vertex_labels.empty() || m.vertex_labels.size() == m.positions.size(),
          "mesh labels (swc_type): none or one per vertex");
}

void check_points(const PointSet& p) {
  require(p.size() > 0, "a point set that is read has points ('no points at all' throws)");
  for (const Vec3& v : p.positions) require(finite(v), "point positions are finite");
  require(p.normals.empty() || p.normals.size() == p.positions.size(),
          "point normals: none or one per point");
  for (const Vec3& n : p.normals) require(finite(n), "point normals are finite");
}

// A particle state that is read has finite values, positive radii, cells in range, and writes
// back to a file that reads to the same state.
void check_particles(const ParticleSystem& s) {
  require(std::isfinite(s.iso), "particle iso is finite");
  for (const ParticleCell& c : s.cells) {
    require(finite(c.box.min()) && finite(c.box.max()), "particle cells are finite");
  }
  for (const SurfaceParticle& p : s.particles) {
    require(finite(p.position) && finite(p.normal), "particles are finite");
    require(std::isfinite(p.delta) && p.delta > 0, "particle radii are finite and positive");
    require(p.cell < s.cells.size(), "particle cell indices are in range");
  }
  static const std::string back = (scratch_dir() / "round_trip_particles.ply").string();
  write_particles(s, back);
  const ParticleSystem again = read_particles(back);
  require(again.particles.size() == s.particles.size() && again.cells.size() == s.cells.size(),
          "particle state round trip keeps the counts");
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    require(again.particles[i].position == s.particles[i].position &&
                again.particles[i].delta == s.particles[i].delta &&
                again.particles[i].cell == s.particles[i].cell,
            "particle state round trip is exact");
  }
}

template <class Point>
void check_curve(const std::vector<Point>& points) {
  require(!points.empty(), "a curve file that is read has points ('no points' throws)");
  for (const Point& p : points) require(p.allFinite(), "curve points are finite");
}

// Every key through every typed accessor (each may refuse its value), then a reader that knows
// two keys only, which refuses any other key with a suggestion.
void check_props(const Props& props) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : props.values) {
    require(!value.first.empty() && value.second > 0, "props values are non-empty, lines 1-based");
    keys.push_back(key);
  }
  const PropsReader all(props, keys, "fuzz");
  for (const std::string& key : keys) {
    require(all.has(key), "PropsReader::has sees every key");
    expect_input_errors_only([&] { (void)all.number(key, 0.0); });
    expect_input_errors_only([&] { (void)all.count(key, 0); });
    expect_input_errors_only([&] { (void)all.flag(key, false); });
    require(all.text(key, "") == props.values.at(key).first, "PropsReader::text is the value");
  }
  expect_input_errors_only([&] {
    const PropsReader some(props, {"count", "min_distance"}, "fuzz");
  });
}

void run(const std::uint8_t* data, std::size_t size) {
  static const std::string path = (scratch_dir() / (std::string("input") + kExtension)).string();
  if (kReader != Reader::kProps) write_file(path, data, size);
  switch (kReader) {
    case Reader::kSkeletonJson:
    case Reader::kSkeletonPly:
    case Reader::kTreeQsm:
    case Reader::kSimpleForest:
    case Reader::kSwc:
      read_then_check(
          [&] {
            QsmImportReport report;
            SkeletonReadOptions options;
            options.qsm_report = &report;
            return read_skeleton(path, options);
          },
          check_skeleton);
      break;
    case Reader::kSkeletonObj:
      read_then_check(
          [&] {
            SkeletonReadOptions options;
            options.obj_radius = 0.01;
            return read_skeleton(path, options);
          },
          check_skeleton);
      break;
    case Reader::kMeshPly:
    case Reader::kMeshObj:
    case Reader::kMeshOff:
      read_then_check([&] { return read_mesh(path); }, check_mesh);
      break;
    case Reader::kPointsText:
    case Reader::kPointsPly:
      read_then_check([&] { return read_points(path); }, check_points);
      break;
    case Reader::kParticlesPly:
      read_then_check([&] { return read_particles(path); }, check_particles);
      break;
    case Reader::kCurve2:
      read_then_check([&] { return read_points2(path); }, check_curve<Vec2>);
      break;
    case Reader::kCurve3:
      read_then_check([&] { return read_points3(path); }, check_curve<Vec3>);
      break;
    case Reader::kProps: {
      // parse_props takes text; read_props only adds the file read.
      const std::string_view text(reinterpret_cast<const char*>(data), size);
      read_then_check([&] { return parse_props(text, "fuzz.props"); }, check_props);
      break;
    }
  }
}

}  // namespace
}  // namespace ramiform::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ramiform::fuzz::run(data, size);
  return 0;
}
