// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Geodesic level-set skeletons of tree point clouds (Xu, Gossett & Chen 2007, §3; AdTree, Du et
// al. 2019, §2.1). The steps are described in include/ramiform/skeleton/from_points.h.

#include "ramiform/skeleton/from_points.h"

#include <Eigen/QR>
#include <nanoflann.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A k-d tree over the cloud; neighbour lists sorted by (distance, index).
class Kd {
 public:
  explicit Kd(std::span<const Vec3> points)
      : cloud_{points}, tree_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree_.buildIndex();
  }
  void nearest(const Vec3& q, std::size_t k,
               std::vector<std::pair<std::uint32_t, double>>& out) const {
    k = std::min(k, cloud_.points.size());
    std::vector<std::uint32_t> index(k);
    std::vector<double> d2(k);
    const std::size_t found = tree_.knnSearch(q.data(), k, index.data(), d2.data());
    out.resize(found);
    for (std::size_t i = 0; i < found; ++i) out[i] = {index[i], d2[i]};
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
  }

 private:
  struct Cloud {
    std::span<const Vec3> points;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return points.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const {
      return points[i][static_cast<Eigen::Index>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box& /*box*/) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                   Cloud, 3, std::uint32_t>;
  Cloud cloud_;
  Tree tree_;
};

// Union-find; the representative is the smallest index of a set.
struct Dsu {
  std::vector<std::uint32_t> up;
  explicit Dsu(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), 0U); }
  std::uint32_t find(std::uint32_t a) {
    while (up[a] != a) {
      up[a] = up[up[a]];
      a = up[a];
    }
    return a;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (a < b) std::swap(a, b);
    up[a] = b;
    return true;
  }
};

// Labels 0..count-1 of the sets of `dsu`, in order of each set's smallest index.
std::uint32_t labels(Dsu& dsu, std::vector<std::uint32_t>& label) {
  const std::size_t n = dsu.up.size();
  label.assign(n, 0);
  std::vector<std::uint32_t> of_root(n, std::numeric_limits<std::uint32_t>::max());
  std::uint32_t count = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t r = dsu.find(i);
    if (of_root[r] == std::numeric_limits<std::uint32_t>::max()) of_root[r] = count++;
    label[i] = of_root[r];
  }
  return count;
}

double median_of(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) {
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  }
  return m;
}

void check_options(const TreeFromPointsOptions& o) {
  if (o.up_axis != 1 && o.up_axis != 2) {
    throw InvalidArgument("tree_from_points: up must be y or z (axis 1 or 2), got axis " +
                          std::to_string(o.up_axis));
  }
  if (!std::isfinite(o.bin_width) || o.bin_width < 0.0) {
    throw InvalidArgument("tree_from_points: bin width must be finite and >= 0 (0: automatic)");
  }
  if (!std::isfinite(o.bin_spacings) || o.bin_spacings <= 0.0 || o.bin_spacings > 1000.0) {
    throw InvalidArgument("tree_from_points: bin_spacings must be in (0, 1000]");
  }
  if (o.neighbours < 1 || o.neighbours > 64) {
    throw InvalidArgument("tree_from_points: neighbours must be in [1, 64]");
  }
  if (!std::isfinite(o.neighbour_spacings) || o.neighbour_spacings <= 0.0 ||
      o.neighbour_spacings > 1000.0) {
    throw InvalidArgument("tree_from_points: neighbour_spacings must be in (0, 1000]");
  }
  if (!std::isfinite(o.min_radius) || o.min_radius < 0.0) {
    throw InvalidArgument("tree_from_points: min radius must be finite and >= 0 (0: automatic)");
  }
  if (!(o.pipe_exponent >= 1.0 && o.pipe_exponent <= 4.0)) {
    throw InvalidArgument("tree_from_points: pipe_exponent must be in [1, 4]");
  }
  if (!(o.straight_tolerance >= 0.0 && o.straight_tolerance <= 1.0)) {
    throw InvalidArgument("tree_from_points: straight_tolerance must be in [0, 1]");
  }
  if (o.min_branch_bins > 1000000 || o.min_branch_points > 1000000000) {
    throw InvalidArgument("tree_from_points: min_branch_points or min_branch_bins too large");
  }
}

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

}  // namespace

