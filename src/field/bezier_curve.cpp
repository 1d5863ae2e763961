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
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

constexpr int kMaxDegree = 15;
constexpr int kMaxG = 2 * kMaxDegree - 1;  // degree of g
constexpr double kEps = std::numeric_limits<double>::epsilon();
// Root finding stops when the Newton step or the bracket is below this (t is in [0, 1]).
constexpr double kRootTolerance = 1e-15;
constexpr int kMaxRootIterations = 200;
// Newton steps shrinking by at least this factor are taken as in the quadratic regime.
constexpr double kAsymptotic = 0.1;
// Distances equal within this relative amount are a tie (see TieRule).
constexpr double kTieRelative = 1e-12;
// Candidates closer than this in t are the same point, not a tie.
constexpr double kSameParameter = 1e-12;
constexpr int kNewtonSteps = 20;

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
  double lo;      // interval
  double hi;
  double guess;   // where the control polygon of g crosses 0 on it: Newton's start
  int sign_lo;    // sign of g just right of lo
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
    throw InvalidArgument(what + ": a Bezier curve needs 2 to 16 control points (degree 1 to 15), got " +
                          std::to_string(count));
  }
  double extent = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!curve.controls[i].allFinite()) {
      throw InvalidArgument(what + ": control " + std::to_string(i) + " is not finite");
    }
    extent = std::max(extent, curve.controls[i].cwiseAbs().maxCoeff());
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
  // C'(t)·(C(t) - P) = n sum_i sum_j ΔP_i·(P_j - P) B_i^{n-1} B_j^n, and
  // B_i^{n-1} B_j^n = C(n-1,i) C(n,j) / C(m,i+j) B_{i+j}^m.
  const double factor = error_factor(m_);
  for (int k = 0; k <= m_; ++k) {
    double h = 0, h_abs = 0, w_abs = 0;
    Vec3 w = Vec3::Zero();
    for (int i = std::max(0, k - n_); i <= std::min(n_ - 1, k); ++i) {
      const int j = k - i;
      const double coef = n_ * kBinomial.c[n_ - 1][i] * kBinomial.c[n_][j] / kBinomial.c[m_][k];
      h += coef * diff[i].dot(q[j]);
      h_abs += coef * diff[i].cwiseAbs().dot(q[j].cwiseAbs());
      w += coef * diff[i];
      w_abs += coef * diff[i].cwiseAbs().sum();
    }
    h_[k] = h;
    w_[k] = w;
    h_error_[k] = factor * h_abs;
    w_error_[k] = factor * w_abs;
  }
}

Vec3 BezierProjector::local_point(double t) const { return bernstein_scaled(scaled_.data(), n_, t); }

int BezierProjector::stationary(const Vec3& q, bool locate_maxima, double* roots, int* skipped) const {
  const int m = m_;
  *skipped = 0;
  const double q_max = q.cwiseAbs().maxCoeff();
  // g's Bernstein coefficients and their rounding bounds.
  std::array<double, kMaxCoefficients> b;
  std::array<double, kMaxCoefficients> e;
  double bound = 0;
  for (int k = 0; k <= m; ++k) {
    b[k] = h_[k] - w_[k].dot(q);
    e[k] = h_error_[k] + w_error_[k] * q_max;
    bound = std::max(bound, e[k]);
  }

  // Exact early exit: Descartes' rule of signs on Bernstein coefficients, on [0, 1] and on
  // halves of it (de Casteljau subdivision) down to a bounded depth. When every piece has 0 or 1
  // sign variation, each root of g is isolated on its piece. Otherwise (clustered roots, or a
  // sign within rounding) the derivative chain runs on all of [0, 1].
  std::array<Piece, kMaxCoefficients> pieces;
  const int piece_count = isolate(b.data(), bound, m, pieces.data());
  if (piece_count < 0) return derivative_chain(b.data(), e.data(), m, locate_maxima, roots, skipped);
  std::array<double, kMaxCoefficients> d;  // g' / m
  for (int k = 0; k < m; ++k) d[k] = b[k + 1] - b[k];
  int count = 0;
  for (int k = 0; k < piece_count; ++k) {
    const Piece& piece = pieces[k];
    if (!locate_maxima && piece.sign_lo > 0) {
      ++*skipped;  // g goes from + to -: a maximum of the distance
      continue;
    }
    roots[count++] = bracketed_root(b.data(), d.data(), m, piece.lo, piece.hi, piece.sign_lo, piece.guess);
  }
  return count;
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
  std::array<double, kMaxCoefficients + 2> roots;
  int skipped = 0;
  const int count = stationary(q, false, roots.data(), &skipped);

  // Candidates in ascending t: the ends and the interior roots.
  std::array<double, kMaxCoefficients + 4> ts;
  std::array<double, kMaxCoefficients + 4> d2;
  std::array<Vec3, kMaxCoefficients + 4> points;
  int c = 0;
  int interior = 0;
  ts[c] = 0;
  points[c] = curve_.controls[0] - origin_;
  d2[c++] = (points[0] - q).squaredNorm();
  for (int k = 0; k < count; ++k) {
    const double t = roots[k];
    if (!(t > 0 && t < 1)) continue;
    ++interior;
    ts[c] = t;
    points[c] = local_point(t);
    d2[c] = (points[c] - q).squaredNorm();
    ++c;
  }
  ts[c] = 1;
  points[c] = curve_.controls[n_] - origin_;
  d2[c] = (points[c] - q).squaredNorm();
  ++c;

  int best = 0;
  for (int k = 1; k < c; ++k) {
    if (d2[k] < d2[best]) best = k;
  }
  const double limit = d2[best] * (1 + kTieRelative) * (1 + kTieRelative);
  int chosen = best;
  bool tie = false;
  for (int k = 0; k < c; ++k) {
    if (k == best || d2[k] > limit) continue;
    if (std::abs(ts[k] - ts[best]) > kSameParameter) tie = true;
    if (rule == TieRule::kFirst ? k < chosen : k > chosen) chosen = k;
  }
  BezierProjection out;
  out.t = ts[chosen];
  out.distance = std::sqrt(d2[chosen]);
  out.point = points[chosen] + origin_;
  out.candidates = interior + skipped + 2;
  out.tie = tie;
  return out;
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
