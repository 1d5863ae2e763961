// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Reading and writing skeletons as JSON, PLY and OBJ. The formats are described in
/// docs/formats.md. Every reader finishes with `validate()` (skeleton/skeleton.h), so a returned
/// skeleton satisfies all skeleton invariants.

#include <string>
#include <string_view>

#include "ramiform/io/swc_io.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

struct QsmImportReport;  // io/qsm_io.h

/// Options of `read_skeleton`.
struct SkeletonReadOptions {
  double obj_radius = 0.0;  ///< radius (model units) given to every node of an OBJ skeleton
                            ///< (OBJ has none); must be finite and > 0 when reading OBJ
  QsmImportReport* qsm_report = nullptr;  ///< when not null and the file is a cylinder model
                                          ///< (`.csv`, `.txt`), receives the import report
  SwcReadOptions swc;  ///< options of an SWC file (`.swc`, io/swc_io.h)
  /// Keep the curved edges of a JSON skeleton (Skeleton::curves) instead of straightening them
  /// into chains of straight edges (straighten_curves, 1 % of the radius), which the fields and
  /// polygonizers need.
  bool keep_curves = false;
};

/// Reads a skeleton, choosing the format by the file extension (case-insensitive): `.json`,
/// `.ply` (ASCII or binary), `.obj`, `.swc` (io/swc_io.h: somata become soma regions), or a
/// cylinder model (io/qsm_io.h): `.csv` is SimpleForest
/// CSV; `.txt` is SimpleForest when its first line names the SimpleForest columns, otherwise
/// TreeQSM text.
///
/// Throws `InputError` naming the file and the line (text formats) or the element index (binary
/// PLY, JSON structure, skeleton invariants) for an unknown extension, an unreadable or empty
/// file, malformed or non-finite numbers, a missing node list or property, or an invalid
/// skeleton. Throws `InvalidArgument` when reading OBJ with `options.obj_radius` not > 0.
[[nodiscard]] Skeleton read_skeleton(const std::string& path,
                                     const SkeletonReadOptions& options = {});

/// Parses skeleton JSON text: {"nodes":[{"position":[x,y,z],"radius":r},...],
/// "edges":[[i,j],...]} (edges optional, 0-based). An edge may instead be an object
/// {"nodes":[i,j],"controls":[[x,y,z],...],"radii":[...]}: a Bezier curve through the inner
/// control points (Skeleton::curves; kept as they are here). A node may carry an integer "type" (e.g. its
/// SWC type); then every node must, and the skeleton's `node_types` hold them. `source_name` is the file name used in error
/// messages. Throws `InputError` like `read_skeleton`.
[[nodiscard]] Skeleton parse_skeleton_json(std::string_view text, const std::string& source_name);

/// Parses the bytes of a PLY skeleton: element `vertex` with scalar properties x, y, z, radius,
/// optional element `edge` with vertex1, vertex2 (0-based). Throws `InputError`.
[[nodiscard]] Skeleton parse_skeleton_ply(std::string_view bytes, const std::string& source_name);

/// Parses an OBJ skeleton: `v x y z` vertices and `l i j [k ...]` polylines (1-based, negative
/// indices count back from the last vertex read); a polyline of k vertices gives k-1 edges.
/// Every node gets the radius `options.obj_radius`. Throws `InputError`, or `InvalidArgument`
/// when `options.obj_radius` is not finite and > 0.
[[nodiscard]] Skeleton parse_skeleton_obj(std::string_view text, const std::string& source_name,
                                          const SkeletonReadOptions& options);

/// The skeleton as JSON text in the format `parse_skeleton_json` reads, one node or edge per
/// line, with each node's "type" when the skeleton has `node_types`; numbers are written with the shortest text that reads back to the identical double.
/// Throws `InvalidArgument` when the skeleton fails `validate()`.
[[nodiscard]] std::string skeleton_to_json(const Skeleton& skeleton);

/// Writes `skeleton_to_json(skeleton)` to `path` atomically (see io/atomic_file.h).
/// Throws `InvalidArgument` for an invalid skeleton and `Failure` when the file cannot be written.
void write_skeleton_json(const Skeleton& skeleton, const std::string& path);

/// Writes a skeleton choosing the format by the extension (case-insensitive): `.json`; `.ply`
/// (binary little-endian: vertex x, y, z, radius as double, edge vertex1, vertex2 as uint);
/// `.obj` (`v` and one `l` line per edge; radii are not stored). Curved edges are kept in JSON
/// and straightened (straighten_curves) for PLY and OBJ. Atomic. Throws `InvalidArgument`
/// for another extension or an invalid skeleton, `Failure` when the file cannot be written.
void write_skeleton(const Skeleton& skeleton, const std::string& path);

}  // namespace ramiform
