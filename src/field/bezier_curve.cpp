// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/bezier_curve.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/bernstein.h"
#include "core/extent_check.h"
#include "field/bezier_curve_simd.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

constexpr int kMaxDegree = 15;
constexpr int kMaxG = 2 * kMaxDegree - 1;  // degree of g
constexpr double kEps = std::numeric_limits<double>::epsilon();
// Root finding stops when the Newton step or the bracket is below this (t is in [0, 1]).
constexpr double kRootTolerance = detail::kBezierRootTolerance;
constexpr int kMaxRootIterations = detail::kBezierMaxRootIterations;
// Newton steps shrinking by at least this factor are taken as in the quadratic regime.
constexpr double kAsymptotic = 0.1;
// Distances equal within this relative amount are a tie (see TieRule).
constexpr double kTieRelative = 1e-12;
// Candidates closer than this in t are the same point, not a tie.
constexpr double kSameParameter = 1e-12;
constexpr int kNewtonSteps = 20;
// Rounding bound of the dot product E·(c - P) in the arc certificate (field/bezier_curve_simd.h).
constexpr double kSlopeRounding = detail::kBezierSlopeRounding;

struct Binomials {
  double c[kMaxG + 1][kMaxG + 1] = {};
};
constexpr Binomials make_binomials() {
  Binomials b;
  for (int n = 0; n <= kMaxG; ++n) {
    b.c[n][0] = 1;
    for (int k = 1; k <= n; ++k) b.c[n][k] = b.c[n - 1][k - 1] + (k <= n - 1 ? b.c[n - 1][k] : 0.0);
  }
  return b;
}
constexpr Binomials kBinomial = make_binomials();

// Rounding-error factor for a Bernstein coefficient or an evaluation of degree d: generous
// multiples of the textbook bounds (de Casteljau: 2d eps; a dot product: 3 eps).
constexpr double error_factor(int d) { return 8.0 * (d + 4) * kEps; }

// The Horner variable of the O(d) Bernstein evaluation: p(t) = base^d * sum_i c_i C(d,i) u^i with
// (u, base) = (t/(1-t), 1-t) for t <= 1/2, or sum over the reversed coefficients with
// ((1-t)/t, t) above. The sum has p's sign and de Casteljau's error bound (relative to the sum of
// |c_i| B_i(t)), which is why it is used rather than the power basis.
struct HornerPoint {
  double u;
  double base;
  bool reversed;
};
inline HornerPoint horner_point(double t) {
  if (t <= 0.5) return {t / (1 - t), 1 - t, false};
  return {(1 - t) / t, t, true};
}
// sum c_i C(d,i) u^i (the reduced value: p(t) / base^d).
inline double reduced(const double* c, int d, const HornerPoint& h) {
  const double* binom = kBinomial.c[d];
  double s;
  if (!h.reversed) {
    s = c[d] * binom[d];
    for (int i = d - 1; i >= 0; --i) s = s * h.u + c[i] * binom[i];
  } else {
    s = c[0];
    for (int i = 1; i <= d; ++i) s = s * h.u + c[i] * binom[i];
  }
  return s;
}
inline double power(double x, int d) {
  double r = 1;
  for (int i = 0; i < d; ++i) r *= x;
  return r;
}
// Bernstein evaluation of pre-scaled coefficients (scaled[i] = C(d,i) c_i).
template <class V>
V bernstein_scaled(const V* scaled, int d, double t) {
  const HornerPoint h = horner_point(t);
  V s = h.reversed ? scaled[0] : scaled[d];
  if (!h.reversed) {
    for (int i = d - 1; i >= 0; --i) s = s * h.u + scaled[i];
  } else {
    for (int i = 1; i <= d; ++i) s = s * h.u + scaled[i];
  }
  return power(h.base, d) * s;
}

// The root of the polynomial p (Bernstein coefficients, degree d, derivative d * dp) in
// (lo, hi), where p has sign `sign_lo` just right of lo and the opposite sign just left of hi and
// exactly one root in between: Newton from t0, safeguarded by bisection, the bracket kept
// (after Numerical Recipes' rtsafe). Newton's step p/p' = base * S_p / (d * S_dp) needs only the
// reduced values.
double bracketed_root(const double* p, const double* dp, int d, double lo, double hi, int sign_lo,
                      double t0) {
  double t = (t0 > lo && t0 < hi) ? t0 : 0.5 * (lo + hi);
  double dx_old = hi - lo;
  double dx = dx_old;
  double newton_step = 0;  // the last accepted Newton step (0 after a bisection)
  for (int it = 0; it < kMaxRootIterations; ++it) {
    const HornerPoint h = horner_point(t);
    const double s = reduced(p, d, h);
    if (s == 0) return t;
    if ((s > 0) == (sign_lo > 0)) {
      lo = t;
    } else {
      hi = t;
    }
    const double sd = reduced(dp, d - 1, h);
    const double step = h.base * s / (d * sd);
    const double next = t - step;
    // A step below the tolerance ends it (Newton converging from one side never shrinks the
    // bracket from the other, so the bracket test alone would fall back to ~50 bisections).
    if (std::abs(step) <= kRootTolerance) return (next >= lo && next <= hi) ? next : t;
    if (!(next > lo && next < hi) || std::abs(2 * step) > std::abs(dx_old)) {
      dx_old = dx;
      dx = 0.5 * (hi - lo);
      t = lo + dx;
    } else {
      // Quadratic convergence: the error after this step is about K step² with
      // K ~ |step| / previous_step²; stop once that estimate is below the tolerance.
      const double previous = newton_step;
      newton_step = std::abs(step);
      dx_old = dx;
      dx = step;
      t = next;
      if (previous > 0 && newton_step < kAsymptotic * previous &&
          newton_step * newton_step * newton_step <= kRootTolerance * previous * previous) {
        return t;
      }
      continue;
    }
    newton_step = 0;
    if (std::abs(dx) <= kRootTolerance || hi - lo <= kRootTolerance) return t;
  }
  return t;
}

constexpr int kMaxIsolationDepth = 6;
constexpr int kMaxCoeff = kMaxG + 1;

// An interval of [0, 1] on which g has exactly one root, a simple one (Descartes).
struct Piece {
  double lo;  // interval
  double hi;
  double guess;  // where the control polygon of g crosses 0 on it: Newton's start
  int sign_lo;   // sign of g just right of lo
};

// Sign variations of Bernstein coefficients c[0..d], each known to within `bound`: -1 when a
// sign is uncertain (|c| <= bound; an exact 0 with a zero bound is skipped by the rule inside and
// uncertain at an end, where it is a root). `at` receives the index after which the last
// variation occurs, `first_sign` the sign just right of the interval's start.
int sign_variations(const double* c, double bound, int d, int* first_sign, int* at) {
  int changes = 0, last_sign = 0;
  *first_sign = 0;
  for (int k = 0; k <= d; ++k) {
    if (c[k] == 0 && bound == 0 && k != 0 && k != d) continue;
    if (std::abs(c[k]) <= bound) return -1;
    const int s = c[k] > 0 ? 1 : -1;
    if (*first_sign == 0) {
      *first_sign = s;
    } else if (s != last_sign) {
      ++changes;
      *at = k;
    }
    last_sign = s;
  }
  return changes;
}

