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
///
/// A BlobTree is a DAG: one field may be a child of several operators, or several times a child
/// of one. An operator evaluates, bounds and restricts each distinct child once per call and
/// reuses the result for every occurrence (in the order of the children, so the values are those
/// of the same tree without sharing, bit for bit). Fields shared by different operators are
/// still evaluated once per operator that uses them.

#include <cstddef>
#include <span>
#include <vector>

#include "ramiform/field/field.h"

namespace ramiform {

/// The deepest nesting a field may have: a field without child fields has depth 1, an operator
/// here or a warp (warps.h) 1 + the depth of its deepest child. evaluate(), bound(), bounds(),
/// restrict() and describe() recurse through the children (and so does the destruction of the
/// last reference), so a deeper tree would overflow the stack; every make_* here and in warps.h
/// throws InvalidArgument beyond this depth. Measured on x86-64 (Release build): the first of
/// those calls to overflow, over every operator kind, does so at a depth of about 14,600 on a
/// 4 MiB stack (oneTBB's worker threads, where polygonizers evaluate) and 29,000 on 8 MiB (a
/// main thread), about 290 bytes a level. Under AddressSanitizer a level takes about 4.2 KB
/// (measured: 3,952 bytes for an n-ary operator's evaluate frame, which overflowed 8 MiB at
/// about 2,000 levels); this limit keeps a factor of 2 on a 4 MiB worker there and of 29 in a
/// Release build. A long chain of unions is better written as one n-ary union.
inline constexpr std::size_t kMaxFieldDepth = 500;

/// Base of the fields built from other fields (the operators here, the warps of warps.h): it
/// records the nesting depth when the field is built and refuses depths beyond kMaxFieldDepth.
/// A field type of a caller that wraps other fields should derive from it so the limit sees it.
class CompositeField : public Field {
 public:
  /// 1 + the deepest child's depth (field_depth).
  [[nodiscard]] std::size_t depth() const { return depth_; }

 protected:
  /// `children` must be non-null; `what` names the operator in the InvalidArgument thrown when
  /// the depth would exceed kMaxFieldDepth.
  CompositeField(double iso, std::span<const FieldPtr> children, const char* what);
  /// For restrict(): a copy that counts into `source`'s counter and keeps its depth (restricted
  /// children are never deeper).
  CompositeField(double iso, const CompositeField& source);

 private:
  std::size_t depth_;
};

/// The nesting depth of `field`: CompositeField::depth(), or 1 for a field of another type.
[[nodiscard]] std::size_t field_depth(const Field& field);

/// Sum blend f = sum f_i (Wyvill's BlobTree "+"). Needs >= 1 child, all with the same iso
/// (InvalidArgument otherwise). Like every operator below, throws InvalidArgument for a null
/// child or when the result would be nested deeper than kMaxFieldDepth.
[[nodiscard]] FieldPtr make_sum(std::vector<FieldPtr> children);
/// Union f = max f_i (>= 1 child).
[[nodiscard]] FieldPtr make_union(std::vector<FieldPtr> children);
/// Intersection f = min f_i (>= 1 child).
[[nodiscard]] FieldPtr make_intersection(std::vector<FieldPtr> children);
/// Difference a minus b: f = min(f_a, 2 iso - f_b): inside a and not inside b.
[[nodiscard]] FieldPtr make_difference(FieldPtr a, FieldPtr b);
/// Affine transform: the shape of `child` moved by `transform` (any invertible affine map,
/// non-uniform scale included): f(p) = f_child(T^-1 p), grad = T^-T grad f_child.
/// Throws InvalidArgument for a singular or non-finite map. A transform of a transform is one
/// transform whose map is the composition (so a chain of moves is one level deep); its values
/// differ from those of the nested pair only by rounding.
[[nodiscard]] FieldPtr make_transform(FieldPtr child, const Affine3& transform);

}  // namespace ramiform
