// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Reading SWC neuron and vessel skeletons (`index type x y z radius parent` per line, `#`
/// comments; the INCF / NeuroMorpho.Org conventions), with the soma turned into a closed soma
/// region that a convolution surface blends with the neurites. docs/formats.md ("SWC") says
/// exactly what is done with each soma convention.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// How a soma (a connected group of type-1 samples) was recognised.
enum class SwcSomaKind {
  kSinglePoint,  ///< one type-1 sample: a sphere of its radius
  kThreePoint,   ///< NeuroMorpho three-point soma (centre, centre -+ r along y): a sphere of r
  kContour,      ///< an outline of type-1 samples: a sphere at the centroid, mean distance radius
  kCylinders,    ///< a chain or tree of overlapping type-1 samples: kept as skeleton segments
};

/// One soma of an SWC file as read.
struct SwcSoma {
  SwcSomaKind kind = SwcSomaKind::kSinglePoint;
  /// The skeleton node of the sphere (point kinds), or of the first sample (kCylinders).
  std::uint32_t node = 0;
  Vec3 center = Vec3::Zero();  ///< sphere centre (kCylinders: the first sample's position)
  double radius = 0;           ///< sphere radius (kCylinders: the largest sample radius)
  std::size_t samples = 0;     ///< type-1 samples it was made from
  std::size_t line = 0;        ///< 1-based line of its first sample
};

/// What the SWC reader found and did.
struct SwcReport {
  std::size_t samples = 0;  ///< sample lines read
  std::size_t roots = 0;    ///< samples with parent -1: one tree, one surface component each
  std::vector<SwcSoma> somata;
  /// Per sample, in file order: the skeleton node that stands for it (its own; the soma
  /// sphere it was merged into; the node of the coincident parent it was merged into).
  std::vector<std::uint32_t> sample_node;
  std::size_t attachments = 0;  ///< nodes added on soma surfaces where neurites leave them
  std::size_t merged = 0;       ///< samples merged into a coincident parent
};

/// Options of `parse_swc`.
struct SwcReadOptions {
  /// true: somata become soma regions and neurites start on their surface (docs/formats.md);
  /// false: every sample is a node and every parent link an edge, as in the file.
  bool soma_regions = true;
  SwcReport* report = nullptr;  ///< when not null, receives what the reader found and did
};

/// Parses SWC text. Samples may come in any order (a parent after its children); parent -1
/// marks a root and several roots give several trees; fields are separated by spaces or tabs;
/// `#` starts a comment; CRLF line ends and a UTF-8 byte order mark are accepted. The
/// skeleton's `node_types` hold each node's SWC type (1 for a soma sphere). A sample whose
/// position equals its parent's is merged into it.
///
/// Throws `InputError` naming `source_name` and the line for: an empty file or one without
/// samples, a line without exactly 7 fields, a non-numeric or non-finite value, an index or
/// type that is not an integer, a negative index, a parent below -1, a radius <= 0, a sample
/// that is its own parent, a duplicate index (naming the first line too), a parent index no
/// sample has, and a cycle of parent links (naming its first line); then the skeleton
/// invariants (skeleton.h).
[[nodiscard]] Skeleton parse_swc(std::string_view text, const std::string& source_name,
                                 const SwcReadOptions& options = {});

/// Reads an SWC file (`parse_swc` of its bytes). Throws `InputError` as `parse_swc`, or when
/// the file cannot be read.
[[nodiscard]] Skeleton read_swc(const std::string& path, const SwcReadOptions& options = {});

}  // namespace ramiform
