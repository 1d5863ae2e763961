// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Pen-and-ink lines of an implicit surface, found from the particles spread over it:
/// silhouettes, suggestive contours and feature lines, each point classified visible or hidden.
///
/// From Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set Implicits"
/// (GRAPP), §5 (suggestive contours: eqs. 3–8, clustering, MST line fitting), §6 (silhouettes:
/// eqs. 9–10, the predictor–corrector tracing with steps scaled by δ_i, chaining; feature lines:
/// straddle points by eq. 11 and the neighbourhood search, tracing) and §3 (hidden lines by
/// surfels), which build on DeCarlo, Finkelstein, Rusinkiewicz & Santella 2003, "Suggestive
/// Contours for Conveying Shape" (SIGGRAPH), and Foster, Jepp, Wyvill, Costa Sousa, Galbraith &
/// Jorge 2005, "Drawing surfaces" (Computers & Graphics).
///
/// Lengths in the options are relative to each particle's repulsion radius δ_i (the paper's
/// stated weakness is parameters that depend on the model's scale), angles are in degrees.
/// Every function here is deterministic: the same inputs give byte-identical results on any
/// thread count. The implementations are in src/lines/ (one file per line kind).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/lines/camera.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform {

/// What a line depicts.
enum class LineKind : std::uint8_t {
  kSilhouette,  ///< contour generator: n·v = 0 (view-dependent)
  kSuggestive,  ///< suggestive contour: minima of n·v along w (view-dependent)
  kFeature,     ///< crease: a sharp change of the normal (view-independent)
};

/// "silhouette", "suggestive", "feature".
[[nodiscard]] std::string_view line_kind_name(LineKind kind);

/// One line on the surface.
struct Polyline {
  LineKind kind = LineKind::kSilhouette;
  std::vector<Vec3> points;  ///< on f == iso, model units, in drawing order
  /// Per point: 1 visible, 0 hidden; empty until classify_visibility() ran.
  std::vector<std::uint8_t> visible;
  bool closed = false;  ///< the last point joins the first
};

/// How suggestive-contour clusters become lines (§5.3).
enum class SuggestiveFit : std::uint8_t {
  kLongestPath,  ///< the longest path of each cluster's MST (one line per cluster)
  kTrim,         ///< the MST with leaf branches of fewer than k_trim particles removed
};

/// How hidden lines are found.
enum class Visibility : std::uint8_t {
  kNone,     ///< every point visible
  kRays,     ///< exact: the segment from the eye to the point searched for an inside point
             ///< (interval bounds, then samples δ/2 apart where they cannot decide)
  kSurfels,  ///< the paper's §3: a depth buffer of disks behind the particles (read at each
             ///< line point's own image position, not at a pixel centre)
};

/// Where feature_lines() finds its straddle pairs (§6, eq. 11).
enum class StraddleSource : std::uint8_t {
  kAuto,      ///< kMovement, then kSearch when it gives no line or the system has no seeding state
  kMovement,  ///< Foster et al.'s test: a particle's normal before and after the simulation
  kSearch,    ///< the paper's improvement 3: particles within straddle_radius of each other
};

/// Options of the line extraction. Lengths are multiples of each particle's δ_i.
struct LineOptions {
  // Silhouettes (§6).
  double k_c = 0.05;             ///< seed particles: |v·n| < k_c (eq. 9), in (0, 1)
  double k_e = 2.0;              ///< tracing continues while |v·n| < k_c·k_e (eq. 10), ≥ 1
  double silhouette_step = 0.5;  ///< predictor step, × δ_i, > 0
  /// Polylines whose ends come within this distance (× δ_i) with similar directions in the
  /// image are chained into one (§6's 2-D analysis), ≥ 0. Feature lines whose ends come this
  /// near in 3-D, running on in the same direction, are joined the same way.
  double chain_distance = 3.0;

