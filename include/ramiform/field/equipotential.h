// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Equipotential surfaces of charged line skeletons (Gruber & Wallner 2014, "Polygonization of
/// Line Skeletons by Using Equipotential Surfaces – A Practical Description", J. Geometry and
/// Graphics 18(1), §3.2 charges, eq. 1 field, §3.4 eq. 2 lambda).
///
/// Point charges sit at every skeleton node and evenly along every edge (spacing at most d_c);
/// each edge has one charge value q_e, a node's charge is the mean of its edges' values, and an
/// open (sharp-edged) leaf end gets extra charges on the extension of its edge. The field is the
/// potential
///
///     f(r) = sum_i q_i / |r - c_i|^(alpha - 1),   alpha >= 2,
///
/// and the surface is f == lambda (inside f > lambda, as every ramiform field). The potential
/// has infinite support, so instead of cutting it off the field sums it with a treecode (Barnes
/// & Hut 1986): charges are held in a binary tree of clusters (median splits, leaves of at most
/// 8); a cluster whose radius rho seen from distance D to its charge-weighted centroid satisfies
/// rho < theta D counts as its monopole plus its quadrupole about that centroid (the dipole
/// vanishes there); nearer clusters are opened down to single charges, which are summed exactly.
/// Measured against a brute-force sum in long double on a 40-node tree, theta = 0.25: the value
/// is within 0.03 % (alpha 2) to 0.7 % (alpha 5) of max(f, lambda), the gradient within 1 % where
/// f >= lambda / 4 (tests/field/equipotential_test.cpp); theta = 0 is the exact sum. To keep
/// the value finite on the charges themselves, distances are softened, |r - c|^2 + h^2 with
/// h = 1e-9 times the charges' extent. bound(box) is conservative: each cluster contributes
/// between Q / d_max^(alpha-1) and Q / d_min^(alpha-1) over the box (single charges of a near
/// leaf each on their own). bounds() refines an octree over the region the total charge can
/// reach, keeping the cells whose bound reaches above lambda.
///
/// Beyond the paper (the radii mode, the default when no `charge` is given): each edge's charges
/// follow its taper, a closed leaf's charge is raised so that the tip keeps its radius, and
/// fit_charges() fits the per-edge values to the skeleton's radii by non-negative least squares.
/// docs/equipotential.md has the measured radius errors.

#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Charges evenly along an edge of length `length` at spacing at most `spacing` (> 0), not
/// counting the two end nodes' charges: max(0, ceil(length / spacing) - 1), placed at
/// t = k / (count + 1), k = 1..count. The particle mesher puts its rings at the same places.
/// Throws InvalidArgument for a non-finite or non-positive spacing, a negative length or more
/// than 2^26 charges on one edge.
[[nodiscard]] std::size_t edge_charge_count(double length, double spacing);

/// Options of the charges and the field. Validated at entry (InvalidArgument naming the option).
struct EquipotentialOptions {
  double alpha = 4.0;  ///< field exponent alpha (>= 2; 2 is Coulomb's law): potential q/r^(alpha-1)
  /// Charge spacing d_c (model units, > 0), or 0: per edge, `spacing_factor` times the smaller
  /// radius of its two nodes.
  double charge_spacing = 0.0;
  double spacing_factor = 0.5;  ///< d_c per edge when charge_spacing is 0 (> 0)
  /// One charge value for every edge (the paper's figures; > 0), or 0: per edge from the
  /// skeleton's radii (q_e = d_e r_e^(alpha-2), which makes the potential of a long straight
  /// edge at its own radius the same for every edge), or `edge_charges`.
  double charge = 0.0;
  std::vector<double> edge_charges;  ///< empty, or one value (> 0) per edge; overrides `charge`
  /// With charges from the radii (charge 0, no edge_charges): each charge of an edge is q_e
  /// times (r(t) / r_e)^(alpha - 2), r(t) the radius interpolated at the charge and r_e the
  /// edge's mean radius, so that a tapered edge stays tapered (one value per edge could not
  /// follow a taper; the paper's figures use untapered edges). Off, or in the paper's mode,
  /// every charge of an edge has the edge's value.
  bool taper = true;
  /// The iso value lambda (> 0), or 0: estimated by eq. 2 (the mean potential of four test
  /// points on a circle around each edge's midpoint, radius r_e, or `charge` when given).
  double lambda = 0.0;
  double lambda_scale = 1.0;  ///< multiplies lambda (Figure 4: 1, 0.5, 0.2); > 0
  bool open_ends = false;     ///< every leaf end open (sharp-edged), not only the flagged ones
  /// Open ends: the extension carries charges over this many radii beyond the leaf (> 0).
  double extension = 4.0;
  double theta = 0.25;  ///< treecode opening criterion theta (0 = exact sum, at most 0.6)
};

/// The charges of a skeleton: positions, values and where each comes from.
struct ChargeSet {
  std::vector<Vec3> positions;  ///< one per charge
  std::vector<double> values;   ///< charge value q_i >= 0, one per charge
  /// Per charge: its edge (edge charges, open-end extensions), or UINT32_MAX (node charges).
  std::vector<std::uint32_t> edge;
  /// Per charge: its node (node charges and open-end extensions), or UINT32_MAX.
  std::vector<std::uint32_t> node;
  /// Per charge of an edge: the taper factor its value is the edge's value times (1 in the
  /// paper's mode; see EquipotentialOptions::taper); 1 for node charges.
  std::vector<double> scale;
  std::vector<double> edge_values;   ///< q_e, one per edge
  std::vector<double> node_values;   ///< q at each node: mean of its edges' (tapered) values
  std::vector<double> edge_spacing;  ///< d_c per edge (model units)
  std::vector<std::uint8_t> open;    ///< per node, 1 where the leaf end is open
  /// The edges of each node, CSR: node n's edges are node_edges[node_edge_offset[n] ..
  /// node_edge_offset[n + 1]) (node_edge_offset has one entry per node plus one), and
  /// node_edge_scale the taper factor of that edge at the node.
  std::vector<std::uint32_t> node_edge_offset, node_edges;
  std::vector<double> node_edge_scale;
  /// Per node, the factor its charge is the mean of its edges' values times: 1, except at the
  /// closed leaves of the radii mode, where make_equipotential() raises the leaf's charge so
  /// that the potential at the leaf's own radius around it reaches lambda (a finite line's
  /// potential falls to about half at its end, so the tube would otherwise narrow toward every
  /// tip).
  std::vector<double> node_factor;
  double alpha = 4.0;
};

