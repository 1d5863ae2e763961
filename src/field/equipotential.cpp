// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/equipotential.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>
#include <sstream>
#include <string>

#include "field/equipotential_simd.h"
#include "field/pointwise_field.h"
#include "field/radius_fit_detail.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kLeafSize = 8;
constexpr std::size_t kMaxEdgeCharges = std::size_t{1} << 26;
constexpr std::size_t kMaxCharges = std::size_t{1} << 26;
constexpr double kBoundTheta = 0.5;  // clusters smaller than this times their distance: one box
constexpr int kBoundsDepth = 10;     // octree levels refining bounds() at most
constexpr std::size_t kBoundsCells = 20000;  // stop refining bounds() beyond this many cells
constexpr double kMaxTipFactor = 50.0;       // a closed leaf's charge is raised at most this much
constexpr double kForkGap = 1.5;    // the fit leaves out stations this many radii from a fork
constexpr double kHuber = 0.02;     // the fit's Huber threshold, relative to lambda
constexpr std::size_t kGroup = detail::kChargeGroup;  // points sharing one traversal

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

void require(bool ok, const std::string& what, double v, const std::string& rule) {
  if (!ok) throw InvalidArgument(what + " must be " + rule + ", got " + fmt(v));
}

// w(s) = s^(-(alpha - 1) / 2) for s = |r - c|^2 + h^2, with fast paths for integer alpha.
struct PowerKernel {
  double alpha = 4.0;
  double half = 1.5;  // (alpha - 1) / 2
  double h2 = 0.0;
  int mode = 0;  // integer alpha 2..7, or 0 for pow

  PowerKernel() = default;
  PowerKernel(double a, double soft2) : alpha(a), half(0.5 * (a - 1.0)), h2(soft2) {
    const double r = std::round(a);
    mode = (r == a && r >= 2 && r <= 7) ? static_cast<int>(r) : 0;
  }

  [[nodiscard]] double w(double s) const { return w_of_u(1.0 / s, s); }
  // w for u = 1 / s (integer alpha only; mode 0 takes the pow of s).
  [[nodiscard]] double w_of_u(double u, double s) const {
    switch (mode) {
      case 2:
        return std::sqrt(u);
      case 3:
        return u;
      case 4:
        return u * std::sqrt(u);
      case 5:
        return u * u;
      case 6:
        return u * u * std::sqrt(u);
      case 7:
        return u * u * u;
      default:
        return std::pow(s, -half);
    }
  }
};

