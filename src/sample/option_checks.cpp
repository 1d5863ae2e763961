// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/option_checks.h"

#include <cmath>

#include "ramiform/core/errors.h"

namespace ramiform::sample_detail {

namespace {

Check check_nonneg(const char* name, double v) {
  if (!std::isfinite(v) || v < 0.0) return OptionError{name, "must be finite and >= 0"};
  return std::nullopt;
}

Check check_grid(std::size_t g) {
  if (g < 2 || g > 512) return OptionError{"grid", "must be in 2..512"};
  return std::nullopt;
}

Check check_project_width(const NearSurfaceOptions& o) {
  if (!std::isfinite(o.project_width) || o.project_width < 0.0 ||
      (o.project_width > 0.0 && o.project_width < o.epsilon)) {
    return OptionError{"project_width", "must be 0 (automatic) or finite and >= epsilon (" +
                                            format_number(o.epsilon) + "), got " +
                                            format_number(o.project_width)};
  }
  return std::nullopt;
}

}  // namespace

Check check(const PoissonOptions& o) {
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  return std::nullopt;
}

Check check(const LaneOptions& o) {
  if (auto e = check_grid(o.grid)) return e;
  try {
    o.kernel.validate();
  } catch (const InvalidArgument& e) {
    return OptionError{"kernel", e.what()};
  }
  return std::nullopt;
}

Check check(const FieldDensityOptions& o, double iso) {
  if (auto e = check_nonneg("exponent", o.exponent)) return e;
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  if (!(iso > 0.0)) {
    return OptionError{"exponent", "density (iso / f)^exponent needs a field with iso > 0 (iso = " +
                                       format_number(iso) + ")"};
  }
  return std::nullopt;
}

Check check(const BoundaryOptions& o) {
  if (auto e = check_nonneg("width", o.width)) return e;
  if (!std::isfinite(o.interior_density) || o.interior_density < 0.0 || o.interior_density > 1.0) {
    return OptionError{"interior_density", "must be in [0, 1]"};
  }
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  return std::nullopt;
}

Check check(const NearSurfaceOptions& o) {
  if (!std::isfinite(o.epsilon) || !(o.epsilon > 0.0)) {
    return OptionError{"epsilon", "must be finite and > 0"};
  }
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  if (auto e = check_nonneg("cache_cell", o.cache_cell)) return e;
  if (auto e = check_nonneg("cache_tolerance", o.cache_tolerance)) return e;
  if (auto e = check_grid(o.grid)) return e;
  if (o.method != NearSurfaceOptions::Method::kProject &&
      o.method != NearSurfaceOptions::Method::kReject) {
    return OptionError{"method", "must be project or reject"};
  }
  if (auto e = check_project_width(o)) return e;
  if (!o.box.isEmpty() && (!o.box.min().allFinite() || !o.box.max().allFinite())) {
    return OptionError{"box", "must be finite"};
  }
  return std::nullopt;
}

void throw_if(const Check& c, const std::string& fn) {
  if (c) throw InvalidArgument(fn + ": option " + c->option + " " + c->problem);
}

}  // namespace ramiform::sample_detail