/// Places the charges of `skeleton` (validated: InputError). A node is an open end when it is
/// a leaf and `options.open_ends` is set or `skeleton.open_ends` flags it.
[[nodiscard]] ChargeSet place_charges(const Skeleton& skeleton,
                                      const EquipotentialOptions& options = {});

/// Sets every charge value from per-edge values (node charges: the mean of their edges; open-end
/// extension charges: their edge's value). `edge_values` has one value >= 0 per edge.
void set_edge_charges(ChargeSet& charges, std::span<const double> edge_values);

/// lambda by eq. 2: the mean potential of four test points per edge on a circle around the
/// edge's midpoint, radius `test_radius[e]` (one per edge, > 0), for the given charges. Not in
/// the paper: a test point inside another edge's tube (nearer its axis than 0.99 of its radius
/// there) is left out of the mean (all are kept if none would remain), as its potential near
/// that axis is not the surface's and one such point decided the mean.
[[nodiscard]] double estimate_lambda(const ChargeSet& charges, const Skeleton& skeleton,
                                     std::span<const double> test_radius, double theta = 0.25);

/// The potential field of `charges` with iso value `lambda` (> 0, finite). `theta` as in
/// EquipotentialOptions. Throws InvalidArgument for empty or invalid charges.
[[nodiscard]] FieldPtr make_equipotential_field(const ChargeSet& charges, double lambda,
                                                double theta = 0.25);

/// Everything `make_equipotential(skeleton, options)` builds.
struct Equipotential {
  ChargeSet charges;
  double lambda = 0.0;  ///< the iso value used (after lambda_scale)
  FieldPtr field;
};

/// Charges, lambda (given or estimated, times lambda_scale) and the field in one call. In the
/// radii mode (no `charge`, no `edge_charges`) with `taper`, every closed leaf's charge is raised
/// so that the mean potential of four points at the leaf's radius around it (perpendicular to
/// its edge) is the estimated lambda (ChargeSet::node_factor).
[[nodiscard]] Equipotential make_equipotential(const Skeleton& skeleton,
                                               const EquipotentialOptions& options = {});

/// Options of fit_charges().
struct ChargeFitOptions {
  int stations_per_edge = 3;  ///< sample stations along each edge (t = (k + 1/2) / n), >= 1
  int directions = 6;         ///< sample points around the edge at each station, >= 3
  int max_sweeps = 200;       ///< coordinate-descent sweeps at most (>= 1)
  /// Stop when the largest relative potential residual |f(s) / lambda - 1| changes by less than
  /// this between two outer rounds (> 0).
  double tolerance = 1e-4;
  /// Every fitted q_e stays at least this fraction of its starting value (in [0, 1)). Without a
  /// floor the least-squares fit zeroes the short edges of a fork whose own samples all lie in
  /// the blend (none is fitted there) but whose charges push the neighbours' samples outward,
  /// and the fork's nodes then fall outside the surface (23 of 3,582 nodes of archi_Tree_1).
  /// A floor of 0.2 keeps the edge alone a tube of about 0.45 of its radius (alpha 4).
  double floor = 0.2;
};

/// Result of fit_charges().
struct ChargeFitResult {
  std::vector<double> edge_values;  ///< fitted q_e (>= 0), one per edge
  int sweeps = 0;                   ///< coordinate-descent sweeps made
  int rounds = 0;                   ///< outer rounds (far field re-evaluated)
  double residual_rms = 0.0;        ///< RMS of f(s) / lambda - 1 over the samples at the end
  double residual_max = 0.0;        ///< largest |f(s) / lambda - 1|
  std::size_t samples = 0;          ///< sample points (stations x directions x edges)
  std::size_t active = 0;           ///< edges whose value ended at the floor
};

/// Fits the per-edge charge values by bounded least squares so that the potential equals
/// `lambda` at points at each edge's requested radius (the radii of `skeleton`'s nodes,
/// interpolated along the edge): min sum_s w_s (f(s) - lambda)^2 over q >= floor x start, with
/// Huber weights w_s (1 within 2 % of lambda, falling as 1/|residual| beyond, recomputed every
/// round, so that the residuals no charge can remove, the webs in the crotches, do not pull
/// every value; stations within 1.5 radii of a fork are left out). The field is linear
/// in q, so lambda only scales the solution and stays fixed. Samples that lie inside another
/// edge's requested tube are left out (there the blend fills the crotch). Solved by cyclic
/// coordinate descent over the edges on the near-field part of the system (exact entries for
/// clusters the treecode would open), with the far field re-evaluated by the treecode between
/// rounds; each coordinate step is exact, so the objective never increases.
[[nodiscard]] ChargeFitResult fit_charges(const ChargeSet& charges, const Skeleton& skeleton,
                                          double lambda, const ChargeFitOptions& options = {},
                                          double theta = 0.25, Context* ctx = nullptr);

}  // namespace ramiform