// Barnes-Hut treecode over the charges: a binary tree of clusters split at the median of the
// longest axis, leaves of at most kLeafSize charges stored contiguously.
class ChargeTree {
 public:
  ChargeTree(std::span<const Vec3> positions, std::span<const double> values, double alpha,
             double theta)
      : theta2_(theta * theta) {
    const std::size_t n = positions.size();
    Aabb all;
    for (const Vec3& p : positions) all.extend(p);
    extent_ = n > 0 ? all.diagonal().norm() : 0.0;
    const double h = 1e-9 * std::max(extent_, 1e-300);
    kernel_ = PowerKernel(alpha, h * h);
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0U);
    if (n > 0) {
      nodes_.reserve(2 * (n / kLeafSize + 1));
      build(positions, 0, static_cast<std::uint32_t>(n));
    }
    pos_.resize(n);
    val_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      pos_[i] = positions[order_[i]];
      val_[i] = values[order_[i]];
    }
    if (n > 0) summarize(0);
    box_ = all;
  }

  [[nodiscard]] const PowerKernel& kernel() const { return kernel_; }
  [[nodiscard]] const Aabb& box() const { return box_; }
  [[nodiscard]] double total() const { return nodes_.empty() ? 0.0 : nodes_[0].q; }
  [[nodiscard]] std::size_t size() const { return pos_.size(); }

  // The potential at p, and its gradient in *grad when grad is set.
  double eval(const Vec3& p, Vec3* grad) const {
    double f = 0.0;
    Vec3 g = Vec3::Zero();
    if (nodes_.empty()) {
      if (grad != nullptr) *grad = g;
      return 0.0;
    }
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& c = nodes_[stack[--top]];
      if (!(c.q > 0)) continue;
      const Vec3 d = p - c.centroid;
      const double d2 = squared_norm(d);
      if (c.rho2 < theta2_ * d2) {
        add_cluster(c, d, d2, f, g, grad != nullptr);
      } else if (c.right == kNone) {
        add_leaf(c, p, f, g, grad != nullptr);
      } else {
        stack[top++] = c.right;
        stack[top++] = c.first;
      }
    }
    if (grad != nullptr) *grad = g;
    return f;
  }

  // eval() at n <= kGroup points at once, bit for bit the same values and gradients (`g` may be
  // null): the clusters every point of the group would treat alike are decided once for the
  // group's box, in eval()'s depth-first order, and each point adds the same terms in the same
  // order as its own traversal would. Where the box does not decide (a cluster far from some
  // points and near others, or within rounding of the criterion), each point decides itself:
  // a point that takes such a cluster whole skips the actions of its subtree. With an integer
  // alpha (2 to 7) the points run as SIMD lanes (field/equipotential_simd.h), the same
  // operations in the same order; otherwise one after another here.
  void eval_group(const Vec3* p, std::size_t n, double* f, Vec3* g) const {
    for (std::size_t k = 0; k < n; ++k) {
      f[k] = 0.0;
      if (g != nullptr) g[k] = Vec3::Zero();
    }
    if (nodes_.empty() || n == 0) return;
    Aabb box;
    for (std::size_t k = 0; k < n; ++k) box.extend(p[k]);
    thread_local std::vector<Action> actions;
    actions.clear();
    collect(0, box, actions);
    if (kernel_.mode != 0) {
      thread_local detail::ChargeGroup group;
      group.count = n;
      for (std::size_t k = 0; k < detail::kChargeGroup; ++k) {
        const Vec3& q = p[k < n ? k : 0];
        group.px[k] = q.x();
        group.py[k] = q.y();
        group.pz[k] = q.z();
      }
      const detail::ChargeKernel kn{kernel_.mode, kernel_.h2, theta2_};
      detail::charge_group_evaluate(kn, nodes_.data(), pos_.data(), val_.data(), actions.data(),
                                    actions.size(), group, g != nullptr);
      for (std::size_t k = 0; k < n; ++k) {
        f[k] = group.f[k];
        if (g != nullptr) g[k] = Vec3(group.gx[k], group.gy[k], group.gz[k]);
      }
      return;
    }
    const bool wg = g != nullptr;
    Vec3 unused = Vec3::Zero();
    std::array<std::uint32_t, kGroup> skip{};
    for (std::uint32_t a = 0; a < actions.size(); ++a) {
      const Action act = actions[a];
      const Node& c = nodes_[act.node];
      for (std::size_t k = 0; k < n; ++k) {
        if (a < skip[k]) continue;
        Vec3& gk = wg ? g[k] : unused;
        const Vec3 d = p[k] - c.centroid;
        const double d2 = squared_norm(d);
        const bool far =
            act.kind == Action::kFar || (act.kind != Action::kOpen && c.rho2 < theta2_ * d2);
        if (far) {
          add_cluster(c, d, d2, f[k], gk, wg);
          if (act.kind == Action::kSplit) skip[k] = act.end;
        } else if (c.right == kNone) {
          add_leaf(c, p[k], f[k], gk, wg);
        }
      }
    }
  }

  // Conservative range of the potential over the box.
  [[nodiscard]] Interval bound(const Aabb& box) const {
    Interval r{0.0, 0.0};
    if (nodes_.empty() || box.isEmpty()) return r;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& c = nodes_[stack[--top]];
      if (!(c.q > 0)) continue;
      const double dmin2 = squared_distance(c.box, box);
      const double size2 = c.box.diagonal().squaredNorm();
      if (c.right == kNone && c.count > 1 && !(size2 < kBoundTheta * kBoundTheta * dmin2)) {
        for (std::uint32_t i = c.first; i < c.first + c.count; ++i) {
          const double lo2 = squared_distance(box, pos_[i]);
          const double hi = max_distance(box, pos_[i]);
          r.lo += val_[i] * kernel_.w(hi * hi + kernel_.h2);
          r.hi += val_[i] * kernel_.w(lo2 + kernel_.h2);
        }
      } else if (c.right == kNone || size2 < kBoundTheta * kBoundTheta * dmin2) {
        r.lo += c.q * kernel_.w(max_squared_distance(c.box, box) + kernel_.h2);
        r.hi += c.q * kernel_.w(dmin2 + kernel_.h2);
      } else {
        stack[top++] = c.right;
        stack[top++] = c.first;
      }
    }
    // Rounding: the sums above are of positive terms; widen by a few ulps of the total.
    r.lo = std::max(0.0, r.lo * (1.0 - 1e-12));
    r.hi = r.hi * (1.0 + 1e-12);
    return r;
  }

  // Charges (original indices) within distance `radius` of p, appended to out.
  void near(const Vec3& p, double radius, std::vector<std::uint32_t>& out) const {
    if (nodes_.empty()) return;
    const double r2 = radius * radius;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& c = nodes_[stack[--top]];
      if (squared_distance(c.box, p) > r2) continue;
      if (c.right == kNone) {
        for (std::uint32_t i = c.first; i < c.first + c.count; ++i) {
          if ((pos_[i] - p).squaredNorm() <= r2) out.push_back(order_[i]);
        }
      } else {
        stack[top++] = c.right;
        stack[top++] = c.first;
      }
    }
  }

 private:
  using Node = detail::ChargeNode;
  using Action = detail::ChargeAction;

  // The actions of the subtree at `id` for the points in `box`, in eval()'s order (left child
  // first). The box decides only with a margin of 1e-9 over rounding in either direction.
  void collect(std::uint32_t id, const Aabb& box, std::vector<Action>& out) const {
    const Node& c = nodes_[id];
    if (!(c.q > 0)) return;
    const double near2 = squared_distance(box, c.centroid);
    const double far = max_distance(box, c.centroid);
    if (c.rho2 < theta2_ * near2 * (1.0 - 1e-9)) {
      out.push_back({id, 0, Action::kFar});
      return;
    }
    const bool open = c.rho2 >= theta2_ * far * far * (1.0 + 1e-9);
    if (c.right == kNone) {
      out.push_back({id, 0, open ? Action::kOpen : Action::kSplit});
      return;
    }
    const auto at = static_cast<std::uint32_t>(out.size());
    if (!open) out.push_back({id, 0, Action::kSplit});
    collect(c.first, box, out);
    collect(c.right, box, out);
    if (!open) out[at].end = static_cast<std::uint32_t>(out.size());
  }

  static double max_squared_distance(const Aabb& a, const Aabb& b) {
    const Vec3 d = (a.max() - b.min()).cwiseAbs().cwiseMax((b.max() - a.min()).cwiseAbs());
    return d.squaredNorm();
  }

  // (dx dx + dy dy) + dz dz: the order the SIMD lanes use (field/equipotential_simd.cpp).
  static double squared_norm(const Vec3& d) {
    return d.x() * d.x() + d.y() * d.y() + d.z() * d.z();
  }

  // A far cluster: its monopole plus quadrupole (the dipole vanishes about the charge-weighted
  // centroid). With k = alpha - 1, w = s^(-k/2) and u = 1/s, the quadrupole term of
  // sum q w(|d - x|) is k w u ((k + 2) d.M.d u - tr M) / 2 and its gradient
  // k (k + 2) w u^2 (2 M d - (k + 4) d.M.d u d + tr M d) / 2. Every operation in the order of
  // field/equipotential_simd.cpp.
  void add_cluster(const Node& c, const Vec3& d, double d2, double& f, Vec3& g,
                   bool with_grad) const {
    const double s = d2 + kernel_.h2;
    const double u = 1.0 / s;
    const double w = kernel_.w_of_u(u, s);
    const double k = kernel_.alpha - 1.0;
    const double* m = c.m;
    const double mdx = m[0] * d.x() + m[1] * d.y() + m[2] * d.z();
    const double mdy = m[1] * d.x() + m[3] * d.y() + m[4] * d.z();
    const double mdz = m[2] * d.x() + m[4] * d.y() + m[5] * d.z();
    const double dmd = d.x() * mdx + d.y() * mdy + d.z() * mdz;
    const double tr = c.trace;
    f = f + (c.q * w + (0.5 * k) * w * u * ((k + 2.0) * dmd * u - tr));
    if (with_grad) {
      const double a = c.q * (-k * w * u);
      const double b = (0.5 * k * (k + 2.0)) * w * u * u;
      const double e = tr - (k + 4.0) * dmd * u;
      g.x() = g.x() + (a * d.x() + b * (2.0 * mdx + e * d.x()));
      g.y() = g.y() + (a * d.y() + b * (2.0 * mdy + e * d.y()));
      g.z() = g.z() + (a * d.z() + b * (2.0 * mdz + e * d.z()));
    }
  }

  void add(double q, const Vec3& d, double d2, double& f, Vec3& g, bool with_grad) const {
    const double s = d2 + kernel_.h2;
    const double u = 1.0 / s;
    const double w = kernel_.w_of_u(u, s);
    f = f + q * w;
    if (with_grad) {
      const double t = q * (-(kernel_.alpha - 1.0) * w * u);
      g.x() = g.x() + t * d.x();
      g.y() = g.y() + t * d.y();
      g.z() = g.z() + t * d.z();
    }
  }

  // Every charge of the leaf c, summed exactly.
  void add_leaf(const Node& c, const Vec3& p, double& f, Vec3& g, bool with_grad) const {
    for (std::uint32_t i = c.first; i < c.first + c.count; ++i) {
      const Vec3 di = p - pos_[i];
      add(val_[i], di, squared_norm(di), f, g, with_grad);
    }
  }

  std::uint32_t build(std::span<const Vec3> positions, std::uint32_t begin, std::uint32_t end) {
    const auto id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    Aabb box;
    for (std::uint32_t i = begin; i < end; ++i) box.extend(positions[order_[i]]);
    nodes_[id].box = box;
    if (end - begin <= kLeafSize) {
      nodes_[id].first = begin;
      nodes_[id].count = end - begin;
      return id;
    }
    int axis = 0;
    box.diagonal().maxCoeff(&axis);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double pa = positions[a][axis], pb = positions[b][axis];
                       return pa < pb || (pa == pb && a < b);
                     });
    const std::uint32_t left = build(positions, begin, mid);
    const std::uint32_t right = build(positions, mid, end);
    nodes_[id].first = left;
    nodes_[id].right = right;
    return id;
  }

  // Charge-weighted centroid, total and radius of every cluster (after pos_/val_ are sorted).
  void summarize(std::uint32_t id) {
    Node& c = nodes_[id];
    std::uint32_t lo = 0, hi = 0;
    if (c.right == kNone) {
      lo = c.first;
      hi = c.first + c.count;
    } else {
      summarize(c.first);
      summarize(c.right);
      lo = leaf_begin(c.first);
      hi = leaf_end(c.right);
    }
    double q = 0.0;
    Vec3 m = Vec3::Zero(), plain = Vec3::Zero();
    for (std::uint32_t i = lo; i < hi; ++i) {
      q += val_[i];
      m += val_[i] * pos_[i];
      plain += pos_[i];
    }
    c.q = q;
    c.centroid = q > 0 ? Vec3(m / q) : Vec3(plain / static_cast<double>(hi - lo));
    double rho2 = 0.0;
    std::array<double, 6> mom{};
    for (std::uint32_t i = lo; i < hi; ++i) {
      const Vec3 x = pos_[i] - c.centroid;
      rho2 = std::max(rho2, x.squaredNorm());
      const double q_i = val_[i];
      mom[0] += q_i * x.x() * x.x();
      mom[1] += q_i * x.x() * x.y();
      mom[2] += q_i * x.x() * x.z();
      mom[3] += q_i * x.y() * x.y();
      mom[4] += q_i * x.y() * x.z();
      mom[5] += q_i * x.z() * x.z();
    }
    c.rho2 = rho2;
    std::copy(mom.begin(), mom.end(), c.m);
    c.trace = mom[0] + mom[3] + mom[5];
  }
  [[nodiscard]] std::uint32_t leaf_begin(std::uint32_t id) const {
    while (nodes_[id].right != kNone) id = nodes_[id].first;
    return nodes_[id].first;
  }
  [[nodiscard]] std::uint32_t leaf_end(std::uint32_t id) const {
    while (nodes_[id].right != kNone) id = nodes_[id].right;
    return nodes_[id].first + nodes_[id].count;
  }

  double theta2_;
  double extent_ = 0.0;
  PowerKernel kernel_;
  Aabb box_;
  std::vector<std::uint32_t> order_;  // sorted position -> original charge index
  std::vector<Vec3> pos_;
  std::vector<double> val_;
  std::vector<Node> nodes_;
};

