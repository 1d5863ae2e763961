// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_checks.h"

#include <cmath>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"

namespace ramiform::detail::tets {
namespace {

// What the bounding point set can resolve:
// - a node's cross-section (jittered by a thousandth of its half size) must stand clear of the
//   rounding of its coordinates, or its corners would coincide;
// - radii and coordinates must lie within [1e-50, 1e50]: the exact in-sphere test multiplies
//   five coordinate differences, which must neither underflow nor overflow;
// - the cross-sections every `station_spacing` radii must stay countable (a 1 m edge with a
//   1e-300 radius would ask for 10^299 of them).
constexpr double kMinRadiusPerCoordinate = 1e-11;
constexpr double kMinScale = 1e-50, kMaxScale = 1e50;
constexpr double kMaxStations = 1 << 24;

void validate_node(const SkeletonNode& n, std::size_t i) {
  const double magnitude = n.position.cwiseAbs().maxCoeff();
  if (n.radius < kMinScale || magnitude > kMaxScale) {
    throw InvalidArgument("tetrahedral polygonizer: node " + std::to_string(i) + ": radius " +
                          format_number(n.radius) + " and coordinates up to " +
                          format_number(magnitude) +
                          " are outside [1e-50, 1e50], where its exact predicates cannot "
                          "underflow or overflow (rescale the skeleton)");
  }
  if (n.radius < kMinRadiusPerCoordinate * magnitude) {
    throw InvalidArgument("tetrahedral polygonizer: node " + std::to_string(i) + ": radius " +
                          format_number(n.radius) + " is below 1e-11 of its largest coordinate (" +
                          format_number(magnitude) +
                          "); its cross-section would vanish in double precision (move the "
                          "skeleton near the origin, or use --method mc)");
  }
}

void validate_station_count(const Skeleton& s, const TetrahedralOptions& o) {
  double stations = 0;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const auto& na = s.nodes[s.edges[e][0]];
    const auto& nb = s.nodes[s.edges[e][1]];
    const double radii = (nb.position - na.position).norm() / (0.5 * (na.radius + nb.radius));
    stations += radii / o.station_spacing;
    if (stations > kMaxStations) {
      throw InvalidArgument("tetrahedral polygonizer: the skeleton needs more than " +
                            format_number(kMaxStations) + " cross-sections (one every " +
                            format_number(o.station_spacing) + " radii; edge " + std::to_string(e) +
                            " alone is " + format_number(radii) +
                            " radii long: are the radii in the skeleton's unit?)");
    }
  }
}

}  // namespace

void validate_options(const TetrahedralOptions& o) {
  auto fail = [](const std::string& m) { throw InvalidArgument("TetrahedralOptions." + m); };
  using O = TetrahedralOptions;
  if (o.levels < O::kMinLevels || o.levels > O::kMaxLevels) {
    fail("levels must be in " + range_text(O::kMinLevels, O::kMaxLevels) + ", got " +
         std::to_string(o.levels));
  }
  if (!(o.section_scale >= O::kMinSectionScale && o.section_scale <= O::kMaxSectionScale)) {
    fail("section_scale must be in " + range_text(O::kMinSectionScale, O::kMaxSectionScale) +
         ", got " + format_number(o.section_scale));
  }
  if (!(o.station_spacing > 0.0) || !std::isfinite(o.station_spacing)) {
    fail("station_spacing must be > 0, got " + std::to_string(o.station_spacing));
  }
  if (o.root_steps < 0 || o.root_steps > 64) fail("root_steps must be in [0, 64]");
  if (!(o.root_value >= TetrahedralOptions::kMinRootValue &&
        o.root_value <= TetrahedralOptions::kMaxRootValue)) {
    fail("root_value must be in [1e-16, 1e-2]");
  }
  if (o.max_growth_rounds < 0) fail("max_growth_rounds must be >= 0");
}

void validate_resolution(const Skeleton& s, const TetrahedralOptions& o) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) validate_node(s.nodes[i], i);
  validate_station_count(s, o);
}

// The peak was measured on generated trees of 1,500 and 20,000 segments: 1.6, 3.7, 12.8 and
// 54 KB per point at levels 0 to 3. A run that cannot fit is refused up front instead of being
// killed by the system after minutes of work.
void check_memory(std::size_t points, const TetrahedralOptions& o, const Context* ctx) {
  const double need = static_cast<double>(points) * 600.0 * pm::pow(4.0, o.levels);
  ramiform::check_memory(ctx, need,
                         "tetrahedral polygonizer: " + std::to_string(points) +
                             " bounding points at --levels " + std::to_string(o.levels),
                         "use fewer levels, or check the radii's units");
}

}  // namespace ramiform::detail::tets