// Where the control polygon c[0..d] crosses 0 between the nonzero coefficients around index
// `at` (the start of a sign variation), as a fraction of the interval.
double polygon_crossing(const double* c, int d, int at) {
  int before = at - 1;
  while (before > 0 && c[before] == 0) --before;
  const double a = c[before], b = c[at];
  return (before + (at - before) * a / (a - b)) / d;
}

// Isolates the roots of g (Bernstein coefficients b of degree m, each within `bound`) in (0, 1)
// by Descartes' rule with bisection of the parameter interval to depth kMaxIsolationDepth.
// Returns the pieces with one root each, in ascending order, or -1 when a piece stays
// ambiguous. Subdivision takes convex combinations, so the bound grows only by their rounding.
int isolate(const double* b, double bound, int m, Piece* pieces) {
  struct Node {
    double lo, hi, bound;
    int depth;
    std::array<double, kMaxCoeff> c;
  };
  std::array<Node, kMaxIsolationDepth + 2> stack;
  std::array<double, kMaxCoeff> left;
  int top = 0;
  {
    Node& root = stack[top++];
    root.lo = 0;
    root.hi = 1;
    root.bound = bound;
    root.depth = 0;
    std::copy(b, b + m + 1, root.c.begin());
  }
  int count = 0;
  while (top > 0) {
    Node& node = stack[top - 1];
    double* c = node.c.data();
    int first_sign = 0, at = 0;
    const int changes = sign_variations(c, node.bound, m, &first_sign, &at);
    if (changes < 0) return -1;
    if (changes <= 1) {
      if (changes == 1) {
        const double x = polygon_crossing(c, m, at);
        pieces[count++] = {node.lo, node.hi, node.lo + x * (node.hi - node.lo), first_sign};
      }
      --top;
      continue;
    }
    if (node.depth == kMaxIsolationDepth) return -1;
    // de Casteljau at the midpoint, in place: the left half's coefficients are the first entry of
    // each row, and what remains in c is the right half (row r leaves entry m - r last).
    // Every intermediate value is a convex combination of c, so each of the m rows adds at most
    // eps * max|c| to the error.
    double largest = 0;
    for (int i = 0; i <= m; ++i) largest = std::max(largest, std::abs(c[i]));
    left[0] = c[0];
    for (int r = 1; r <= m; ++r) {
      for (int i = 0; i <= m - r; ++i) c[i] = 0.5 * (c[i] + c[i + 1]);
      left[r] = c[0];
    }
    const double mid = 0.5 * (node.lo + node.hi);
    node.bound += m * kEps * largest;
    ++node.depth;
    const double lo = node.lo;
    node.lo = mid;
    Node& next = stack[top++];  // the left half, processed first
    next.lo = lo;
    next.hi = mid;
    next.bound = node.bound;
    next.depth = node.depth;
    std::copy(left.begin(), left.begin() + m + 1, next.c.begin());
  }
  return count;
}

// The paper's root isolation (§3.4) of g (Bernstein coefficients b, bounds e, degree m) on
// [0, 1]: see the header. Roots into `roots`, sorted; maxima of the distance skipped (and
// counted in `skipped`) unless `locate_maxima`.
int derivative_chain(const double* b, const double* e, int m, bool locate_maxima, double* roots,
                     int* skipped) {
  std::array<std::array<double, kMaxCoeff>, kMaxCoeff> level;
  std::array<std::array<double, kMaxCoeff>, kMaxCoeff> error;
  std::copy(b, b + m + 1, level[0].begin());
  std::copy(e, e + m + 1, error[0].begin());
  // Level j holds the forward differences Δ^j b (g^(j) up to a positive factor), degree m - j.
  for (int j = 1; j <= m; ++j) {
    const double* prev = level[j - 1].data();
    const double* prev_error = error[j - 1].data();
    for (int i = 0; i <= m - j; ++i) {
      level[j][i] = prev[i + 1] - prev[i];
      error[j][i] = prev_error[i + 1] + prev_error[i] + kEps * std::abs(level[j][i]);
    }
  }
  // The sign of level j at t, 0 when within its rounding bound.
  auto signed_value = [&](int j, double t) {
    const int d = m - j;
    const HornerPoint h = horner_point(t);
    const double* c = level[j].data();
    const double* ce = error[j].data();
    const double* binom = kBinomial.c[d];
    const double factor = error_factor(d);
    double s, bound;
    if (!h.reversed) {
      s = c[d] * binom[d];
      bound = (ce[d] + factor * std::abs(c[d])) * binom[d];
      for (int i = d - 1; i >= 0; --i) {
        s = s * h.u + c[i] * binom[i];
        bound = bound * h.u + (ce[i] + factor * std::abs(c[i])) * binom[i];
      }
    } else {
      s = c[0];
      bound = ce[0] + factor * std::abs(c[0]);
      for (int i = 1; i <= d; ++i) {
        s = s * h.u + c[i] * binom[i];
        bound = bound * h.u + (ce[i] + factor * std::abs(c[i])) * binom[i];
      }
    }
    return std::abs(s) <= bound ? 0.0 : s;
  };

  // Interior roots of level j + 1 (the breakpoints of level j), from the linear level down.
  std::array<double, kMaxCoeff + 2> breaks;
  std::array<double, kMaxCoeff + 2> found;
  int break_count = 0;
  int found_count = 0;
  for (int j = m - 1; j >= 0; --j) {
    found_count = 0;
    auto push = [&](double t) {
      if (found_count == 0 || found[found_count - 1] < t) found[found_count++] = t;
    };
    double x_prev = 0;
    double v_prev = signed_value(j, 0.0);
    for (int k = 0; k <= break_count; ++k) {
      const double x = k < break_count ? breaks[k] : 1.0;
      const double v = signed_value(j, x);
      if (v_prev == 0) {
        push(x_prev);
      } else if (v != 0 && (v_prev < 0) != (v < 0)) {
        if (j == 0 && !locate_maxima && v_prev > 0) {
          ++*skipped;  // g goes from + to -: a maximum of the distance
        } else {
          push(bracketed_root(level[j].data(), level[j + 1].data(), m - j, x_prev, x,
                              v_prev > 0 ? 1 : -1, 0.5 * (x_prev + x)));
        }
      }
      x_prev = x;
      v_prev = v;
    }
    if (v_prev == 0) push(1.0);
    if (j == 0) break;
    break_count = 0;
    for (int k = 0; k < found_count; ++k) {
      if (found[k] > 0 && found[k] < 1) breaks[break_count++] = found[k];
    }
  }
  std::copy(found.begin(), found.begin() + found_count, roots);
  return found_count;
}

