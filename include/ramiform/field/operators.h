// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Operators that build a BlobTree from fields: sum blend, union, intersection, difference and
/// affine transforms. Every operator keeps a conservative bound() and bounds(), and restrict()
/// passes the box down so pruning keeps working deep in the tree.
///
/// CSG operators (union, intersection, difference) shift each child's values by
/// (parent iso - child iso) so children of different iso values combine correctly; the result
/// takes the first child's iso. The sum blend needs equal iso values.

#include <vector>

#include "ramiform/field/field.h"

namespace ramiform {

/// Sum blend f = sum f_i (Wyvill's BlobTree "+"). Needs >= 1 child, all with the same iso
/// (InvalidArgument otherwise).
[[nodiscard]] FieldPtr make_sum(std::vector<FieldPtr> children);
/// Union f = max f_i (>= 1 child).
[[nodiscard]] FieldPtr make_union(std::vector<FieldPtr> children);
/// Intersection f = min f_i (>= 1 child).
[[nodiscard]] FieldPtr make_intersection(std::vector<FieldPtr> children);
/// Difference a minus b: f = min(f_a, 2 iso - f_b): inside a and not inside b.
[[nodiscard]] FieldPtr make_difference(FieldPtr a, FieldPtr b);
/// Affine transform: the shape of `child` moved by `transform` (any invertible affine map,
/// non-uniform scale included): f(p) = f_child(T^-1 p), grad = T^-T grad f_child.
/// Throws InvalidArgument for a singular or non-finite map.
[[nodiscard]] FieldPtr make_transform(FieldPtr child, const Affine3& transform);

}  // namespace ramiform
