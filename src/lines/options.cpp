// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <cmath>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

void require(bool ok, const char* name, double value, const char* range) {
  if (!ok) {
    throw InvalidArgument(std::string("line options: ") + name + " must be " + range + ", got " +
                          format_shortest(value));
  }
}

}  // namespace

std::string_view line_kind_name(LineKind kind) {
  switch (kind) {
    case LineKind::kSilhouette:
      return "silhouette";
    case LineKind::kSuggestive:
      return "suggestive";
    case LineKind::kFeature:
      return "feature";
  }
  return "unknown";
}

void select_line_kinds(LineOptions& options, const std::vector<std::string>& kinds) {
  options.silhouettes = options.suggestive = options.features = false;
  for (const std::string& k : kinds) {
    if (k == line_kind_name(LineKind::kSilhouette)) {
      options.silhouettes = true;
    } else if (k == line_kind_name(LineKind::kSuggestive)) {
      options.suggestive = true;
    } else if (k == line_kind_name(LineKind::kFeature)) {
      options.features = true;
    } else {
      throw InvalidArgument("unknown line kind '" + k +
                            "' (kinds: silhouette, suggestive, feature)");
    }
  }
}

Visibility visibility_from_name(std::string_view name) {
  if (name == "rays") return Visibility::kRays;
  if (name == "surfels") return Visibility::kSurfels;
  if (name == "none") return Visibility::kNone;
  throw InvalidArgument("visibility must be rays, surfels or none, got '" + std::string(name) +
                        "'");
}

StraddleSource straddle_from_name(std::string_view name) {
  if (name == "auto") return StraddleSource::kAuto;
  if (name == "movement") return StraddleSource::kMovement;
  if (name == "search") return StraddleSource::kSearch;
  throw InvalidArgument("straddle must be auto, movement or search, got '" + std::string(name) +
                        "'");
}

SuggestiveFit fit_from_name(std::string_view name) {
  if (name == "longest") return SuggestiveFit::kLongestPath;
  if (name == "trim") return SuggestiveFit::kTrim;
  throw InvalidArgument("fit must be longest or trim, got '" + std::string(name) + "'");
}

void validate(const LineOptions& o) {
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
  require(o.k_c > 0 && o.k_c < 1, "k_c", o.k_c, "in (0, 1)");
  require(std::isfinite(o.k_e) && o.k_e >= 1, "k_e", o.k_e, ">= 1");
  require(o.k_c * o.k_e < 1, "k_c * k_e", o.k_c * o.k_e, "below 1");
  require(finite_positive(o.silhouette_step), "silhouette_step", o.silhouette_step, "> 0");
  require(std::isfinite(o.chain_distance) && o.chain_distance >= 0, "chain_distance",
          o.chain_distance, ">= 0");
  require(finite_positive(o.k_d), "k_d", o.k_d, "> 0");
  require(o.theta_sc_deg >= 0 && o.theta_sc_deg < 90, "theta_sc", o.theta_sc_deg,
          "in [0, 90) degrees");
  require(finite_positive(o.cluster_radius), "cluster_radius", o.cluster_radius, "> 0");
  require(o.cluster_k >= 1 && o.cluster_k <= 64, "cluster_k", o.cluster_k, "in 1..64");
  require(o.k_trim >= 1, "k_trim", o.k_trim, ">= 1");
  require(o.smoothing >= 0 && o.smoothing <= 100, "smoothing", o.smoothing, "in 0..100");
  require(o.min_cluster >= 2, "min_cluster", o.min_cluster, ">= 2");
  require(std::isfinite(o.t_d) && o.t_d >= 0, "t_d", o.t_d, ">= 0");
  require(std::isfinite(o.min_line_length) && o.min_line_length >= 0, "min_line_length",
          o.min_line_length, ">= 0");
  require(o.k_a_deg > 0 && o.k_a_deg < 180, "k_a", o.k_a_deg, "in (0, 180) degrees");
  require(finite_positive(o.straddle_radius), "straddle_radius", o.straddle_radius, "> 0");
  require(o.straddle == StraddleSource::kAuto || o.straddle == StraddleSource::kMovement ||
              o.straddle == StraddleSource::kSearch,
          "straddle", static_cast<double>(o.straddle), "auto, movement or search (0..2)");
  require(std::isfinite(o.occlusion_tolerance) && o.occlusion_tolerance >= 0, "occlusion_tolerance",
          o.occlusion_tolerance, ">= 0");
  require(o.surfel_resolution >= 16 && o.surfel_resolution <= 16384, "surfel_resolution",
          o.surfel_resolution, "in 16..16384");
}

}  // namespace ramiform