// g's Bernstein coefficients of degree m = 2n-1 (b_k = h_k - w_k·q) and their rounding bounds,
// from the controls q[0..n] of a curve (relative to the projector's origin).
// C'(t)·(C(t) - P) = n sum_i sum_j ΔP_i·(P_j - P) B_i^{n-1} B_j^n, and
// B_i^{n-1} B_j^n = C(n-1,i) C(n,j) / C(m,i+j) B_{i+j}^m.
void g_coefficients(const Vec3* q, int n, double* h_out, Vec3* w_out, double* h_error,
                    double* w_error) {
  const int m = 2 * n - 1;
  std::array<Vec3, kMaxDegree> diff;
  for (int i = 0; i < n; ++i) diff[i] = q[i + 1] - q[i];
  const double factor = error_factor(m);
  for (int k = 0; k <= m; ++k) {
    double h = 0, h_abs = 0, w_abs = 0;
    Vec3 w = Vec3::Zero();
    for (int i = std::max(0, k - n); i <= std::min(n - 1, k); ++i) {
      const int j = k - i;
      const double coef = n * kBinomial.c[n - 1][i] * kBinomial.c[n][j] / kBinomial.c[m][k];
      h += coef * diff[i].dot(q[j]);
      h_abs += coef * diff[i].cwiseAbs().dot(q[j].cwiseAbs());
      w += coef * diff[i];
      w_abs += coef * diff[i].cwiseAbs().sum();
    }
    h_out[k] = h;
    w_out[k] = w;
    h_error[k] = factor * h_abs;
    w_error[k] = factor * w_abs;
  }
}

// The roots of g (coefficients from g_coefficients, degree m) for the point q, sorted, into
// `roots`; returns their count. When `locate_maxima` is false, roots where g goes from + to -
// (maxima of the distance) may be skipped; `skipped` counts them.
int stationary_roots(const double* h, const Vec3* w, const double* h_error, const double* w_error,
                     int m, const Vec3& q, bool locate_maxima, double* roots, int* skipped) {
  *skipped = 0;
  const double q_max = q.cwiseAbs().maxCoeff();
  // g's Bernstein coefficients and their rounding bounds.
  std::array<double, kMaxCoeff> b;
  std::array<double, kMaxCoeff> e;
  double bound = 0;
  for (int k = 0; k <= m; ++k) {
    b[k] = h[k] - w[k].dot(q);
    e[k] = h_error[k] + w_error[k] * q_max;
    bound = std::max(bound, e[k]);
  }

  // Exact early exit: Descartes' rule of signs on Bernstein coefficients, on [0, 1] and on
  // halves of it (de Casteljau subdivision) down to a bounded depth. When every piece has 0 or 1
  // sign variation, each root of g is isolated on its piece. Otherwise (clustered roots, or a
  // sign within rounding) the derivative chain runs on all of [0, 1].
  std::array<Piece, kMaxCoeff> pieces;
  const int piece_count = isolate(b.data(), bound, m, pieces.data());
  if (piece_count < 0)
    return derivative_chain(b.data(), e.data(), m, locate_maxima, roots, skipped);
  std::array<double, kMaxCoeff> d;  // g' / m
  for (int k = 0; k < m; ++k) d[k] = b[k + 1] - b[k];
  int count = 0;
  for (int k = 0; k < piece_count; ++k) {
    const Piece& piece = pieces[k];
    if (!locate_maxima && piece.sign_lo > 0) {
      ++*skipped;  // g goes from + to -: a maximum of the distance
      continue;
    }
    roots[count++] =
        bracketed_root(b.data(), d.data(), m, piece.lo, piece.hi, piece.sign_lo, piece.guess);
  }
  return count;
}

// The candidates of a projection (in any order); the nearest wins, ties by `rule` on t. When full,
// those that can neither win nor tie are dropped (g has at most 2n-1 roots, but arcs of the fast
// path may each report a root at a shared end).
struct Candidates {
  static constexpr int kCapacity = kMaxCoeff + 4;
  std::array<double, kCapacity> t;
  std::array<double, kCapacity> d2;
  std::array<Vec3, kCapacity> point;  // relative to the projector's origin
  int count = 0;
  void add(double tc, const Vec3& pc, const Vec3& q) {
    if (count == kCapacity) compact();
    if (count == kCapacity) --count;  // every one ties: memory safety only
    t[count] = tc;
    point[count] = pc;
    // Written out: the batched path (bezier_curve_simd.cpp) computes the same sum.
    const double dx = pc.x() - q.x(), dy = pc.y() - q.y(), dz = pc.z() - q.z();
    d2[count] = dx * dx + dy * dy + dz * dz;
    ++count;
  }
  void compact() {
    const double best = *std::min_element(d2.begin(), d2.begin() + count);
    // Twice the tie limit: a later, nearer candidate may still tie with a kept one.
    const double limit = best * (1 + 4 * kTieRelative);
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      if (d2[k] > limit) continue;
      t[kept] = t[k];
      d2[kept] = d2[k];
      point[kept] = point[k];
      ++kept;
    }
    count = kept;
  }
};

BezierProjection choose(const Candidates& c, TieRule rule, const Vec3& origin, int counted) {
  int best = 0;
  for (int k = 1; k < c.count; ++k) {
    if (c.d2[k] < c.d2[best]) best = k;
  }
  const double limit = c.d2[best] * (1 + kTieRelative) * (1 + kTieRelative);
  int chosen = best;
  bool tie = false;
  for (int k = 0; k < c.count; ++k) {
    if (k == best || c.d2[k] > limit) continue;
    if (std::abs(c.t[k] - c.t[best]) > kSameParameter) tie = true;
    if (rule == TieRule::kFirst ? c.t[k] < c.t[chosen] : c.t[k] > c.t[chosen]) chosen = k;
  }
  BezierProjection out;
  out.t = c.t[chosen];
  out.distance = std::sqrt(c.d2[chosen]);
  out.point = c.point[chosen] + origin;
  out.candidates = counted;
  out.tie = tie;
  return out;
}

void check_t(double t, const char* what) {
  if (!(t >= 0.0 && t <= 1.0)) {
    throw InvalidArgument(std::string(what) + ": curve parameter t must be in [0, 1], got " +
                          std::to_string(t));
  }
}

void check_point(const Vec3& p, const char* what) {
  if (!p.allFinite()) throw InvalidArgument(std::string(what) + ": the query point is not finite");
}

// de Casteljau on the `order`-th forward differences of values[0..d], times d!/(d-order)!.
template <class V>
V casteljau(const std::vector<V>& values, double t, int order) {
  const int d = static_cast<int>(values.size()) - 1;
  std::array<V, kMaxDegree + 1> w;
  for (int i = 0; i <= d; ++i) w[i] = values[i];
  return detail::casteljau_in_place(w.data(), d, t, order, V(values[0] * 0.0));
}