  // Suggestive contours (§5).
  double k_d = 0.5;             ///< x± = x ± k_d·δ_i·w (eqs. 4–5), > 0
  double theta_sc_deg = 10.0;   ///< stability: the angle between n and −v exceeds θ_sc (eq. 8)
  double cluster_radius = 2.0;  ///< neighbour search radius, × δ_i (§5.2), > 0
  int cluster_k = 3;            ///< neighbours per particle in the cluster graph (§5.2), ≥ 1
  SuggestiveFit fit = SuggestiveFit::kLongestPath;  ///< §5.3
  int k_trim = 3;       ///< kTrim: leaf branches with fewer particles are removed, ≥ 1
  int smoothing = 2;    ///< Laplacian smoothing passes of each line, re-projected, ≥ 0
  int min_cluster = 3;  ///< clusters with fewer particles give no line, ≥ 2
  /// DeCarlo et al. 2003's threshold on the derivative of the radial curvature, made
  /// scale-free: a particle is kept only where δ_i²·D_ŵ κ_r > t_d (ŵ the unit w), estimated from
  /// the same probes x± as eqs. 6–7 (see suggestive_contours()). ≥ 0; 0 keeps every minimum.
  double t_d = 0.0;
  /// Suggestive lines shorter than this (× the mean δ_i of their particles) are dropped, ≥ 0.
  double min_line_length = 0.0;

  // Feature lines (§6).
  double k_a_deg = 8.6;          ///< straddle points: angle(n_i, n_j) > k_a (eq. 11; 0.15 rad)
  double straddle_radius = 1.5;  ///< neighbourhood search radius for straddle pairs, × δ_i
  /// Which test gives the straddle pairs. kAuto is the paper's order: Foster et al.'s
  /// before/after-movement test first, the neighbourhood search "when the Foster et al. method
  /// fails" (no line from it) or the particles carry no seeding state.
  StraddleSource straddle = StraddleSource::kAuto;

  // Hidden lines.
  /// kRays by default, for correctness. Surfels are faster on MPU fields (on 2,495 line points
  /// over 10,000 particles of an MPU bunny 11–18 ms against 39–74 ms for kRays, whose 12,083
  /// bound(box) calls cost 3–6 µs each; 2 cores shared with other work) but wrong where it
  /// shows: 17 of the 1,870 points away from contours (0.9 %) showed through gaps between the
  /// disks, and on a scanned cow seen from the side a third of the back's silhouette came out
  /// dashed, its points hidden by the disks of the particles just in front of the rim. kRays is
  /// exact (tests/lines/visibility_test.cpp) and about as fast on analytic fields.
  Visibility visibility = Visibility::kRays;
  /// A point is hidden when the surface lies in front of it by more than this (× δ_i).
  double occlusion_tolerance = 0.25;
  /// kSurfels: pixels along the frame's height of the grid the disks are binned on. The depth
  /// buffer is read at each line point's exact image position, so this sets only the speed.
  int surfel_resolution = 1024;

  // Which lines draw_lines() extracts.
  bool silhouettes = true;
  bool suggestive = true;
  bool features = true;
};

/// Throws InvalidArgument naming the first option out of its documented range.
void validate(const LineOptions& options);

/// Sets options.silhouettes, .suggestive and .features to exactly the kinds named
/// ("silhouette", "suggestive", "feature"; the names of line_kind_name). Throws InvalidArgument
/// naming an unknown kind.
void select_line_kinds(LineOptions& options, const std::vector<std::string>& kinds);

/// "rays", "surfels" or "none"; throws InvalidArgument for another name.
[[nodiscard]] Visibility visibility_from_name(std::string_view name);

/// "auto", "movement" or "search" (StraddleSource); throws InvalidArgument for another name.
[[nodiscard]] StraddleSource straddle_from_name(std::string_view name);

/// "longest" (kLongestPath) or "trim" (kTrim); throws InvalidArgument for another name.
[[nodiscard]] SuggestiveFit fit_from_name(std::string_view name);