void check_charges(const ChargeSet& c) {
  const std::size_t n = c.positions.size();
  if (n == 0) throw InvalidArgument("equipotential field: no charges");
  if (c.values.size() != n) {
    throw InvalidArgument("equipotential field: " + std::to_string(c.values.size()) +
                          " charge values for " + std::to_string(n) + " charges");
  }
  require(std::isfinite(c.alpha) && c.alpha >= 2.0 && c.alpha <= 16.0, "alpha", c.alpha,
          "in [2, 16]");
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!c.positions[i].allFinite()) {
      throw InvalidArgument("equipotential field: charge " + std::to_string(i) +
                            " has a non-finite position");
    }
    if (!std::isfinite(c.values[i]) || c.values[i] < 0) {
      throw InvalidArgument("equipotential field: charge " + std::to_string(i) + " has value " +
                            fmt(c.values[i]) + " (must be finite and >= 0)");
    }
    total += c.values[i];
  }
  if (!(total > 0) || !std::isfinite(total)) {
    throw InvalidArgument("equipotential field: the charges sum to " + fmt(total) +
                          " (must be finite and > 0)");
  }
}

class EquipotentialField final : public Field {
 public:
  EquipotentialField(const ChargeSet& charges, double lambda, double theta)
      : Field(lambda),
        tree_(charges.positions, charges.values, charges.alpha, theta),
        alpha_(charges.alpha),
        theta_(theta) {}