template <class V>
V checked_casteljau(const BezierCurve& c, const std::vector<V>& values, double t, int order,
                    const char* what) {
  validate(c, what);
  check_t(t, what);
  return casteljau(values, t, order);
}

}  // namespace

void validate(const BezierCurve& curve, const std::string& what) {
  const std::size_t count = curve.controls.size();
  if (count < 2 || count > kMaxDegree + 1) {
    throw InvalidArgument(what +
                          ": a Bezier curve needs 2 to 16 control points (degree 1 to 15), got " +
                          std::to_string(count));
  }
  double extent = 0;
  detail::ExtentCheck span;  // g's coefficients multiply coordinates: they would overflow first
  for (std::size_t i = 0; i < count; ++i) {
    if (!curve.controls[i].allFinite()) {
      throw InvalidArgument(what + ": control " + std::to_string(i) + " is not finite");
    }
    extent = std::max(extent, curve.controls[i].cwiseAbs().maxCoeff());
    if (!span.add(curve.controls[i])) {
      throw InvalidArgument(what + ": control " + std::to_string(i) + ": " + span.problem("it"));
    }
  }
  if (!curve.radii.empty() && curve.radii.size() != count) {
    throw InvalidArgument(what + ": " + std::to_string(curve.radii.size()) + " radii for " +
                          std::to_string(count) + " controls (give none or one per control)");
  }
  for (std::size_t i = 0; i < curve.radii.size(); ++i) {
    if (!std::isfinite(curve.radii[i]) || curve.radii[i] <= 0) {
      throw InvalidArgument(what + ": radius of control " + std::to_string(i) +
                            " must be finite and > 0, got " + std::to_string(curve.radii[i]));
    }
  }
  double spread = 0;
  for (std::size_t i = 1; i < count; ++i) {
    spread = std::max(spread, (curve.controls[i] - curve.controls[0]).cwiseAbs().maxCoeff());
  }
  if (spread <= tol::kCoincident * extent) {
    throw InvalidArgument(what + ": degenerate curve: every control coincides with control 0");
  }
}

Vec3 bezier_point(const BezierCurve& c, double t) {
  return checked_casteljau(c, c.controls, t, 0, "bezier_point");
}
Vec3 bezier_derivative(const BezierCurve& c, double t) {
  return checked_casteljau(c, c.controls, t, 1, "bezier_derivative");
}
Vec3 bezier_second_derivative(const BezierCurve& c, double t) {
  return checked_casteljau(c, c.controls, t, 2, "bezier_second_derivative");
}
double bezier_radius(const BezierCurve& c, double t) {
  validate(c, "bezier_radius");
  check_t(t, "bezier_radius");
  return c.radii.empty() ? 1.0 : casteljau(c.radii, t, 0);
}
double bezier_radius_derivative(const BezierCurve& c, double t) {
  validate(c, "bezier_radius_derivative");
  check_t(t, "bezier_radius_derivative");
  return c.radii.empty() ? 0.0 : casteljau(c.radii, t, 1);
}

BezierProjector::BezierProjector(BezierCurve curve, const std::string& what)
    : curve_(std::move(curve)) {
  validate(curve_, what);
  n_ = static_cast<int>(curve_.controls.size()) - 1;
  m_ = 2 * n_ - 1;
  for (const Vec3& p : curve_.controls) box_.extend(p);
  origin_ = box_.center();
  // Coordinates relative to the box centre: the coefficients stay small for far-away curves.
  std::array<Vec3, kMaxControls> q;
  std::array<Vec3, kMaxControls> diff;
  for (int i = 0; i <= n_; ++i) {
    q[i] = curve_.controls[i] - origin_;
    scaled_[i] = kBinomial.c[n_][i] * q[i];
  }
  for (int i = 0; i < n_; ++i) {
    diff[i] = q[i + 1] - q[i];
    first_[i] = n_ * kBinomial.c[n_ - 1][i] * diff[i];
  }
  for (int i = 0; i + 1 < n_; ++i) {
    second_[i] = n_ * (n_ - 1) * kBinomial.c[n_ - 2][i] * (diff[i + 1] - diff[i]);
  }
  g_coefficients(q.data(), n_, h_.data(), w_.data(), h_error_.data(), w_error_.data());
  if (n_ <= kMaxFastDegree) build_arcs();
}

Vec3 BezierProjector::local_point(double t) const {
  return bernstein_scaled(scaled_.data(), n_, t);
}

int BezierProjector::stationary(const Vec3& q, bool locate_maxima, double* roots,
                                int* skipped) const {
  return stationary_roots(h_.data(), w_.data(), h_error_.data(), w_error_.data(), m_, q,
                          locate_maxima, roots, skipped);
}