/// What an extraction did (each call adds to the fields it concerns).
struct LineStats {
  std::size_t particles = 0;             ///< particles of the system
  std::size_t silhouette_seeds = 0;      ///< particles with |v·n| < k_c
  std::size_t suggestive_particles = 0;  ///< particles passing eqs. 6–8
  std::size_t suggestive_clusters = 0;   ///< clusters (after merging)
  std::size_t straddle_pairs = 0;        ///< straddle point pairs found (both tests)
  /// Of them: particles whose normal turned by more than k_a between seeding and the end of
  /// the simulation (the movement test), and particle pairs of the neighbourhood search.
  std::size_t straddle_pairs_movement = 0, straddle_pairs_search = 0;
  std::size_t lines[3] = {0, 0, 0};  ///< polylines per LineKind
  double length[3] = {0, 0, 0};      ///< total 3-D length per LineKind, model units
  double hidden_fraction = 0;        ///< hidden length / total length (after visibility)
  double seconds_features = 0, seconds_silhouettes = 0, seconds_suggestive = 0,
         seconds_visibility = 0;  ///< wall-clock seconds
  std::uint64_t field_evals = 0;  ///< point evaluations of the field
};

/// Feature lines (§6): straddle pairs whose normals differ by more than k_a (eq. 11) — by
/// options.straddle, a particle's seeding and final states (Foster et al.'s test; needs
/// has_seed_state(particles)) and/or particle pairs within straddle_radius·δ — traced along the
/// crease (direction n_i × n_j, the two sides re-projected each step of ~δ_i) until the normals
/// no longer differ by k_a or another feature line is near. Then lines whose ends meet within
/// chain_distance·δ, running on in the same direction (within 30°, the gap along it), are joined,
/// and a line whose own ends so meet is closed; lines never turn a corner (three creases meet
/// there, none continues another). View-independent: compute once, reuse for every view.
/// Throws InvalidArgument for bad options, and for StraddleSource::kMovement on particles
/// without a seeding state.
[[nodiscard]] std::vector<Polyline> feature_lines(const Field& field,
                                                  const ParticleSystem& particles,
                                                  const LineOptions& options = {},
                                                  LineStats* stats = nullptr,
                                                  const Context* ctx = nullptr);

/// What every view of one particle system looks up the same way, made once: the particles'
/// k-d tree (δ at a point is its nearest particle's, for the silhouette tracer and hidden lines)
/// and, on first use, each particle's surfel radius (Visibility::kSurfels). Without one, every
/// call builds these for itself; a caller drawing many views of the same particles (the
/// studio's line mode) builds it once and passes it. The drawings are the same either way.
/// Keeps a reference to `particles`, which must outlive it and stay unchanged; passing it with
/// another particle system throws InvalidArgument. Thread-safe once made.
class ParticleLookup {
 public:
  /// `particles` must not be empty (throws InvalidArgument).
  explicit ParticleLookup(const ParticleSystem& particles);
  ~ParticleLookup();
  ParticleLookup(const ParticleLookup&) = delete;
  ParticleLookup& operator=(const ParticleLookup&) = delete;

