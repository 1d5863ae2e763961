// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The props entry point: distribution names, their keys, and generate_points, which reads one
// distribution's options from a Props and reports a bad option at the line that set it.
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/sample/point_sets.h"
#include "ramiform/sample/props.h"
#include "sample/option_checks.h"

namespace ramiform {

using namespace sample_detail;

namespace {

/// Reads options from props and maps failed option checks to the props line that set them.
class OptionReader {
 public:
  OptionReader(const Props& props, const std::string& name)
      : in_(props, distribution_keys(name), "distribution '" + name + "'") {}

  const PropsReader& in() const { return in_; }

  /// Throws InputError at the key's line when the check failed. Option names equal the keys,
  /// except the two flags.
  void raise(const Check& c) const {
    if (!c) return;
    std::string key = c->option;
    if (key == "use_cache") key = "cache";
    if (key == "use_lane_grid") key = "lane_grid";
    in_.fail(key, c->problem);
  }

 private:
  PropsReader in_;
};

PoissonOptions poisson_options(const OptionReader& r, std::size_t count) {
  PoissonOptions o;
  o.count = count;
  o.min_distance = r.in().number("min_distance", 0.0);
  o.max_failures = r.in().count("max_failures", o.max_failures);
  o.max_attempts = r.in().count("max_attempts", 0);
  r.raise(check(o));
  return o;
}

LaneOptions lane_options(const OptionReader& r, std::size_t count) {
  LaneOptions o;
  o.count = count;
  try {
    o.kernel = LaneKernel::parse(r.in().text("kernel", "none"));
  } catch (const InvalidArgument& e) {
    r.in().fail("kernel", e.what());
  }
  o.grid = r.in().count("grid", o.grid);
  o.prune_grid = r.in().flag("prune_grid", o.prune_grid);
  o.max_attempts = r.in().count("max_attempts", 0);
  r.raise(check(o));
  return o;
}

FieldDensityOptions field_options(const OptionReader& r, std::size_t count, double iso) {
  FieldDensityOptions o;
  o.count = count;
  o.exponent = r.in().number("exponent", o.exponent);
  o.min_distance = r.in().number("min_distance", 0.0);
  o.max_attempts = r.in().count("max_attempts", 0);
  r.raise(check(o, iso));
  return o;
}

BoundaryOptions boundary_options(const OptionReader& r, std::size_t count) {
  BoundaryOptions o;
  o.count = count;
  o.width = r.in().number("width", 0.0);
  o.interior_density = r.in().number("interior_density", 0.0);
  o.min_distance = r.in().number("min_distance", 0.0);
  o.max_attempts = r.in().count("max_attempts", 0);
  r.raise(check(o));
  return o;
}

NearSurfaceOptions::Method near_method(const PropsReader& in) {
  const std::string method = in.text("method", "project");
  if (method == "reject") return NearSurfaceOptions::Method::kReject;
  if (method != "project") in.fail("method", "must be project or reject");
  return NearSurfaceOptions::Method::kProject;
}

NearSurfaceOptions near_surface_options(const OptionReader& r, std::size_t count) {
  const PropsReader& in = r.in();
  NearSurfaceOptions o;
  o.count = count;
  o.epsilon = in.number("epsilon", o.epsilon);
  o.min_distance = in.number("min_distance", 0.0);
  o.method = near_method(in);
  o.project_width = in.number("project_width", 0.0);
  o.use_cache = in.flag("cache", false);
  o.cache_cell = in.number("cache_cell", 0.0);
  o.cache_tolerance = in.number("cache_tolerance", 0.0);
  o.use_lane_grid = in.flag("lane_grid", false);
  o.grid = in.count("grid", o.grid);
  o.prune = in.flag("prune", o.prune);
  o.max_attempts = in.count("max_attempts", 0);
  r.raise(check(o));
  return o;
}

// Reads the options of distribution `name` and samples.
PointSet sample_with(const Field& field, const std::string& name, const OptionReader& r,
                     std::size_t count, std::uint64_t seed, Context* ctx, SampleStats* stats) {
  if (name == "uniform") {
    UniformOptions o;
    o.count = count;
    o.max_attempts = r.in().count("max_attempts", 0);
    return sample_uniform(field, o, seed, ctx, stats);
  }
  if (name == "stratified") {
    StratifiedOptions o;
    o.count = count;
    return sample_stratified(field, o, seed, ctx, stats);
  }
  if (name == "poisson") return sample_poisson(field, poisson_options(r, count), seed, ctx, stats);
  if (name == "lane") return sample_lane(field, lane_options(r, count), seed, ctx, stats);
  if (name == "field") {
    return sample_field_density(field, field_options(r, count, field.iso()), seed, ctx, stats);
  }
  if (name == "boundary") {
    return sample_boundary(field, boundary_options(r, count), seed, ctx, stats);
  }
  // near_surface (distribution_keys rejected every other name)
  return sample_near_surface(field, near_surface_options(r, count), seed, ctx, stats);
}

}  // namespace

std::vector<std::string> distribution_names() {
  return {"uniform", "stratified", "poisson", "lane", "field", "boundary", "near_surface"};
}

std::vector<std::string> distribution_keys(const std::string& name) {
  if (name == "uniform") return {"count", "max_attempts"};
  if (name == "stratified") return {"count"};
  if (name == "poisson") return {"count", "min_distance", "max_failures", "max_attempts"};
  if (name == "lane") return {"count", "kernel", "grid", "prune_grid", "max_attempts"};
  if (name == "field") return {"count", "exponent", "min_distance", "max_attempts"};
  if (name == "boundary") {
    return {"count", "width", "interior_density", "min_distance", "max_attempts"};
  }
  if (name == "near_surface") {
    return {"count",         "epsilon", "min_distance", "method",
            "project_width", "cache",   "cache_cell",   "cache_tolerance",
            "lane_grid",     "grid",    "prune",        "max_attempts"};
  }
  const std::string hint = closest_key(name, distribution_names());
  std::string msg = "unknown distribution '" + name + "'";
  if (!hint.empty()) msg += " (did you mean '" + hint + "'?)";
  msg += "; valid:";
  for (const auto& n : distribution_names()) msg += " " + n;
  throw InvalidArgument(msg);
}

PointSet generate_points(const Field& field, const std::string& name, const Props& props,
                         std::uint64_t seed, std::size_t count_override, Context* ctx,
                         SampleStats* stats) {
  const OptionReader r(props, name);
  const bool count_from_props = count_override == 0 && r.in().has("count");
  const std::size_t count = count_override > 0 ? count_override : r.in().count("count", 1000);
  try {
    return sample_with(field, name, r, count, seed, ctx, stats);
  } catch (const ResourceLimit& e) {
    // The samplers refuse a count above the memory budget (check_point_memory); that count
    // was set at a line of the props file, so the message starts there like any bad option.
    if (!count_from_props) throw;
    r.in().fail("count", e.what());
  }
}

}  // namespace ramiform
