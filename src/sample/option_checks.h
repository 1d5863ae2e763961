// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: the option checks shared by the typed sampler functions (which
/// throw InvalidArgument) and generate_points (which maps them to the props line that set the
/// option).

#include <optional>
#include <string>

#include "ramiform/sample/point_sets.h"

namespace ramiform::sample_detail {

/// A failed check: the option's name (as in the options struct) and what is wrong with it.
struct OptionError {
  std::string option;
  std::string problem;
};
/// No value when the options are valid.
using Check = std::optional<OptionError>;

[[nodiscard]] Check check(const PoissonOptions& o);
[[nodiscard]] Check check(const LaneOptions& o);
/// `iso` is the field's: the density (iso / f)^exponent needs iso > 0.
[[nodiscard]] Check check(const FieldDensityOptions& o, double iso);
[[nodiscard]] Check check(const BoundaryOptions& o);
[[nodiscard]] Check check(const NearSurfaceOptions& o);

/// Throws InvalidArgument("FN: option OPTION PROBLEM") when the check failed.
void throw_if(const Check& c, const std::string& fn);

}  // namespace ramiform::sample_detail
