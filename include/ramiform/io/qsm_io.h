// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Importing cylinder models (quantitative structure models, QSMs) of trees as skeletons:
/// TreeQSM cylinder text and SimpleForest CSV. The formats are described in docs/formats.md.
///
/// A cylinder model lists cylinders (start point, end point, radius, parent cylinder). The
/// importer turns it into one connected skeleton that passes `validate()`:
///
/// - Every cylinder becomes a polyline along its axis from its start node to its end node.
/// - **Joining.** A child whose start lies within 0.5 · min(r_parent, r_child) (tol::kQsmJoin)
///   of the closest point of its parent's axis segment (clamped to the segment) starts at the
///   parent's node there, so consecutive cylinders of a branch share nodes. Otherwise (a side
///   branch starting on the parent's surface, or a gap) the child keeps its own start node and
///   a *connector* edge joins it to the parent's axis node. The connector keeps the child's
///   cylinder (its direction, length and radius) as it is and puts the change from the parent's
///   radius to the child's inside the parent; moving the child's start onto the axis instead
///   would tilt short children and widen their whole first segment to the parent's radius.
/// - **Splitting.** A child attached more than 0.25 · r_parent (tol::kQsmMerge, along the
///   axis) from both ends of its parent's axis splits the parent there, so the graph gets a
///   branch node. Attachment points closer than 0.25 · r_parent to each other share one split
///   node (at their mean).
/// - **Tiny cylinders.** A cylinder whose end lies within 0.25 · r of its start node is merged
///   into that node (no edge); its children attach there. Measuring from the node, not from the
///   cylinder's own start, keeps runs of tiny cylinders from collapsing more than that.
/// - **Duplicates and overlaps.** Where a cylinder's next axis node would lie within 0.25 · r of
///   a node already joined to its current node, that node is reused and no second edge is made
///   (duplicate cylinders, and overlapping ones that repeat an existing edge). Edges are never
///   duplicated.
/// - **Parents.** A parent index that does not name another cylinder of the file (out of range,
///   the cylinder itself, part of a parent cycle) and every root marker after the first make a
///   cylinder an *orphan*: it is attached to the nearest axis segment of a cylinder outside its
///   own subtree (then joined as above) and counted in `reattached`. The result is one connected
///   tree. Without any root marker, the first cylinder's topmost ancestor is the root.
/// - **Radii.** A node's radius is the mean of the largest radius of the cylinders ending there
///   and the largest radius of those starting there (only one of them at the root and the
///   tips; the cylinder's radius at split nodes). A radius step between consecutive cylinders
///   thus becomes a taper over the two edges around the node, centred on it; the cylinder radii
///   themselves are kept as they are (radius jumps are data).

#include <cstddef>
#include <string>
#include <string_view>

#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// What the import did, filled by the readers when a pointer is given.
struct QsmImportReport {
  std::size_t cylinders = 0;      ///< cylinders read (data lines)
  std::size_t merged_tiny = 0;    ///< tiny cylinders merged into their start node
  std::size_t split_parents = 0;  ///< split nodes inserted into a parent's axis
  std::size_t connectors = 0;     ///< connector edges from a parent's axis to a child's start
  std::size_t reattached = 0;     ///< orphans attached to the nearest cylinder axis
  std::size_t duplicates = 0;     ///< cylinders whose end reused a node already joined to
                                  ///< their chain (repeated cylinders), adding no new end node
};

/// Reads a TreeQSM cylinder text file: whitespace-separated columns, one cylinder per line,
/// metres. The first 9 columns are used: radius, length, start x y z, axis direction x y z,
/// parent (1-based line number among the cylinders, 0 = root); further columns are ignored.
/// One header line (its first field not a number) is skipped; blank lines and `#` comments
/// are ignored. The axis is normalized.
///
/// Throws `InputError` naming the file and line for an unreadable or empty file, fewer than 9
/// columns, malformed or non-finite numbers, a radius <= 0, a negative length, a zero axis, or
/// a parent that is not a whole number.
[[nodiscard]] Skeleton read_treeqsm(const std::string& path, QsmImportReport* report = nullptr);

/// Parses TreeQSM text (see `read_treeqsm`); `source_name` names the file in error messages.
[[nodiscard]] Skeleton parse_treeqsm(std::string_view text, const std::string& source_name,
                                     QsmImportReport* report = nullptr);

/// Reads a SimpleForest cylinder CSV: a header line naming the columns (matched without regard
/// to case or surrounding blanks, in any order), then one cylinder per line. Used columns: `ID`,
/// `parentID` (negative = root), `startX`, `startY`, `startZ`, `endX`, `endY`, `endZ`, `radius`;
/// others are ignored. Ids are whole numbers, unique, in any order.
///
/// Throws `InputError` naming the file and line for an unreadable or empty file, a missing
/// column, a line whose field count differs from the header's, an empty field, malformed or
/// non-finite numbers, a radius <= 0, an id or parent id that is not a whole number, or a
/// repeated id.
[[nodiscard]] Skeleton read_simpleforest(const std::string& path,
                                         QsmImportReport* report = nullptr);

/// Parses SimpleForest CSV text (see `read_simpleforest`).
[[nodiscard]] Skeleton parse_simpleforest(std::string_view text, const std::string& source_name,
                                          QsmImportReport* report = nullptr);

/// True when the first non-blank line of `text` is a SimpleForest header (it names the columns
/// `parentID` and `startX`). Used to tell SimpleForest text from TreeQSM text.
[[nodiscard]] bool looks_like_simpleforest(std::string_view text);

}  // namespace ramiform