  [[nodiscard]] Interval bound(const Aabb& box) const override { return tree_.bound(box); }

  [[nodiscard]] Aabb bounds() const override {
    std::call_once(bounds_once_, [&] { bounds_ = compute_bounds(); });
    return bounds_;
  }

  [[nodiscard]] std::string describe() const override {
    std::ostringstream o;
    o << "equipotential surface, " << tree_.size() << " charges, alpha " << alpha_ << ", lambda "
      << iso() << ", treecode theta " << theta_;
    return o.str();
  }

 protected:
  // Groups of kGroup consecutive points share one traversal (ChargeTree::eval_group: the same
  // values as one point at a time); the groups, like the parallel chunks, do not depend on the
  // thread count.
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    Vec3* g = gradients.empty() ? nullptr : gradients.data();
    auto body = [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; i += kGroup) {
        tree_.eval_group(points.data() + i, std::min(kGroup, e - i), values.data() + i,
                         g == nullptr ? nullptr : g + i);
      }
    };
    if (points.size() >= 4 * detail::kPointwiseGrain) {
      parallel::for_chunks(points.size(), detail::kPointwiseGrain, body, ctx);
    } else {
      body(0, points.size());
    }
  }

 private:
  // f > lambda needs a point within (Q / lambda)^(1 / (alpha - 1)) of the charges' box; the
  // box of the cells of an octree over that region whose bound reaches above lambda.
  [[nodiscard]] Aabb compute_bounds() const {
    const double lambda = iso();
    const double reach = std::pow(tree_.total() / lambda, 1.0 / (alpha_ - 1.0));
    Aabb root = tree_.box();
    root.min().array() -= reach;
    root.max().array() += reach;
    std::vector<Aabb> cells{root}, next;
    if (!(tree_.bound(root).hi > lambda)) return Aabb();
    for (int depth = 0; depth < kBoundsDepth && cells.size() <= kBoundsCells; ++depth) {
      next.clear();
      for (const Aabb& c : cells) {
        const Vec3 mid = c.center();
        for (int k = 0; k < 8; ++k) {
          Vec3 lo, hi;
          for (int a = 0; a < 3; ++a) {
            const bool up = ((k >> a) & 1) != 0;
            lo[a] = up ? mid[a] : c.min()[a];
            hi[a] = up ? c.max()[a] : mid[a];
          }
          const Aabb child(lo, hi);
          if (tree_.bound(child).hi > lambda) next.push_back(child);
        }
      }
      cells.swap(next);
    }
    Aabb out;
    for (const Aabb& c : cells) out.extend(c);
    return out;
  }

  ChargeTree tree_;
  double alpha_;
  double theta_;
  mutable std::once_flag bounds_once_;
  mutable Aabb bounds_;
};

void validate_options(const EquipotentialOptions& o, std::size_t edges) {
  require(std::isfinite(o.alpha) && o.alpha >= 2.0 && o.alpha <= 16.0, "alpha", o.alpha,
          "in [2, 16]");
  require(std::isfinite(o.charge_spacing) && o.charge_spacing >= 0, "charge_spacing",
          o.charge_spacing, "finite and >= 0");
  require(std::isfinite(o.spacing_factor) && o.spacing_factor > 0, "spacing_factor",
          o.spacing_factor, "finite and > 0");
  require(std::isfinite(o.charge) && o.charge >= 0, "charge", o.charge, "finite and >= 0");
  require(std::isfinite(o.lambda) && o.lambda >= 0, "lambda", o.lambda, "finite and >= 0");
  require(std::isfinite(o.lambda_scale) && o.lambda_scale > 0, "lambda_scale", o.lambda_scale,
          "finite and > 0");
  require(std::isfinite(o.extension) && o.extension > 0 && o.extension <= 1000, "extension",
          o.extension, "in (0, 1000]");
  require(std::isfinite(o.theta) && o.theta >= 0 && o.theta <= 0.6, "theta", o.theta,
          "in [0, 0.6]");
  if (!o.edge_charges.empty()) {
    if (o.edge_charges.size() != edges) {
      throw InvalidArgument("edge_charges: " + std::to_string(o.edge_charges.size()) +
                            " values for " + std::to_string(edges) + " edges");
    }
    for (std::size_t e = 0; e < edges; ++e) {
      require(std::isfinite(o.edge_charges[e]) && o.edge_charges[e] > 0,
              "edge_charges[" + std::to_string(e) + "]", o.edge_charges[e], "finite and > 0");
    }
  }
}

// Unit vectors perpendicular to u (any u != 0).
void frame(const Vec3& u, Vec3& e1, Vec3& e2) {
  const Vec3 t = std::abs(u.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = u.cross(t).normalized();
  e2 = u.cross(e1).normalized();
}

// Raises the charge of every closed leaf (degree 1, not open) so that the mean potential of four
// points at the leaf's radius around it, perpendicular to its edge, is lambda: the missing
// potential times r^(alpha - 1) is added at the leaf (exact at those points).
void compensate_tips(ChargeSet& c, const Skeleton& skeleton, double lambda, double theta) {
  const std::size_t nn = skeleton.node_count();
  std::vector<std::uint32_t> leaves;
  for (std::size_t n = 0; n < nn; ++n) {
    if (c.node_edge_offset[n + 1] - c.node_edge_offset[n] == 1 && c.open[n] == 0)
      leaves.push_back(static_cast<std::uint32_t>(n));
  }
  if (leaves.empty()) return;
  const ChargeTree tree(c.positions, c.values, c.alpha, theta);
  std::vector<double> factor(leaves.size(), 1.0);
  parallel::for_each(leaves.size(), 64, [&](std::size_t k) {
    const std::uint32_t n = leaves[k];
    const std::uint32_t e = c.node_edges[c.node_edge_offset[n]];
    const std::uint32_t other =
        skeleton.edges[e][0] == n ? skeleton.edges[e][1] : skeleton.edges[e][0];
    const Vec3& p = skeleton.nodes[n].position;
    Vec3 e1, e2;
    frame((p - skeleton.nodes[other].position).normalized(), e1, e2);
    const double r = skeleton.nodes[n].radius;
    double f = 0.0;
    for (const Vec3& d : {e1, e2, Vec3(-e1), Vec3(-e2)}) f += 0.25 * tree.eval(p + r * d, nullptr);
    const double missing = lambda - f;
    const double q = c.node_values[n];
    if (missing > 0 && q > 0) {
      factor[k] = std::min(kMaxTipFactor, 1.0 + missing * std::pow(r, c.alpha - 1.0) / q);
    }
  });
  for (std::size_t k = 0; k < leaves.size(); ++k) c.node_factor[leaves[k]] = factor[k];
  set_edge_charges(c, std::vector<double>(c.edge_values));
}

}  // namespace