Skeleton tree_from_points(std::span<const Vec3> points, const TreeFromPointsOptions& options,
                          TreeFromPointsReport* report) {
  check_options(options);
  const std::size_t n = points.size();
  if (n < 10) {
    throw InvalidArgument("tree_from_points: need at least 10 points, got " + std::to_string(n));
  }
  if (n > std::size_t{1} << 30) {
    throw InvalidArgument("tree_from_points: more than 2^30 points");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) {
      throw InvalidArgument("tree_from_points: point " + std::to_string(i) + " is not finite");
    }
  }
  TreeFromPointsReport rep;
  rep.points = n;
  const auto t_graph = Clock::now();

  // 1. Neighbour graph.
  const Kd kd(points);
  const std::size_t k = options.neighbours + 1;  // the point itself comes first
  std::vector<std::uint32_t> knn(n * k, kNone);
  std::vector<double> knn_d(n * k, 0.0);
  std::vector<double> nearest(n, 0.0);
  {
    std::vector<std::pair<std::uint32_t, double>> out;
    for (std::size_t i = 0; i < n; ++i) {
      kd.nearest(points[i], k, out);
      double first = 0.0;
      for (std::size_t a = 0; a < out.size(); ++a) {
        knn[i * k + a] = out[a].first;
        knn_d[i * k + a] = std::sqrt(out[a].second);
        if (first == 0.0 && out[a].first != i) first = knn_d[i * k + a];
      }
      nearest[i] = first;
    }
  }
  {
    std::vector<double> positive;
    positive.reserve(n);
    for (double d : nearest) {
      if (d > 0.0) positive.push_back(d);
    }
    if (positive.empty()) throw InvalidArgument("tree_from_points: all points coincide");
    rep.median_spacing = median_of(positive);
  }
  const double spacing = rep.median_spacing;
  const double radius = options.neighbour_spacings * spacing;
  const double w = options.bin_width > 0.0 ? options.bin_width : options.bin_spacings * spacing;
  rep.bin_width = w;
  const double min_radius = options.min_radius > 0.0 ? options.min_radius : 0.5 * spacing;
  rep.min_radius = min_radius;

  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(n * options.neighbours);
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::size_t a = 0; a < k; ++a) {
      const std::uint32_t j = knn[i * k + a];
      if (j == kNone || j == i || knn_d[i * k + a] > radius) continue;
      edges.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  Dsu dsu(n);
  for (const auto& [a, b] : edges) dsu.unite(a, b);
  std::vector<std::uint32_t> part;
  std::uint32_t parts = labels(dsu, part);
  rep.graph_parts = parts;
  // Bridging (Borůvka's rule): every part but the largest finds its shortest pair to another
  // part; the pairs are added and the parts merge, until one is left.
  while (parts > 1) {
    std::vector<std::size_t> size(parts, 0);
    for (std::uint32_t p : part) ++size[p];
    const auto largest =
        static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
    struct Best {
      double d2 = std::numeric_limits<double>::infinity();
      std::uint32_t i = kNone, j = kNone;
    };
    std::vector<Best> best(parts);
    auto offer = [&](std::uint32_t c, double d2, std::uint32_t i, std::uint32_t j) {
      Best& b = best[c];
      const auto key = std::make_pair(std::min(i, j), std::max(i, j));
      if (d2 < b.d2 ||
          (d2 == b.d2 && key < std::make_pair(std::min(b.i, b.j), std::max(b.i, b.j)))) {
        b = {d2, i, j};
      }
    };
    std::vector<std::pair<std::uint32_t, double>> out;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t c = part[i];
      if (c == largest) continue;
      kd.nearest(points[i], std::min<std::size_t>(n, 48), out);
      for (const auto& [j, d2] : out) {
        if (part[j] != c) {
          offer(c, d2, i, j);
          break;
        }
      }
    }
    for (std::uint32_t c = 0; c < parts; ++c) {
      if (c == largest || best[c].i != kNone) continue;
      // No other part among the 48 nearest of any of its points: search all points.
      for (std::uint32_t i = 0; i < n; ++i) {
        if (part[i] != c) continue;
        for (std::uint32_t j = 0; j < n; ++j) {
          if (part[j] != c) offer(c, (points[i] - points[j]).squaredNorm(), i, j);
        }
      }
    }
    for (std::uint32_t c = 0; c < parts; ++c) {
      if (c == largest) continue;
      const Best& b = best[c];
      if (dsu.unite(b.i, b.j)) {
        edges.emplace_back(std::min(b.i, b.j), std::max(b.i, b.j));
        ++rep.bridges;
      }
    }
    parts = labels(dsu, part);
  }
  std::sort(edges.begin(), edges.end());
  rep.graph_edges = edges.size();
  // Adjacency (CSR), neighbours in index order.
  std::vector<std::uint32_t> first(n + 1, 0);
  for (const auto& [a, b] : edges) {
    ++first[a + 1];
    ++first[b + 1];
  }
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t> adj(first[n]);
  std::vector<double> adj_len(first[n]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (const auto& [a, b] : edges) {
      const double len = (points[a] - points[b]).norm();
      adj[fill[a]] = b;
      adj_len[fill[a]++] = len;
      adj[fill[b]] = a;
      adj_len[fill[b]++] = len;
    }
  }
  rep.seconds_graph = seconds_since(t_graph);
  const auto t_levels = Clock::now();

  // 2. Root region and geodesic distances.
  const int up = options.up_axis;
  std::uint32_t lowest = 0;
  for (std::uint32_t i = 1; i < n; ++i) {
    if (points[i][up] < points[lowest][up]) lowest = i;
  }
  const double h0 = points[lowest][up];
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> pred(n, kNone);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  {
    // The part of the graph within one bin width above the lowest point that holds it.
    std::vector<std::uint32_t> stack{lowest};
    std::vector<std::uint8_t> seen(n, 0);
    seen[lowest] = 1;
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      dist[i] = points[i][up] - h0;
      queue.emplace(dist[i], i);
      for (std::uint32_t e = first[i]; e < first[i + 1]; ++e) {
        const std::uint32_t j = adj[e];
        if (seen[j] == 0 && points[j][up] - h0 < w) {
          seen[j] = 1;
          stack.push_back(j);
        }
      }
    }
  }
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for (std::uint32_t e = first[i]; e < first[i + 1]; ++e) {
      const std::uint32_t j = adj[e];
      const double nd = d + adj_len[e];
      if (nd < dist[j] || (nd == dist[j] && pred[j] != kNone && i < pred[j])) {
        const bool improved = nd < dist[j];
        dist[j] = nd;
        pred[j] = i;
        if (improved) queue.emplace(nd, j);
      }
    }
  }
  rep.max_geodesic = *std::max_element(dist.begin(), dist.end());

  // 3. Level sets: parts of the graph restricted to each bin.
  std::vector<std::uint32_t> bin(n);
  for (std::size_t i = 0; i < n; ++i) {
    bin[i] = static_cast<std::uint32_t>(std::min(std::floor(dist[i] / w), 4.0e9));
  }
  rep.bins = static_cast<std::size_t>(*std::max_element(bin.begin(), bin.end())) + 1;
  Dsu level(n);
  for (const auto& [a, b] : edges) {
    if (bin[a] == bin[b]) level.unite(a, b);
  }
  std::vector<std::uint32_t> raw_label;
  const std::uint32_t raw_count = labels(level, raw_label);
  // Order the parts: the root's first, then by bin, then by smallest point index.
  std::vector<std::uint32_t> min_point(raw_count, kNone);
  std::vector<std::uint32_t> part_bin(raw_count, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t c = raw_label[i];
    if (min_point[c] == kNone) min_point[c] = i;
    part_bin[c] = bin[i];
  }
  std::vector<std::uint32_t> order(raw_count);
  std::iota(order.begin(), order.end(), 0U);
  const std::uint32_t root_raw = raw_label[lowest];
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if ((a == root_raw) != (b == root_raw)) return a == root_raw;
    if (part_bin[a] != part_bin[b]) return part_bin[a] < part_bin[b];
    return min_point[a] < min_point[b];
  });
  std::vector<std::uint32_t> rank(raw_count);
  for (std::uint32_t r = 0; r < raw_count; ++r) rank[order[r]] = r;
  const std::size_t m = raw_count;
  rep.raw_nodes = m;
  std::vector<std::uint32_t> node_of(n);
  for (std::size_t i = 0; i < n; ++i) node_of[i] = rank[raw_label[i]];

  // 4. Parents by the predecessors' votes.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> votes;  // (node, parent candidate)
  for (std::size_t i = 0; i < n; ++i) {
    if (pred[i] == kNone) continue;
    const std::uint32_t a = node_of[i];
    const std::uint32_t b = node_of[pred[i]];
    if (a != b) votes.emplace_back(a, b);
  }
  std::sort(votes.begin(), votes.end());
  std::vector<std::uint32_t> parent(m, 0);
  std::vector<std::size_t> parent_votes(m, 0);
  parent[0] = kNone;
  for (std::size_t s = 0; s < votes.size();) {
    std::size_t e = s;
    while (e < votes.size() && votes[e] == votes[s]) ++e;
    const auto [a, b] = votes[s];
    if (e - s > parent_votes[a]) {  // ties: the smaller candidate (seen first)
      parent_votes[a] = e - s;
      parent[a] = b;
    }
    s = e;
  }
  // Every parent precedes its child: the predecessor's distance is smaller, so its bin is not
  // larger, and a different part in the same bin would have been joined to it.

  // Node data.
  std::vector<Vec3> centroid(m, Vec3::Zero());
  std::vector<std::size_t> count(m, 0);
  std::vector<std::uint32_t> node_bin(m, 0);
  for (std::size_t i = 0; i < n; ++i) {
    centroid[node_of[i]] += points[i];
    ++count[node_of[i]];
    node_bin[node_of[i]] = bin[i];
  }
  for (std::size_t c = 0; c < m; ++c) centroid[c] /= static_cast<double>(count[c]);

  // 6a. Drop small side branches (before the radii, whose axes follow the children).
  std::vector<std::size_t> sub_points(count);
  std::vector<std::uint32_t> sub_bin(node_bin);
  for (std::size_t c = m; c-- > 1;) {
    sub_points[parent[c]] += sub_points[c];
    sub_bin[parent[c]] = std::max(sub_bin[parent[c]], sub_bin[c]);
  }
  std::vector<std::vector<std::uint32_t>> children(m);
  for (std::uint32_t c = 1; c < m; ++c) children[parent[c]].push_back(c);
  std::vector<std::uint8_t> removed(m, 0);
  for (std::uint32_t a = 0; a < m; ++a) {
    if (removed[a] != 0) {
      for (std::uint32_t c : children[a]) removed[c] = 1;
      continue;
    }
    if (children[a].size() < 2) continue;
    std::uint32_t main = children[a][0];
    for (std::uint32_t c : children[a]) {
      if (sub_points[c] > sub_points[main]) main = c;
    }
    for (std::uint32_t c : children[a]) {
      if (c == main) continue;
      if (sub_points[c] < options.min_branch_points ||
          sub_bin[c] - node_bin[a] < options.min_branch_bins) {
        removed[c] = 1;
        ++rep.dropped_branches;
      }
    }
  }
  // Compact.
  std::vector<std::uint32_t> new_index(m, kNone);
  std::vector<std::uint32_t> keep;
  for (std::uint32_t c = 0; c < m; ++c) {
    if (removed[c] == 0) {
      new_index[c] = static_cast<std::uint32_t>(keep.size());
      keep.push_back(c);
    }
  }
  rep.dropped_nodes = m - keep.size();
  const std::size_t q = keep.size();
  std::vector<std::uint32_t> par(q, kNone);
  std::vector<Vec3> pos(q);
  std::vector<std::vector<std::uint32_t>> kids(q);
  for (std::uint32_t a = 0; a < q; ++a) {
    pos[a] = centroid[keep[a]];
    if (a > 0) {
      par[a] = new_index[parent[keep[a]]];
      kids[par[a]].push_back(a);
    }
  }
  rep.seconds_levels = seconds_since(t_levels);
  const auto t_radii = Clock::now();

  // 5. Radii: median distance of a node's points to its local axis.
  std::vector<std::vector<std::uint32_t>> members(q);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = new_index[node_of[i]];
    if (a != kNone) members[a].push_back(i);
  }
  Vec3 up_dir = Vec3::Zero();
  up_dir[up] = 1.0;
  std::vector<double> raw(q, min_radius);
  std::vector<Vec3> centre(pos);  // the fitted axis points (the centroids where no fit)
  {
    std::vector<double> d;
    for (std::uint32_t a = 0; a < q; ++a) {
      Vec3 below = par[a] != kNone ? pos[par[a]] : pos[a];
      Vec3 above = pos[a];
      if (!kids[a].empty()) {
        above = Vec3::Zero();
        for (std::uint32_t c : kids[a]) above += pos[c];
        above /= static_cast<double>(kids[a].size());
      }
      Vec3 axis = above - below;
      axis = axis.norm() > 0.0 ? Vec3(axis.normalized()) : up_dir;
      d.clear();
      for (std::uint32_t i : members[a]) {
        const Vec3 v = points[i] - pos[a];
        d.push_back((v - v.dot(axis) * axis).norm());
      }
      const double r_median = median_of(d);
      raw[a] = std::max(r_median, min_radius);
      // A scanner sees a branch from one side: the points of a cross-section lie on an arc, their
      // centroid off the axis and their median distance to it short of the radius. A circle
      // fitted in the plane across the axis (the algebraic fit of Kåsa 1976, "A circle fitting
      // procedure and its error analysis", IEEE Trans. Instrum. Meas. 25(1)) finds the axis and
      // the radius of an arc; it is taken when it fits well (RMS residual below 20 % of its
      // radius), its radius is at most 2.5 times the median distance and its centre within
      // its radius of the centroid; a fork's two branches in one section fail the test.
      const std::size_t np = members[a].size();
      if (np >= 8 && r_median > 0.0) {
        const Vec3 u = axis.unitOrthogonal();
        const Vec3 v = axis.cross(u);
        Eigen::MatrixXd design(static_cast<Eigen::Index>(np), 3);
        Eigen::VectorXd rhs(static_cast<Eigen::Index>(np));
        std::vector<std::pair<double, double>> xy(np);
        for (std::size_t t = 0; t < np; ++t) {
          const Vec3 w0 = (points[members[a][t]] - pos[a]) / r_median;
          const double x = w0.dot(u), y = w0.dot(v);
          xy[t] = {x, y};
          const auto row = static_cast<Eigen::Index>(t);
          design(row, 0) = x;
          design(row, 1) = y;
          design(row, 2) = 1.0;
          rhs(row) = -(x * x + y * y);
        }
        const Eigen::Vector3d sol = design.colPivHouseholderQr().solve(rhs);
        const double cx = -0.5 * sol(0), cy = -0.5 * sol(1);
        const double r2 = cx * cx + cy * cy - sol(2);
        if (sol.allFinite() && r2 > 0.0) {
          const double rf = std::sqrt(r2);
          double ss = 0.0;
          for (const auto& [x, y] : xy) {
            const double e = std::hypot(x - cx, y - cy) - rf;
            ss += e * e;
          }
          const double rms = std::sqrt(ss / static_cast<double>(np));
          if (rms < 0.2 * rf && rf <= 2.5 && std::hypot(cx, cy) <= rf && rf >= 1.0) {
            raw[a] = std::max(rf * r_median, min_radius);
            centre[a] = pos[a] + r_median * (cx * u + cy * v);
          }
        }
      }
    }
  }
  for (std::uint32_t a = 0; a < q; ++a) pos[a] = centre[a];
  // The tree stands on its lowest points: the root node goes down to their height (the bin's
  // centroid is half a bin above it, and the surface closes over its end node).
  if (q > 1) pos[0][up] = std::min(pos[0][up], h0);
  // Median filter along branches (up to two nodes each way, not across forks).
  std::vector<double> smooth(q);
  {
    std::vector<double> window;
    for (std::uint32_t a = 0; a < q; ++a) {
      window.assign(1, raw[a]);
      std::uint32_t b = a;
      for (int s = 0; s < 2 && par[b] != kNone && kids[par[b]].size() == 1; ++s) {
        b = par[b];
        window.push_back(raw[b]);
      }
      b = a;
      for (int s = 0; s < 2 && kids[b].size() == 1; ++s) {
        b = kids[b][0];
        window.push_back(raw[b]);
      }
      smooth[a] = median_of(window);
    }
  }
  // From the root out: not larger than the parent; the pipe model bounds the children at forks.
  std::vector<double> r(q);
  r[0] = std::max(smooth[0], min_radius);
  const double e = options.pipe_exponent;
  for (std::uint32_t a = 0; a < q; ++a) {
    if (kids[a].empty()) continue;
    double sum = 0.0;
    for (std::uint32_t c : kids[a]) {
      r[c] = std::min(smooth[c], r[a]);
      sum += std::pow(r[c], e);
    }
    const double bound = std::pow(r[a], e);
    const double scale = kids[a].size() >= 2 && sum > bound ? std::pow(bound / sum, 1.0 / e) : 1.0;
    for (std::uint32_t c : kids[a]) r[c] = std::max(r[c] * scale, min_radius);
  }

  // 6b. Thin degree-2 chains.
  std::vector<std::uint8_t> gone(q, 0);
  double extent = 0.0;
  {
    Aabb box;
    for (const Vec3& p : pos) box.extend(p);
    extent = box.diagonal().norm();
  }
  const double tol = options.straight_tolerance;
  for (std::uint32_t a = 0; a < q; ++a) {
    if (a != 0 && kids[a].size() == 1) continue;  // chains start at the root, forks and tips
    for (std::uint32_t c0 : kids[a]) {
      std::vector<std::uint32_t> chain{a, c0};
      while (kids[chain.back()].size() == 1) chain.push_back(kids[chain.back()][0]);
      std::size_t i = 0;
      while (i + 1 < chain.size()) {
        std::size_t j = i + 1;
        while (tol > 0.0 && j + 1 < chain.size()) {
          const std::size_t cand = j + 1;
          const Vec3 s0 = pos[chain[i]];
          const Vec3 seg = pos[chain[cand]] - s0;
          const double len2 = seg.squaredNorm();
          bool ok = len2 > 0.0;
          for (std::size_t t = i + 1; ok && t < cand; ++t) {
            const std::uint32_t x = chain[t];
            const double u = std::clamp((pos[x] - s0).dot(seg) / len2, 0.0, 1.0);
            const double lerp = (1.0 - u) * r[chain[i]] + u * r[chain[cand]];
            ok = (pos[x] - (s0 + u * seg)).norm() <= tol * r[x] &&
                 std::abs(r[x] - lerp) <= tol * r[x];
          }
          if (!ok) break;
          j = cand;
        }
        for (std::size_t t = i + 1; t < j; ++t) gone[chain[t]] = 1;
        par[chain[j]] = chain[i];
        i = j;
      }
    }
  }
  // A node on top of its parent (duplicate points) would make a zero-length edge: drop it.
  for (std::uint32_t a = 1; a < q; ++a) {
    if (gone[a] != 0) continue;
    std::uint32_t p = par[a];
    while (gone[p] != 0) p = par[p];
    par[a] = p;
    if ((pos[a] - pos[p]).norm() <= 1e-9 * extent) {
      gone[a] = 1;
      for (std::uint32_t c : kids[a]) par[c] = p;
    }
  }
  Skeleton sk;
  std::vector<std::uint32_t> out_index(q, kNone);
  for (std::uint32_t a = 0; a < q; ++a) {
    if (gone[a] != 0) continue;
    out_index[a] = static_cast<std::uint32_t>(sk.nodes.size());
    sk.nodes.push_back({pos[a], r[a]});
    if (a > 0) {
      std::uint32_t p = par[a];
      while (gone[p] != 0) p = par[p];
      sk.edges.push_back({out_index[p], out_index[a]});
    }
  }
  rep.thinned_nodes = q - sk.nodes.size();
  rep.nodes = sk.nodes.size();
  std::vector<std::uint32_t> child_count(sk.nodes.size(), 0);
  for (const auto& ed : sk.edges) ++child_count[ed[0]];
  for (std::size_t a = 0; a < sk.nodes.size(); ++a) {
    if (a > 0 && child_count[a] == 0) ++rep.tips;
    if (child_count[a] >= 2) ++rep.forks;
  }
  rep.seconds_radii = seconds_since(t_radii);
  validate(sk, "tree_from_points");
  if (report != nullptr) *report = rep;
  return sk;
}

}  // namespace ramiform