void BezierProjector::build_arcs() {
  // Midpoint halving of the control polygon until each arc's sphere (radius R) is small against
  // rho = floor / max|C''| (floor: below): g is then certified increasing for every query
  // within about rho - R of the arc's centre, whatever its direction, and farther on the convex
  // side, so halving further would gain little (kArcSplit 0.25 gives twice the arcs for a few
  // per cent fewer fallbacks, and is slower). Near a cusp (|C'| -> 0) or a tight bend the depth
  // limit stops it, and queries there fall back to the exact isolation on the arc.
  constexpr int kMaxArcDepth = 6;
  constexpr double kArcSplit = 0.5;
  // Rounding of the bounds (computed from rounded controls): the floor is lowered by this much
  // of its terms' magnitude.
  constexpr double kReachMargin = 1e-9;
  const int n = n_;
  struct Work {
    std::array<Vec3, kMaxControls> q;
    double t0, t1;
    int depth;
  };
  std::vector<Work> stack;
  {
    Work root;
    for (int i = 0; i <= n; ++i) root.q[i] = curve_.controls[i] - origin_;
    root.t0 = 0;
    root.t1 = 1;
    root.depth = 0;
    stack.push_back(root);
  }
  std::vector<Vec3> centres;
  std::vector<double> radii;
  std::vector<double> deviations;   // largest distance of each arc's controls from its chord
  std::vector<Vec3> tangents;       // C'(t0) of each arc in t
  std::vector<Vec3> accelerations;  // C''(t0) of each arc in t
  Vec3 last_tangent = Vec3::Zero();
  Vec3 last_acceleration = Vec3::Zero();
  while (!stack.empty()) {
    Work w = stack.back();
    stack.pop_back();
    const Vec3* q = w.q.data();
    // Hodograph controls D_j = n ΔQ_j (C' in the arc's s), and C'' controls n(n-1) Δ²Q_j.
    double max_second = 0;
    for (int j = 0; j + 2 <= n; ++j) {
      max_second = std::max(max_second, (n * (n - 1) * (q[j + 2] - 2 * q[j + 1] + q[j])).norm());
    }
    Aabb box;
    for (int j = 0; j <= n; ++j) box.extend(q[j]);
    const Vec3 centre = box.center();
    double radius = 0;
    for (int j = 0; j <= n; ++j) radius = std::max(radius, (q[j] - centre).norm());
    // g'(s) = |C'|² + C''·(C - c) + C''·(c - P). The first two terms form a polynomial of degree
    // 2n-2 in s whose least Bernstein coefficient bounds them from below (`floor`); the last is
    // at least min_j E_j·(c - P) (E_j: the controls of C'', convex hull).
    double floor = std::numeric_limits<double>::infinity();
    {
      const int d = 2 * n - 2;
      for (int k = 0; k <= d; ++k) {
        double v = 0, v_abs = 0;
        for (int i = std::max(0, k - (n - 1)); i <= std::min(n - 1, k); ++i) {
          const Vec3 di = n * (q[i + 1] - q[i]), dj = n * (q[k - i + 1] - q[k - i]);
          const double coef = kBinomial.c[n - 1][i] * kBinomial.c[n - 1][k - i] / kBinomial.c[d][k];
          v += coef * di.dot(dj);
          v_abs += coef * di.norm() * dj.norm();
        }
        for (int i = std::max(0, k - n); i <= std::min(n - 2, k); ++i) {
          const Vec3 ei = n * (n - 1) * (q[i + 2] - 2 * q[i + 1] + q[i]);
          const Vec3 rj = q[k - i] - centre;
          const double coef = kBinomial.c[n - 2][i] * kBinomial.c[n][k - i] / kBinomial.c[d][k];
          v += coef * ei.dot(rj);
          v_abs += coef * ei.norm() * rj.norm();
        }
        floor = std::min(floor, v - kReachMargin * v_abs);
      }
    }
    const double rho =
        max_second > 0 ? floor / max_second : std::numeric_limits<double>::infinity();
    if (w.depth < kMaxArcDepth && !(floor > 0 && radius <= kArcSplit * rho)) {
      // de Casteljau at 1/2: left half's controls are the first entries of each row.
      Work left, right;
      std::array<Vec3, kMaxControls> row = w.q;
      left.q[0] = row[0];
      right.q[n] = row[n];
      for (int r = 1; r <= n; ++r) {
        for (int i = 0; i <= n - r; ++i) row[i] = 0.5 * (row[i] + row[i + 1]);
        left.q[r] = row[0];
        right.q[n - r] = row[n - r];
      }
      const double mid = 0.5 * (w.t0 + w.t1);
      left.t0 = w.t0;
      left.t1 = mid;
      right.t0 = mid;
      right.t1 = w.t1;
      left.depth = right.depth = w.depth + 1;
      stack.push_back(right);
      stack.push_back(left);  // processed first: arcs come out in ascending t
      continue;
    }
    Arc arc;
    arc.t0 = w.t0;
    arc.t1 = w.t1;
    // Power basis in s: a_j = C(n,j) Δ^j Q_0.
    std::array<Vec3, kMaxControls> diff = w.q;
    for (int j = 0; j <= n; ++j) {
      arc.power[j] = kBinomial.c[n][j] * diff[0];
      for (int i = 0; i + j < n; ++i) diff[i] = diff[i + 1] - diff[i];
    }
    for (int j = 0; j + 2 <= n; ++j) arc.second[j] = n * (n - 1) * (q[j + 2] - 2 * q[j + 1] + q[j]);
    arc.floor = floor;
    for (int j = 0; j + 2 <= n; ++j)
      arc.second_max = std::max(arc.second_max, arc.second[j].cwiseAbs().maxCoeff());
    // |g''| = |3 C'·C'' + C'''·(C - P)| <= 3 max|C'| max|C''| + max|C'''| (|P - c| + R).
    {
      double max_first = 0, max_third = 0;
      for (int j = 0; j < n; ++j) max_first = std::max(max_first, (n * (q[j + 1] - q[j])).norm());
      for (int j = 0; j + 3 <= n; ++j) {
        const Vec3 third = n * (n - 1) * (n - 2) * (q[j + 3] - 3 * q[j + 2] + 3 * q[j + 1] - q[j]);
        max_third = std::max(max_third, third.norm());
      }
      arc.g2_fixed = 3 * max_first * max_second * (1 + kReachMargin);
      arc.g2_per_distance = max_third * (1 + kReachMargin);
    }
    g_coefficients(q, n, arc.g.h.data(), arc.g.w.data(), arc.g.h_error.data(),
                   arc.g.w_error.data());
    arcs_.push_back(arc);
    centres.push_back(centre);
    // Inflated for rounding (as the group spheres are): a query at the arc's control farthest
    // from the centre (the arc's end, where the nearest point may be) lies on the exact sphere,
    // and the sphere test against a zero bound (a query on an arc end: the first visit's ends
    // give best2 = 0) would otherwise reject the arc that holds the root by one rounding.
    radii.push_back(radius * (1 + kReachMargin) + 1e-12 * (centre.cwiseAbs().maxCoeff() + radius));
    {
      // The arc lies in the convex hull of its controls, and the distance to the chord segment
      // is convex: the arc is within max_j dist(Q_j, chord) of the chord.
      const Vec3 chord = q[n] - q[0];
      const double chord2 = chord.squaredNorm();
      double deviation = 0;
      for (int j = 0; j <= n; ++j) {
        const Vec3 w = q[j] - q[0];
        const double s = chord2 > 0 ? std::clamp(w.dot(chord) / chord2, 0.0, 1.0) : 0.0;
        deviation = std::max(deviation, (w - s * chord).norm());
      }
      deviations.push_back(deviation * (1 + kReachMargin) + kReachMargin * radius);
    }
    const double span = w.t1 - w.t0;
    tangents.push_back(n * (q[1] - q[0]) / span);
    last_tangent = n * (q[n] - q[n - 1]) / span;
    accelerations.push_back(n > 1 ? Vec3(n * (n - 1) * (q[2] - 2 * q[1] + q[0]) / (span * span))
                                  : Vec3::Zero());
    last_acceleration =
        n > 1 ? Vec3(n * (n - 1) * (q[n] - 2 * q[n - 1] + q[n - 2]) / (span * span)) : Vec3::Zero();
  }
  const std::size_t count = arcs_.size();
  ArcScan& a = scan_;
  for (std::size_t k = 0; k < count; ++k) {
    a.cx.push_back(centres[k].x());
    a.cy.push_back(centres[k].y());
    a.cz.push_back(centres[k].z());
    a.radius.push_back(radii[k]);
    const Vec3 start = arcs_[k].power[0];
    const Vec3 end =
        k + 1 < count ? Vec3(arcs_[k + 1].power[0]) : Vec3(curve_.controls[n] - origin_);
    const Vec3 chord = end - start;
    const double chord2 = chord.x() * chord.x() + chord.y() * chord.y() + chord.z() * chord.z();
    a.ux.push_back(chord.x());
    a.uy.push_back(chord.y());
    a.uz.push_back(chord.z());
    a.inv_chord2.push_back(chord2 > 0 ? 1 / chord2 : 0.0);
    a.deviation.push_back(deviations[k]);
  }
  for (std::size_t k = 0; k <= count; ++k) {
    const Vec3 p = k < count ? Vec3(arcs_[k].power[0]) : Vec3(curve_.controls[n] - origin_);
    const Vec3 t = k < count ? tangents[k] : last_tangent;
    a.px.push_back(p.x());
    a.py.push_back(p.y());
    a.pz.push_back(p.z());
    a.tx.push_back(t.x());
    a.ty.push_back(t.y());
    a.tz.push_back(t.z());
    const Vec3 acc = k < count ? accelerations[k] : last_acceleration;
    a.ax.push_back(acc.x());
    a.ay.push_back(acc.y());
    a.az.push_back(acc.z());
  }
  // The same arcs as flat arrays for the batched path (field/bezier_curve_simd.h).
  auto table = std::make_shared<detail::BezierArcTable>();
  table->degree = n;
  table->count = static_cast<int>(count);
  table->cx = a.cx;
  table->cy = a.cy;
  table->cz = a.cz;
  table->radius = a.radius;
  table->ux = a.ux;
  table->uy = a.uy;
  table->uz = a.uz;
  table->inv_chord2 = a.inv_chord2;
  table->deviation = a.deviation;
  // Group spheres: centred at the middle of the group's arc centres' box, holding every arc
  // sphere of the group; inflated (1e-9 relative and 1e-12 of the coordinates' magnitude) so
  // that a group the batched path finds out of reach holds no arc its per-arc test would take.
  for (std::size_t g0 = 0; g0 < count; g0 += detail::kBezierGroup) {
    const std::size_t g1 = std::min(count, g0 + detail::kBezierGroup);
    Aabb centres;
    for (std::size_t k = g0; k < g1; ++k) centres.extend(Vec3(a.cx[k], a.cy[k], a.cz[k]));
    const Vec3 c = centres.center();
    double r = 0;
    for (std::size_t k = g0; k < g1; ++k)
      r = std::max(r, (Vec3(a.cx[k], a.cy[k], a.cz[k]) - c).norm() + a.radius[k]);
    table->gx.push_back(c.x());
    table->gy.push_back(c.y());
    table->gz.push_back(c.z());
    table->gradius.push_back(r * (1 + 1e-9) + 1e-12 * (c.cwiseAbs().maxCoeff() + r));
  }
  for (const Arc& arc : arcs_) {
    const double span = arc.t1 - arc.t0;
    table->t0.push_back(arc.t0);
    table->span.push_back(span);
    table->tolerance.push_back(kRootTolerance / span);
    table->floor.push_back(arc.floor);
    table->second_max.push_back(arc.second_max);
    table->g2_fixed.push_back(arc.g2_fixed);
    table->g2_per_distance.push_back(arc.g2_per_distance);
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (const Arc& arc : arcs_) {
      table->ex.push_back(arc.second[j].x());
      table->ey.push_back(arc.second[j].y());
      table->ez.push_back(arc.second[j].z());
    }
  }
  for (int j = 0; j <= n; ++j) {
    for (const Arc& arc : arcs_) {
      table->ax.push_back(arc.power[j].x());
      table->ay.push_back(arc.power[j].y());
      table->az.push_back(arc.power[j].z());
    }
  }
  table->px = a.px;
  table->py = a.py;
  table->pz = a.pz;
  table->tx = a.tx;
  table->ty = a.ty;
  table->tz = a.tz;
  table->sx = a.ax;
  table->sy = a.ay;
  table->sz = a.az;
  table_ = std::move(table);
}