double detail::charge_tree_value(const ChargeSet& charges, double theta, const Vec3& p,
                                 Vec3* gradient) {
  check_charges(charges);
  return ChargeTree(charges.positions, charges.values, charges.alpha, theta).eval(p, gradient);
}

std::size_t edge_charge_count(double length, double spacing) {
  if (!std::isfinite(spacing) || !(spacing > 0)) {
    throw InvalidArgument("edge_charge_count: spacing must be finite and > 0, got " + fmt(spacing));
  }
  if (!std::isfinite(length) || !(length >= 0)) {
    throw InvalidArgument("edge_charge_count: length must be finite and >= 0, got " + fmt(length));
  }
  const double count = std::ceil(length / spacing) - 1.0;
  if (count > static_cast<double>(kMaxEdgeCharges)) {
    throw InvalidArgument("edge_charge_count: an edge of length " + fmt(length) +
                          " at charge spacing " + fmt(spacing) + " needs more than 2^26 charges");
  }
  return count > 0 ? static_cast<std::size_t>(count) : 0;
}

ChargeSet place_charges(const Skeleton& skeleton, const EquipotentialOptions& options) {
  validate(skeleton);
  validate_options(options, skeleton.edge_count());
  const std::size_t nn = skeleton.node_count(), ne = skeleton.edge_count();
  ChargeSet c;
  c.alpha = options.alpha;
  const std::vector<std::uint32_t> deg = degrees(skeleton);
  c.node_edge_offset.assign(nn + 1, 0);
  for (std::size_t n = 0; n < nn; ++n) c.node_edge_offset[n + 1] = c.node_edge_offset[n] + deg[n];
  c.node_edges.resize(2 * ne);
  const bool tapered = options.taper && options.charge == 0 && options.edge_charges.empty();
  // The taper factor (r / r_e)^(alpha - 2) at radius r on edge e.
  auto taper = [&](std::size_t e, double r) {
    if (!tapered) return 1.0;
    const double re = 0.5 * (skeleton.nodes[skeleton.edges[e][0]].radius +
                             skeleton.nodes[skeleton.edges[e][1]].radius);
    return std::pow(r / re, options.alpha - 2.0);
  };
  c.node_edge_scale.resize(2 * ne);
  {
    std::vector<std::uint32_t> fill(c.node_edge_offset.begin(), c.node_edge_offset.end() - 1);
    for (std::size_t e = 0; e < ne; ++e) {
      for (const std::uint32_t n : skeleton.edges[e]) {
        c.node_edge_scale[fill[n]] = taper(e, skeleton.nodes[n].radius);
        c.node_edges[fill[n]++] = static_cast<std::uint32_t>(e);
      }
    }
  }
  c.node_factor.assign(nn, 1.0);
  c.open.assign(nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    const bool flagged = !skeleton.open_ends.empty() && skeleton.open_ends[n] != 0;
    if (deg[n] == 1 && (options.open_ends || flagged)) c.open[n] = 1;
  }
  // Per edge: spacing, charge count and value.
  c.edge_spacing.resize(ne);
  c.edge_values.resize(ne);
  std::vector<std::size_t> counts(ne);
  std::size_t total = nn;
  for (std::size_t e = 0; e < ne; ++e) {
    const SkeletonNode& a = skeleton.nodes[skeleton.edges[e][0]];
    const SkeletonNode& b = skeleton.nodes[skeleton.edges[e][1]];
    const double len = (b.position - a.position).norm();
    const double d = options.charge_spacing > 0
                         ? options.charge_spacing
                         : options.spacing_factor * std::min(a.radius, b.radius);
    c.edge_spacing[e] = d;
    counts[e] = edge_charge_count(len, d);
    total += counts[e];
    if (!options.edge_charges.empty()) {
      c.edge_values[e] = options.edge_charges[e];
    } else if (options.charge > 0) {
      c.edge_values[e] = options.charge;
    } else {
      const double r = 0.5 * (a.radius + b.radius);
      const double step = len / static_cast<double>(counts[e] + 1);
      c.edge_values[e] = step * std::pow(r, options.alpha - 2.0);
    }
    if (!std::isfinite(c.edge_values[e]) || !(c.edge_values[e] > 0)) {
      throw InvalidArgument("edge " + std::to_string(e) + ": its charge value " +
                            fmt(c.edge_values[e]) + " is not finite and > 0 (radius or length " +
                            "out of range for alpha " + fmt(options.alpha) + ")");
    }
  }
  std::vector<std::size_t> extension(nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    if (c.open[n] == 0) continue;
    const std::uint32_t e = c.node_edges[c.node_edge_offset[n]];
    const double reach = options.extension * skeleton.nodes[n].radius;
    extension[n] = static_cast<std::size_t>(std::ceil(reach / c.edge_spacing[e]));
    if (extension[n] > kMaxEdgeCharges) {
      throw InvalidArgument("node " + std::to_string(n) + ": its open end needs more than 2^26 " +
                            "extension charges (extension / charge spacing too large)");
    }
    total += extension[n];
  }
  if (total > kMaxCharges) {
    throw InvalidArgument("equipotential: " + std::to_string(total) +
                          " charges exceed the limit of 2^26 (raise charge_spacing)");
  }
  c.positions.reserve(total);
  c.values.reserve(total);
  c.scale.reserve(total);
  c.edge.reserve(total);
  c.node.reserve(total);
  // Node charges first, then each edge's inner charges, then the open ends' extensions.
  c.node_values.resize(nn);
  for (std::size_t n = 0; n < nn; ++n) {
    c.positions.push_back(skeleton.nodes[n].position);
    c.values.push_back(0.0);
    c.scale.push_back(1.0);
    c.edge.push_back(kNone);
    c.node.push_back(static_cast<std::uint32_t>(n));
  }
  for (std::size_t e = 0; e < ne; ++e) {
    const SkeletonNode& na = skeleton.nodes[skeleton.edges[e][0]];
    const SkeletonNode& nb = skeleton.nodes[skeleton.edges[e][1]];
    const Vec3& a = na.position;
    const Vec3& b = nb.position;
    for (std::size_t k = 1; k <= counts[e]; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(counts[e] + 1);
      c.positions.push_back(a + t * (b - a));
      c.values.push_back(0.0);
      c.scale.push_back(taper(e, na.radius + t * (nb.radius - na.radius)));
      c.edge.push_back(static_cast<std::uint32_t>(e));
      c.node.push_back(kNone);
    }
  }
  for (std::size_t n = 0; n < nn; ++n) {
    if (extension[n] == 0) continue;
    const std::uint32_t e = c.node_edges[c.node_edge_offset[n]];
    const std::uint32_t other =
        skeleton.edges[e][0] == n ? skeleton.edges[e][1] : skeleton.edges[e][0];
    const Vec3& p = skeleton.nodes[n].position;
    const Vec3 u = (p - skeleton.nodes[other].position).normalized();
    for (std::size_t k = 1; k <= extension[n]; ++k) {
      c.positions.push_back(p + (static_cast<double>(k) * c.edge_spacing[e]) * u);
      c.values.push_back(0.0);
      c.scale.push_back(taper(e, skeleton.nodes[n].radius));
      c.edge.push_back(e);
      c.node.push_back(static_cast<std::uint32_t>(n));
    }
  }
  // Isolated nodes: one charge that alone gives a sphere of the node's radius at the same
  // potential as a long edge of that radius (so lambda estimates agree); or `charge`.
  for (std::size_t n = 0; n < nn; ++n) {
    if (deg[n] != 0) continue;
    const double r = skeleton.nodes[n].radius;
    c.node_values[n] = options.charge > 0 ? options.charge : std::pow(r, options.alpha - 1.0);
  }
  set_edge_charges(c, c.edge_values);
  return c;
}