  struct Impl;  ///< src/lines/line_common.h
  [[nodiscard]] const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// Silhouettes (§6): seeds with |v·n| < k_c, each traced both ways by a predictor (along the
/// contour generator's 3-D tangent ∇f × ∇(n·v), whose projection is the image tangent except at
/// cusps; step silhouette_step·δ) and corrector (back onto f == iso and
/// n·v == 0) until the line closes a loop, reaches another silhouette, or |v·n| ≥ k_c·k_e;
/// then a second pass seeds from particles with k_c ≤ |v·n| < k_c·k_e farther than 1.5 δ from
/// every line, corrected onto the contour (the gaps where traces stopped on a bumpy rim);
/// nearby ends chained. Points satisfy |f − iso| / |∇f| ≤ 1e-3 δ and |n·v| ≤ 1e-3.
/// `lookup`: made for `particles` (ParticleLookup), or nullptr.
[[nodiscard]] std::vector<Polyline> silhouettes(const Field& field, const ParticleSystem& particles,
                                                const Camera& camera,
                                                const LineOptions& options = {},
                                                LineStats* stats = nullptr,
                                                const Context* ctx = nullptr,
                                                const ParticleLookup* lookup = nullptr);

/// Suggestive contours (§5): particles where n·(eye − x) (n the particle's outward normal) is
/// smaller than at x± = x ± k_d·δ_i·ŵ, ŵ the unit projection of the view vector on the tangent
/// plane (eqs. 4–7: a local minimum along w, DeCarlo et al.'s n·v with their v = eye − x; the
/// paper's n·v with eq. 3's v has this sign with an inward normal ∇f/|∇f|; the vector is not
/// normalized, so that the minima are exactly the zeros of the radial curvature that grows
/// along w; both inequalities are tightened by the bend of w's integral curves, estimated from
/// the normals at x±, see src/lines/suggestive.cpp), on the front-facing side
/// (n·(eye − x) > 0), away from where the surface faces the viewer (eq. 8: angle(n, −v) >
/// θ_sc). Clustered (§5.2: links to the cluster_k nearest suggestive particles within
/// cluster_radius·δ_i, clusters that meet merged), fitted by each cluster's minimum spanning
/// tree's longest path or trimmed tree (§5.3; clusters of fewer than min_cluster particles give
/// no line), smoothed with fixed ends and re-projected (interior points satisfy
/// |f − iso| / |∇f| ≤ 1e-7 δ; the ends are particles). Lines are open, `visible` left empty, in
/// the order of their clusters' first particles. stats->suggestive_clusters counts every
/// cluster, single particles included.
[[nodiscard]] std::vector<Polyline> suggestive_contours(
    const Field& field, const ParticleSystem& particles, const Camera& camera,
    const LineOptions& options = {}, LineStats* stats = nullptr, const Context* ctx = nullptr);

/// Sets every line's `visible` flags for `camera` by options.visibility (kRays: the segment
/// from the eye to the point, shortened by occlusion_tolerance·δ at the point's end, is tested
/// for a point inside (f > iso) by interval bounds over pieces of it and samples at most δ/2
/// apart where the bounds cannot decide; kSurfels: a depth buffer of particle disks, each of
/// radius the distance to the third nearest other particle, one radius behind its particle,
/// read at each line point's image position; points outside the frame or behind the eye stay
/// visible). δ at a line point is the nearest particle's. Sets stats->hidden_fraction (hidden
/// length / total length, each segment's length split half to each end) and adds to
/// seconds_visibility and field_evals. Throws InvalidArgument for bad options or camera, a line
/// point that is not finite, and lines with points but no particles (unless kNone).
/// `lookup`: made for `particles` (ParticleLookup), or nullptr.
void classify_visibility(const Field& field, const ParticleSystem& particles, const Camera& camera,
                         std::span<Polyline> lines, const LineOptions& options = {},
                         LineStats* stats = nullptr, const Context* ctx = nullptr,
                         const ParticleLookup* lookup = nullptr);

/// A drawing: the lines of one view.
struct LineDrawing {
  Camera camera;
  std::vector<Polyline> lines;  ///< silhouettes, then suggestive contours, then feature lines
};

/// One view: the line kinds the options ask for, then classify_visibility(). `features`:
/// feature lines computed earlier by feature_lines() for this field and particle system (they
/// are view-independent and copied into the drawing); nullptr computes them when
/// options.features is set. `lookup`: made for `particles` (ParticleLookup) and reused across
/// views, or nullptr.
[[nodiscard]] LineDrawing draw_lines(const Field& field, const ParticleSystem& particles,
                                     const Camera& camera, const LineOptions& options = {},
                                     const std::vector<Polyline>* features = nullptr,
                                     LineStats* stats = nullptr, const Context* ctx = nullptr,
                                     const ParticleLookup* lookup = nullptr);

}  // namespace ramiform