int BezierProjector::isolate_arc(const void* self, int arc, const double* q, double* roots,
                                 int* skipped) {
  const auto& p = *static_cast<const BezierProjector*>(self);
  const ArcG& g = p.arcs_[static_cast<std::size_t>(arc)].g;
  return stationary_roots(g.h.data(), g.w.data(), g.h_error.data(), g.w_error.data(), 2 * p.n_ - 1,
                          Vec3(q[0], q[1], q[2]), false, roots, skipped);
}

namespace {

// C, C' and C'' of a power-basis polynomial (coefficients a[0..N]) at s, by Horner.
struct Jet {
  Vec3 c, d1, d2;
};
template <int N>
inline Jet power_jet(const Vec3* a, double s) {
  Vec3 c = a[N], d1 = Vec3::Zero(), d2 = Vec3::Zero();
  for (int j = N - 1; j >= 0; --j) {
    d2 = d2 * s + d1;
    d1 = d1 * s + c;
    c = c * s + a[j];
  }
  return {c, d1, 2 * d2};
}
inline Vec3 power_point(const Vec3* a, int n, double s) {
  Vec3 c = a[n];
  for (int j = n - 1; j >= 0; --j) c = c * s + a[j];
  return c;
}

struct ArcRoot {
  double s;
  Vec3 point;
};

// The root of g on an arc where g is increasing (certified), g(0) < 0 <= g(1): Newton from the
// chord guess s0, safeguarded by bisection with the bracket kept. With g' >= slope > 0 and
// |g''| <= G2 on the arc, the root is within |g(s)| / slope of s, and the Newton step from s
// lands within G2 g(s)² / (2 slope³) of it: the iteration stops once g(s)² <= `stop`, which the
// caller sets so that this is below `tolerance` (or once the step itself is).
template <int N>
ArcRoot arc_root(const Vec3* a, const Vec3& q, double s0, double tolerance, double stop) {
  // Coordinates apart (plain scalars keep the Horner chains in registers).
  double ax[N + 1], ay[N + 1], az[N + 1];
  for (int j = 0; j <= N; ++j) {
    ax[j] = a[j].x();
    ay[j] = a[j].y();
    az[j] = a[j].z();
  }
  const double qx = q.x(), qy = q.y(), qz = q.z();
  double lo = 0, hi = 1;
  double s = s0 > 0 && s0 < 1 ? s0 : 0.5;
  for (int it = 0; it < kMaxRootIterations; ++it) {
    // C, C' and C''/2 by Horner; the first two steps, where C' and C''/2 start from 0, are
    // written out without their products by 0 (the batched path does the same operations).
    double cx = ax[N], cy = ay[N], cz = az[N];
    double ux = cx, uy = cy, uz = cz;  // C'
    double vx = 0, vy = 0, vz = 0;     // C'' / 2
    cx = cx * s + ax[N - 1];
    cy = cy * s + ay[N - 1];
    cz = cz * s + az[N - 1];
    if constexpr (N >= 2) {
      vx = ux;
      vy = uy;
      vz = uz;
      ux = ux * s + cx;
      uy = uy * s + cy;
      uz = uz * s + cz;
      cx = cx * s + ax[N - 2];
      cy = cy * s + ay[N - 2];
      cz = cz * s + az[N - 2];
    }
    for (int j = N - 3; j >= 0; --j) {
      vx = vx * s + ux;
      vy = vy * s + uy;
      vz = vz * s + uz;
      ux = ux * s + cx;
      uy = uy * s + cy;
      uz = uz * s + cz;
      cx = cx * s + ax[j];
      cy = cy * s + ay[j];
      cz = cz * s + az[j];
    }
    const double rx = cx - qx, ry = cy - qy, rz = cz - qz;
    const double g = ux * rx + uy * ry + uz * rz;
    if (g == 0) return {s, Vec3(cx, cy, cz)};
    if (g < 0) {
      lo = s;
    } else {
      hi = s;
    }
    const double gp = ux * ux + uy * uy + uz * uz + 2 * (vx * rx + vy * ry + vz * rz);
    const double step = g / gp;
    const double next = s - step;
    if (!(gp > 0) || !(next > lo && next < hi)) {
      s = 0.5 * (lo + hi);
      if (hi - lo <= tolerance) return {s, power_point(a, N, s)};
      continue;
    }
    // C(next) by Horner (the same operations as the batched path's).
    if (g * g <= stop || std::abs(step) <= tolerance) return {next, power_point(a, N, next)};
    s = next;
  }
  return {s, power_point(a, N, s)};
}

}  // namespace