void set_edge_charges(ChargeSet& c, std::span<const double> edge_values) {
  const std::size_t ne = c.edge_spacing.size();
  if (edge_values.size() != ne) {
    throw InvalidArgument("set_edge_charges: " + std::to_string(edge_values.size()) +
                          " values for " + std::to_string(ne) + " edges");
  }
  for (std::size_t e = 0; e < ne; ++e) {
    require(std::isfinite(edge_values[e]) && edge_values[e] >= 0, "edge value " + std::to_string(e),
            edge_values[e], "finite and >= 0");
  }
  if (c.edge_values.data() != edge_values.data()) {
    c.edge_values.assign(edge_values.begin(), edge_values.end());
  }
  const std::size_t nn = c.node_values.size();
  for (std::size_t n = 0; n < nn; ++n) {
    const std::uint32_t b = c.node_edge_offset[n], e = c.node_edge_offset[n + 1];
    if (b == e) continue;  // isolated: keeps its own value
    double s = 0.0;
    for (std::uint32_t k = b; k < e; ++k)
      s += c.edge_values[c.node_edges[k]] * c.node_edge_scale[k];
    c.node_values[n] = c.node_factor[n] * s / static_cast<double>(e - b);
  }
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    c.values[i] =
        c.edge[i] != kNone ? c.edge_values[c.edge[i]] * c.scale[i] : c.node_values[c.node[i]];
  }
}

// eq. 2's test points deeper than this fraction of its radius inside another edge's tube are
// left out of lambda's mean (estimate_lambda()).
constexpr double kTestPointMargin = 0.01;

double estimate_lambda(const ChargeSet& charges, const Skeleton& skeleton,
                       std::span<const double> test_radius, double theta) {
  check_charges(charges);
  require(std::isfinite(theta) && theta >= 0 && theta <= 0.6, "theta", theta, "in [0, 0.6]");
  const std::size_t ne = skeleton.edge_count();
  if (test_radius.size() != ne) {
    throw InvalidArgument("estimate_lambda: " + std::to_string(test_radius.size()) +
                          " test radii for " + std::to_string(ne) + " edges");
  }
  std::vector<Vec3> tests;
  if (ne == 0) {
    // No edges: four points at each node's radius.
    for (const SkeletonNode& n : skeleton.nodes) {
      for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)})
        tests.push_back(n.position + n.radius * d);
    }
  }
  for (std::size_t e = 0; e < ne; ++e) {
    require(std::isfinite(test_radius[e]) && test_radius[e] > 0, "test radius " + std::to_string(e),
            test_radius[e], "finite and > 0");
    const Vec3& a = skeleton.nodes[skeleton.edges[e][0]].position;
    const Vec3& b = skeleton.nodes[skeleton.edges[e][1]].position;
    Vec3 e1, e2;
    frame((b - a).normalized(), e1, e2);
    const Vec3 m = 0.5 * (a + b);
    const double r = test_radius[e];
    tests.push_back(m + r * e1);
    tests.push_back(m + r * e2);
    tests.push_back(m - r * e1);
    tests.push_back(m - r * e2);
  }
  // A test point inside another edge's tube (nearer its axis than 0.99 of that edge's radius
  // there) is not on the surface eq. 2 assumes: near that axis its potential is far above the
  // tubes', and one such point decides the mean (segments crossing at their midpoints gave
  // lambda 1.4e21, near-parallel siblings 0.25-0.35 radii apart after a 13 degree fork 130-420
  // instead of about 2.5). Such points are left out (all of them kept if none would remain).
  std::vector<char> keep(tests.size(), 1);
  if (ne > 1) {
    const std::vector<detail::EdgeGeometry> geo = detail::edge_geometry(skeleton);
    const detail::TubeIndex tubes(geo);
    parallel::for_chunks(tests.size(), 256, [&](std::size_t begin, std::size_t end) {
      std::vector<std::uint32_t> ids;
      for (std::size_t i = begin; i < end; ++i) {
        const auto own = static_cast<std::uint32_t>(i / 4);
        if (tubes.inside_other(tests[i], own, ids, kTestPointMargin)) keep[i] = 0;
      }
    });
    if (std::find(keep.begin(), keep.end(), 1) == keep.end()) keep.assign(tests.size(), 1);
  }
  const ChargeTree tree(charges.positions, charges.values, charges.alpha, theta);
  std::vector<double> v(tests.size(), 0.0);
  parallel::for_each(tests.size(), 256, [&](std::size_t i) {
    if (keep[i] != 0) v[i] = tree.eval(tests[i], nullptr);
  });
  double s = 0.0;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {  // fixed order: the same on any thread count
    if (keep[i] == 0) continue;
    s += v[i];
    ++kept;
  }
  return s / static_cast<double>(kept);
}

FieldPtr make_equipotential_field(const ChargeSet& charges, double lambda, double theta) {
  check_charges(charges);
  require(std::isfinite(lambda) && lambda > 0, "lambda", lambda, "finite and > 0");
  require(std::isfinite(theta) && theta >= 0 && theta <= 0.6, "theta", theta, "in [0, 0.6]");
  return std::make_shared<EquipotentialField>(charges, lambda, theta);
}

Equipotential make_equipotential(const Skeleton& skeleton, const EquipotentialOptions& options) {
  Equipotential out;
  out.charges = place_charges(skeleton, options);
  double lambda = options.lambda;
  if (!(lambda > 0)) {
    const bool paper = options.charge > 0 || !options.edge_charges.empty();
    std::vector<double> radius(skeleton.edge_count());
    for (std::size_t e = 0; e < radius.size(); ++e) {
      radius[e] = paper ? out.charges.edge_values[e]
                        : 0.5 * (skeleton.nodes[skeleton.edges[e][0]].radius +
                                 skeleton.nodes[skeleton.edges[e][1]].radius);
    }
    lambda = estimate_lambda(out.charges, skeleton, radius, options.theta);
    if (!paper && options.taper) compensate_tips(out.charges, skeleton, lambda, options.theta);
  }
  out.lambda = lambda * options.lambda_scale;
  out.field = make_equipotential_field(out.charges, out.lambda, options.theta);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Charge fit.

ChargeFitResult fit_charges(const ChargeSet& charges, const Skeleton& skeleton, double lambda,
                            const ChargeFitOptions& options, double theta, Context* ctx) {
  check_charges(charges);
  require(std::isfinite(lambda) && lambda > 0, "lambda", lambda, "finite and > 0");
  require(std::isfinite(theta) && theta >= 0 && theta <= 0.6, "theta", theta, "in [0, 0.6]");
  detail::check_at_least(options.stations_per_edge, 1, "stations_per_edge");
  detail::check_at_least(options.directions, 3, "directions");
  detail::check_at_least(options.max_sweeps, 1, "max_sweeps");
  require(std::isfinite(options.tolerance) && options.tolerance > 0, "tolerance", options.tolerance,
          "finite and > 0");
  require(options.floor >= 0 && options.floor < 1, "floor", options.floor, "in [0, 1)");
  const std::size_t ne = skeleton.edge_count();
  if (charges.edge_spacing.size() != ne) {
    throw InvalidArgument("fit_charges: the charges were placed for " +
                          std::to_string(charges.edge_spacing.size()) +
                          " edges, the skeleton has " + std::to_string(ne));
  }
  ChargeFitResult result;
  result.edge_values = charges.edge_values;
  if (ne == 0) return result;

  // Samples on the requested tubes, outside every other edge's tube.
  const std::vector<detail::EdgeGeometry> geo = detail::edge_geometry(skeleton);
  const detail::TubeIndex tubes(geo);
  const int ns = options.stations_per_edge, nd = options.directions;
  std::vector<std::uint8_t> fork(skeleton.node_count(), 0);
  for (std::size_t n = 0; n < skeleton.node_count(); ++n)
    fork[n] = charges.node_edge_offset[n + 1] - charges.node_edge_offset[n] >= 3 ? 1 : 0;
  const std::size_t per_edge = static_cast<std::size_t>(ns) * static_cast<std::size_t>(nd);
  std::vector<Vec3> cand(ne * per_edge);
  std::vector<std::uint8_t> keep(cand.size(), 0);
  std::vector<double> cand_r(cand.size());
  parallel::for_chunks(
      ne, 16,
      [&](std::size_t b, std::size_t e_end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t e = b; e < e_end; ++e) {
          const detail::EdgeGeometry& g = geo[e];
          for (int k = 0; k < ns; ++k) {
            const double t = (k + 0.5) / ns;
            const Vec3 axis = g.a + (t * g.len) * g.u;
            const double r = g.ra + t * (g.rb - g.ra);
            // Stations in a fork's blend (within kForkGap radii of a node with three or more
            // edges) are not fitted: there the blend is meant to be wider than either tube.
            const bool in_blend = (fork[skeleton.edges[e][0]] && t * g.len < kForkGap * g.ra) ||
                                  (fork[skeleton.edges[e][1]] && (1 - t) * g.len < kForkGap * g.rb);
            for (int j = 0; j < nd; ++j) {
              const double phi = 2.0 * M_PI * (j + 0.5 * (k % 2)) / nd;
              const std::size_t s = e * per_edge + static_cast<std::size_t>(k * nd + j);
              cand[s] = axis + r * (std::cos(phi) * g.e1 + std::sin(phi) * g.e2);
              cand_r[s] = r;
              keep[s] =
                  !in_blend && !tubes.inside_other(cand[s], static_cast<std::uint32_t>(e), ids) ? 1
                                                                                                : 0;
            }
          }
        }
      },
      ctx);
  std::vector<Vec3> pts;
  std::vector<double> pr;
  std::vector<std::uint32_t> owner;
  for (std::size_t s = 0; s < cand.size(); ++s) {
    if (keep[s] == 0) continue;
    pts.push_back(cand[s]);
    pr.push_back(cand_r[s]);
    owner.push_back(static_cast<std::uint32_t>(s / per_edge));
  }
  result.samples = pts.size();
  if (pts.empty()) return result;

  // Near-field columns: each sample's exact coefficient for the edges whose charges lie within
  // kNear requested radii (at least three charge spacings) of it. A charge of edge e adds w to
  // column e; a node charge adds w / degree to each of its edges; isolated nodes are constant.
  constexpr double kNear = 8.0;
  const ChargeTree geometry(charges.positions, std::vector<double>(charges.positions.size(), 1.0),
                            charges.alpha, 0.0);
  const PowerKernel& kern = geometry.kernel();
  struct Entry {
    std::uint32_t edge;
    double a;
  };
  const std::size_t np = pts.size();
  std::vector<std::vector<Entry>> rows(np);
  double max_spacing = 0.0;
  for (const double d : charges.edge_spacing) max_spacing = std::max(max_spacing, d);
  parallel::for_chunks(
      np, 64,
      [&](std::size_t b, std::size_t e_end) {
        std::vector<std::uint32_t> near;
        for (std::size_t s = b; s < e_end; ++s) {
          near.clear();
          const double radius = std::max(kNear * pr[s], 3.0 * charges.edge_spacing[owner[s]]);
          geometry.near(pts[s], radius, near);
          std::sort(near.begin(), near.end());
          std::vector<Entry>& row = rows[s];
          for (const std::uint32_t i : near) {
            const double w = kern.w((pts[s] - charges.positions[i]).squaredNorm() + kern.h2);
            if (charges.edge[i] != kNone) {
              row.push_back({charges.edge[i], w * charges.scale[i]});
            } else {
              const std::uint32_t n = charges.node[i];
              const std::uint32_t b0 = charges.node_edge_offset[n],
                                  b1 = charges.node_edge_offset[n + 1];
              for (std::uint32_t k = b0; k < b1; ++k) {
                row.push_back({charges.node_edges[k], w * charges.node_factor[n] *
                                                          charges.node_edge_scale[k] /
                                                          static_cast<double>(b1 - b0)});
              }
            }
          }
          // Merge duplicate columns (sorted by edge, fixed order).
          std::stable_sort(row.begin(), row.end(),
                           [](const Entry& x, const Entry& y) { return x.edge < y.edge; });
          std::size_t out = 0;
          for (std::size_t k = 0; k < row.size(); ++k) {
            if (out > 0 && row[out - 1].edge == row[k].edge) {
              row[out - 1].a += row[k].a;
            } else {
              row[out++] = row[k];
            }
          }
          row.resize(out);
        }
      },
      ctx);
  (void)max_spacing;
  // Columns: per edge, (sample, coefficient), for the coordinate steps.
  std::vector<std::vector<std::pair<std::uint32_t, double>>> cols(ne);
  for (std::size_t s = 0; s < np; ++s) {
    for (const Entry& en : rows[s]) cols[en.edge].push_back({static_cast<std::uint32_t>(s), en.a});
  }

  std::vector<double> q(charges.edge_values.begin(), charges.edge_values.end());
  std::vector<double> lower(ne);
  for (std::size_t e = 0; e < ne; ++e) lower[e] = options.floor * q[e];
  ChargeSet work = charges;
  std::vector<double> near_f(np), far_f(np), total_f(np);
  auto near_value = [&](std::size_t s) {
    double v = 0.0;
    for (const Entry& en : rows[s]) v += en.a * q[en.edge];
    return v;
  };
  auto full_field = [&](std::vector<double>& out) {
    set_edge_charges(work, q);
    const ChargeTree tree(work.positions, work.values, work.alpha, theta);
    parallel::for_each(
        np, 256, [&](std::size_t s) { out[s] = tree.eval(pts[s], nullptr); }, ctx);
  };
  constexpr int kMaxRounds = 30;
  double previous = std::numeric_limits<double>::infinity();
  for (int round = 0; round < kMaxRounds; ++round) {
    ++result.rounds;
    full_field(total_f);
    for (std::size_t s = 0; s < np; ++s) far_f[s] = total_f[s] - near_value(s);
    // residual r_s = near(q) + far - lambda, relative to lambda.
    std::vector<double> res(np);
    for (std::size_t s = 0; s < np; ++s) res[s] = near_value(s) + far_f[s] - lambda;
    // Huber weights from this round's residuals: a sample farther than kHuber * lambda from
    // lambda (a fork's crotch, where the blend is wider than either tube by design) pulls
    // linearly, not quadratically, so it cannot shrink its whole edge.
    std::vector<double> wt(np);
    for (std::size_t s = 0; s < np; ++s) {
      const double r = std::abs(res[s]) / lambda;
      wt[s] = r <= kHuber ? 1.0 : kHuber / r;
    }
    std::vector<double> norm2(ne, 0.0);
    for (std::size_t e = 0; e < ne; ++e) {
      for (const auto& [s, a] : cols[e]) norm2[e] += wt[s] * a * a;
    }
    for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
      ++result.sweeps;
      double change = 0.0;
      for (std::size_t e = 0; e < ne; ++e) {
        if (!(norm2[e] > 0)) continue;
        double dot = 0.0;
        for (const auto& [s, a] : cols[e]) dot += wt[s] * a * res[s];
        const double nq = std::max(lower[e], q[e] - dot / norm2[e]);
        const double dq = nq - q[e];
        if (dq == 0.0) continue;
        for (const auto& [s, a] : cols[e]) res[s] += a * dq;
        change = std::max(change, std::abs(dq) / std::max(std::abs(nq), 1e-300));
        q[e] = nq;
      }
      if (change < 0.1 * options.tolerance) break;
    }
    full_field(total_f);
    double mx = 0.0, ss = 0.0;
    for (std::size_t s = 0; s < np; ++s) {
      const double r = total_f[s] / lambda - 1.0;
      mx = std::max(mx, std::abs(r));
      ss += r * r;
    }
    result.residual_max = mx;
    result.residual_rms = std::sqrt(ss / static_cast<double>(np));
    if (std::abs(previous - mx) < options.tolerance) break;
    previous = mx;
  }
  // Edges without samples of their own keep their starting value unless their charges reach
  // other edges' samples; none falls below the floor (see ChargeFitOptions::floor).
  result.active = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    if (q[e] <= lower[e]) ++result.active;
  }
  result.edge_values = q;
  return result;
}

}  // namespace ramiform