template <int N>
BezierProjection BezierProjector::project_arcs(const Vec3& q, TieRule rule) const {
  const ArcScan& a = scan_;
  const int count = static_cast<int>(arcs_.size());
  const double qx = q.x(), qy = q.y(), qz = q.z();
  const double* cx = a.cx.data();
  const double* cy = a.cy.data();
  const double* cz = a.cz.data();
  const double* radius = a.radius.data();
  const double* px = a.px.data();
  const double* py = a.py.data();
  const double* pz = a.pz.data();
  const double* tx = a.tx.data();
  const double* ty = a.ty.data();
  const double* tz = a.tz.data();
  // Squared distance from q to every arc's centre; the arc with the nearest centre goes first:
  // what it finds bounds the others.
  std::array<double, kMaxArcs> dc2;
  int first = 0;
  double first_d2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) {
    const double dx = cx[i] - qx, dy = cy[i] - qy, dz = cz[i] - qz;
    const double d2 = dx * dx + dy * dy + dz * dz;
    dc2[static_cast<std::size_t>(i)] = d2;
    if (d2 < first_d2) {
      first_d2 = d2;
      first = i;
    }
  }
  auto end_d2 = [&](int k) {
    const double dx = px[k] - qx, dy = py[k] - qy, dz = pz[k] - qz;
    return dx * dx + dy * dy + dz * dz;
  };
  // g at arc end k (in t), the same value wherever it is used, and g' there.
  auto g_end = [&](int k) {
    return tx[k] * (px[k] - qx) + ty[k] * (py[k] - qy) + tz[k] * (pz[k] - qz);
  };
  auto g_slope = [&](int k) {
    return tx[k] * tx[k] + ty[k] * ty[k] + tz[k] * tz[k] + a.ax[k] * (px[k] - qx) +
           a.ay[k] * (py[k] - qy) + a.az[k] * (pz[k] - qz);
  };
  Candidates c;
  c.add(0, Vec3(px[0], py[0], pz[0]), q);
  c.add(1, Vec3(px[count], py[count], pz[count]), q);
  // Upper bound of the nearest distance: the curve's ends and the first arc's ends.
  double best2 = std::min({c.d2[0], c.d2[1], end_d2(first), end_d2(first + 1)});
  int interior = 0, skipped = 0;

  auto visit = [&](int i) {
    const Arc& arc = arcs_[static_cast<std::size_t>(i)];
    const double span = arc.t1 - arc.t0;
    const double dx = cx[i] - qx, dy = cy[i] - qy, dz = cz[i] - qz;
    // A lower bound of g' on the arc (in s); C'' = 0 for n = 1.
    double bend = N > 1 ? std::numeric_limits<double>::infinity() : 0.0;
    for (int j = 0; j + 1 < N; ++j) {
      bend =
          std::min(bend, arc.second[j].x() * dx + arc.second[j].y() * dy + arc.second[j].z() * dz);
    }
    // Certified when the bound beats the rounding of the query-dependent term.
    const double slope = arc.floor + bend;
    const double rounding =
        kSlopeRounding * arc.second_max * (std::abs(dx) + std::abs(dy) + std::abs(dz));
    if (slope > rounding) {
      // g increasing on the arc: one minimum inside when g goes from - to +, else none.
      const double g0 = g_end(i);
      const double g1 = g_end(i + 1);
      if (!(g0 < 0 && g1 >= 0)) return;
      const double tolerance = kRootTolerance / span;
      const double g2 =
          arc.g2_fixed +
          arc.g2_per_distance * (std::sqrt(dc2[static_cast<std::size_t>(i)]) + radius[i]);
      const double stop = g2 > 0 ? 2 * tolerance * slope * slope * slope / g2
                                 : std::numeric_limits<double>::infinity();
      // Start: the root of g's cubic Hermite interpolant from the ends (values and slopes),
      // by one Newton step from the chord's root (a second costs more than it saves).
      const double m0 = span * g_slope(i), m1 = span * g_slope(i + 1);
      double s0 = g0 / (g0 - g1);
      {
        const double u = s0, u2 = u * u, u3 = u2 * u;
        const double h = g0 * (2 * u3 - 3 * u2 + 1) + g1 * (3 * u2 - 2 * u3) +
                         m0 * (u3 - 2 * u2 + u) + m1 * (u3 - u2);
        const double dh =
            (g1 - g0) * (6 * u - 6 * u2) + m0 * (3 * u2 - 4 * u + 1) + m1 * (3 * u2 - 2 * u);
        const double next = u - h / dh;
        if (dh > 0 && next > 0 && next < 1) s0 = next;
      }
      const ArcRoot root = arc_root<N>(arc.power.data(), q, s0, tolerance, stop);
      ++interior;
      c.add(arc.t0 + root.s * span, root.point, q);
      best2 = std::min(best2, c.d2[c.count - 1]);
      return;
    }
    // Out of reach: the exact isolation on the arc (Rigaudière et al. §3.4).
    std::array<double, kMaxCoefficients + 2> roots;
    int arc_skipped = 0;
    const int found =
        stationary_roots(arc.g.h.data(), arc.g.w.data(), arc.g.h_error.data(), arc.g.w_error.data(),
                         2 * N - 1, q, false, roots.data(), &arc_skipped);
    skipped += arc_skipped;
    for (int k = 0; k < found; ++k) {
      const double s = roots[k];
      if (!(s >= 0 && s <= 1)) continue;
      const double t = arc.t0 + s * span;
      if (!(t > 0 && t < 1)) continue;
      ++interior;
      c.add(t, power_point(arc.power.data(), N, s), q);
      best2 = std::min(best2, c.d2[c.count - 1]);
    }
  };

  visit(first);
  // An arc whose sphere is farther than the best point found by then (inflated for ties and
  // rounding) cannot hold the nearest point. The bound is not tightened by the visits that
  // follow: they are independent of each other, so that the batched path can queue their
  // Newton runs and run them in full vectors (field/bezier_curve_simd.cpp).
  constexpr double kPruneSlack = detail::kBezierPruneSlack;
  // Two lower bounds of the distance to an arc: to its sphere, and to its chord less the arc's
  // deviation from the chord (tighter for flat arcs).
  const double prune = std::sqrt(best2) * (1 + kPruneSlack);
  for (int i = 0; i < count; ++i) {
    const double lim = radius[i] + prune;
    if (i == first || dc2[static_cast<std::size_t>(i)] > lim * lim) continue;
    const double wx = qx - px[i], wy = qy - py[i], wz = qz - pz[i];
    double s = (wx * a.ux[i] + wy * a.uy[i] + wz * a.uz[i]) * a.inv_chord2[i];
    s = s < 0 ? 0.0 : s;
    s = s > 1 ? 1.0 : s;
    const double rx = wx - s * a.ux[i], ry = wy - s * a.uy[i], rz = wz - s * a.uz[i];
    const double chord_lim = prune + a.deviation[i];
    if (rx * rx + ry * ry + rz * rz > chord_lim * chord_lim) continue;
    visit(i);
  }
  return choose(c, rule, origin_, interior + skipped + 2);
}

BezierProjection BezierProjector::project_whole(const Vec3& q, TieRule rule) const {
  std::array<double, kMaxCoefficients + 2> roots;
  int skipped = 0;
  const int count = stationary(q, false, roots.data(), &skipped);
  // Candidates in ascending t: the ends and the interior roots.
  Candidates c;
  c.add(0, curve_.controls[0] - origin_, q);
  int interior = 0;
  for (int k = 0; k < count; ++k) {
    const double t = roots[k];
    if (!(t > 0 && t < 1)) continue;
    ++interior;
    c.add(t, local_point(t), q);
  }
  c.add(1, curve_.controls[n_] - origin_, q);
  return choose(c, rule, origin_, interior + skipped + 2);
}

std::vector<double> BezierProjector::stationary_parameters(const Vec3& p) const {
  check_point(p, "stationary_parameters");
  std::array<double, kMaxCoefficients + 2> roots;
  int skipped = 0;
  const int count = stationary(p - origin_, true, roots.data(), &skipped);
  return {roots.begin(), roots.begin() + count};
}

BezierProjection BezierProjector::project(const Vec3& p, TieRule rule) const {
  check_point(p, "project");
  const Vec3 q = p - origin_;
  switch (arcs_.empty() ? 0 : n_) {
    case 1:
      return project_arcs<1>(q, rule);
    case 2:
      return project_arcs<2>(q, rule);
    case 3:
      return project_arcs<3>(q, rule);
    case 4:
      return project_arcs<4>(q, rule);
    case 5:
      return project_arcs<5>(q, rule);
    case 6:
      return project_arcs<6>(q, rule);
    case 7:
      return project_arcs<7>(q, rule);
    default:
      return project_whole(q, rule);
  }
}

void BezierProjector::project(std::span<const Vec3> points, std::span<BezierProjection> out,
                              TieRule rule) const {
  if (points.size() != out.size()) {
    throw InvalidArgument("project: " + std::to_string(points.size()) + " points but " +
                          std::to_string(out.size()) + " outputs");
  }
  for (const Vec3& p : points) {
    if (!(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z())))
      check_point(p, "project");  // throws
  }
  // Above degree 7 there are no arcs; below 4 points a vector would be mostly padding.
  if (arcs_.empty() || points.size() < 4) {
    for (std::size_t k = 0; k < points.size(); ++k) out[k] = project(points[k], rule);
    return;
  }
  // Blocks of the batched arc path (SIMD across points); a point whose nearest candidates are
  // near a tie is projected one by one, where choose() applies the rule.
  constexpr std::size_t kBlock = detail::kBezierBatch;
  std::array<double, kBlock> qx, qy, qz;
  std::array<detail::BezierLaneResult, kBlock> lanes;
  for (std::size_t begin = 0; begin < points.size(); begin += kBlock) {
    const std::size_t count = std::min(kBlock, points.size() - begin);
    for (std::size_t k = 0; k < count; ++k) {
      const Vec3 q = points[begin + k] - origin_;
      qx[k] = q.x();
      qy[k] = q.y();
      qz[k] = q.z();
    }
    detail::project_arcs_batch(*table_, qx.data(), qy.data(), qz.data(), count, &isolate_arc, this,
                               lanes.data());
    for (std::size_t k = 0; k < count; ++k) {
      const detail::BezierLaneResult& r = lanes[k];
      if (r.redo) {
        out[begin + k] = project(points[begin + k], rule);
        continue;
      }
      BezierProjection& o = out[begin + k];
      o.t = r.t;
      o.distance = r.distance;
      o.point = Vec3(r.x, r.y, r.z) + origin_;
      o.candidates = r.counted + 2;
      o.tie = false;
    }
  }
}

BezierProjection BezierProjector::project_newton(const Vec3& p, int starts) const {
  check_point(p, "project_newton");
  if (starts < 2) {
    throw InvalidArgument("project_newton: starts must be >= 2, got " + std::to_string(starts));
  }
  const Vec3 q = p - origin_;
  double t = 0;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < starts; ++i) {
    const double s = static_cast<double>(i) / (starts - 1);
    const double d2 = (local_point(s) - q).squaredNorm();
    if (d2 < best) {
      best = d2;
      t = s;
    }
  }
  for (int it = 0; it < kNewtonSteps; ++it) {
    const Vec3 r = local_point(t) - q;
    const Vec3 d1 = bernstein_scaled(first_.data(), n_ - 1, t);
    const Vec3 dd = n_ >= 2 ? bernstein_scaled(second_.data(), n_ - 2, t) : Vec3::Zero();
    const double g = d1.dot(r);
    const double gp = d1.squaredNorm() + dd.dot(r);
    if (gp == 0) break;
    const double next = std::clamp(t - g / gp, 0.0, 1.0);
    const bool done = std::abs(next - t) <= kRootTolerance;
    t = next;
    if (done) break;
  }
  BezierProjection out;
  out.t = t;
  const Vec3 c = local_point(t);
  out.distance = (c - q).norm();
  out.point = c + origin_;
  out.candidates = starts;
  return out;
}

}  // namespace ramiform
