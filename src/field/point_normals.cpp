// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/point_normals.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <tuple>
#include <vector>

#include "field/point_kdtree.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

constexpr std::size_t kGrain = 256;

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

PointSet orient_normals(const PointSet& points, const NormalOptions& options, NormalReport* report,
                        const Context* ctx) {
  if (options.neighbours < 3 || options.neighbours > 256) {
    throw InvalidArgument("orient normals: neighbours must be in 3..256, got " +
                          std::to_string(options.neighbours));
  }
  const std::size_t n = points.positions.size();
  if (n < 3)
    throw InvalidArgument("orient normals: needs at least 3 points, got " + std::to_string(n));
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw InvalidArgument("orient normals: too many points (" + std::to_string(n) + ")");
  const bool given = points.has_normals();
  if (given && points.normals.size() != n) {
    throw InvalidArgument("orient normals: " + std::to_string(points.normals.size()) +
                          " normals for " + std::to_string(n) + " points (need 0 or one each)");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!points.positions[i].allFinite())
      throw InvalidArgument("orient normals: point " + std::to_string(i) +
                            " has a non-finite position");
    if (given && (!points.normals[i].allFinite() || !(points.normals[i].norm() > 0))) {
      throw InvalidArgument("orient normals: point " + std::to_string(i) +
                            " has a zero or non-finite normal");
    }
  }
  const auto k = std::min(static_cast<std::size_t>(options.neighbours), n - 1);
  const std::vector<Vec3>& pos = points.positions;
  const detail::PointKdTree tree(pos);

  // k nearest neighbours of every point, itself excluded (coincident points count as others).
  std::vector<std::uint32_t> knn(n * k);
  parallel::for_chunks(
      n, kGrain,
      [&](std::size_t b, std::size_t e) {
        std::vector<std::pair<std::uint32_t, double>> found;
        for (std::size_t i = b; i < e; ++i) {
          tree.nearest(pos[i], k + 1, found);
          std::size_t m = 0;
          for (const auto& [j, d2] : found) {
            if (j == i || m == k) continue;
            knn[i * k + m++] = j;
          }
          // If i was not among the k + 1 (more than k coincident points), drop the farthest.
        }
      },
      ctx);

  PointSet out;
  out.positions = pos;
  out.normals.resize(n);
  if (given) {
    for (std::size_t i = 0; i < n; ++i) out.normals[i] = points.normals[i].normalized();
  } else {
    parallel::for_chunks(
        n, kGrain,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) {
            Vec3 mean = pos[i];
            for (std::size_t m = 0; m < k; ++m) mean += pos[knn[i * k + m]];
            mean /= static_cast<double>(k + 1);
            Mat3 C = (pos[i] - mean) * (pos[i] - mean).transpose();
            for (std::size_t m = 0; m < k; ++m) {
              const Vec3 d = pos[knn[i * k + m]] - mean;
              C += d * d.transpose();
            }
            const Eigen::SelfAdjointEigenSolver<Mat3> eig(C);
            Vec3 v = eig.eigenvectors().col(0);
            if (!(v.norm() > 0) || !v.allFinite()) v = Vec3::UnitZ();
            out.normals[i] = v.normalized();
          }
        },
        ctx);
  }
  check_cancel(ctx);

  // The symmetric neighbour graph (adjacency lists, sorted, without duplicates).
  std::vector<std::vector<std::uint32_t>> adjacent(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t m = 0; m < k; ++m) {
      const std::uint32_t j = knn[i * k + m];
      adjacent[i].push_back(j);
      adjacent[j].push_back(static_cast<std::uint32_t>(i));
    }
  }
  for (auto& a : adjacent) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  // Components, each with its root: the largest x, ties by the lowest index.
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    for (const std::uint32_t j : adjacent[i]) {
      const std::uint32_t a = find_root(parent, static_cast<std::uint32_t>(i));
      const std::uint32_t b = find_root(parent, j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<std::int64_t> start(n, -1);  // per union-find root: the component's start point
  std::size_t components = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t r = find_root(parent, static_cast<std::uint32_t>(i));
    if (start[r] < 0) {
      start[r] = static_cast<std::int64_t>(i);
      ++components;
    } else if (pos[i].x() > pos[static_cast<std::size_t>(start[r])].x()) {
      start[r] = static_cast<std::int64_t>(i);
    }
  }

  // Consistency of two neighbours' normals: n_v . n_w' with n_w' = n_w - 2 (n_w . e) e, n_w
  // reflected in the plane normal to the edge's unit direction e. On a circle through both
  // points, or across a thin sheet or a narrow gap, consistently oriented normals give +1,
  // where Hoppe's plain n_v . n_w is about -1. Between neighbours on one tangent plane it is
  // n_v . n_w.
  auto consistency = [&](std::uint32_t v, std::uint32_t w) {
    const Vec3& a = out.normals[v];
    const Vec3& b = out.normals[w];
    const Vec3 d = pos[w] - pos[v];
    const double len2 = d.squaredNorm();
    if (!(len2 > 0)) return a.dot(b);
    return a.dot(b) - 2 * a.dot(d) * b.dot(d) / len2;
  };
  // Prim's minimum spanning tree from each start, orienting every point as it joins the tree.
  using Entry = std::tuple<double, std::uint32_t, std::uint32_t>;  // cost, point, tree parent
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  std::vector<char> visited(n, 0);
  for (std::size_t r = 0; r < n; ++r) {
    if (start[r] < 0) continue;
    const auto s = static_cast<std::uint32_t>(start[r]);
    if (out.normals[s].x() < 0) out.normals[s] = -out.normals[s];
    queue.emplace(0.0, s, s);
    while (!queue.empty()) {
      const auto [cost, v, from] = queue.top();
      queue.pop();
      if (visited[v] != 0) continue;
      visited[v] = 1;
      if (v != from && consistency(from, v) < 0) out.normals[v] = -out.normals[v];
      for (const std::uint32_t w : adjacent[v]) {
        if (visited[w] == 0) queue.emplace(1 - std::abs(consistency(v, w)), w, v);
      }
    }
    check_cancel(ctx);
  }

  if (given) {
    // The propagation is right where the neighbour graph is: on a tube about as thin as the
    // neighbour spacing (a cow's tail) it can turn correct normals over. A given normal is
    // therefore only reversed where its own neighbourhood disagrees with it too: the sum of
    // its consistency with its neighbours' given normals is negative. A piece of the cloud
    // whose given normals mostly point against the propagation's outward orientation is taken
    // to be inverted as a whole (every normal inward) and reversed first.
    std::vector<Vec3> g(n);
    for (std::size_t i = 0; i < n; ++i) g[i] = points.normals[i].normalized();
    std::vector<std::int64_t> balance(n, 0);  // per union-find root: agreeing minus disagreeing
    for (std::size_t i = 0; i < n; ++i) {
      balance[find_root(parent, static_cast<std::uint32_t>(i))] +=
          out.normals[i].dot(g[i]) < 0 ? -1 : 1;
    }
    auto reflected = [&](const Vec3& a, const Vec3& b, std::size_t v, std::size_t w) {
      const Vec3 d = pos[w] - pos[v];
      const double len2 = d.squaredNorm();
      return len2 > 0 ? a.dot(b) - 2 * a.dot(d) * b.dot(d) / len2 : a.dot(b);
    };
    // Each piece's normals, reversed when the piece is inverted.
    std::vector<Vec3> current(n);
    for (std::size_t i = 0; i < n; ++i) {
      const bool inverted = balance[find_root(parent, static_cast<std::uint32_t>(i))] < 0;
      current[i] = inverted ? Vec3(-g[i]) : g[i];
    }
    // Rounds of votes (each reads the previous round's normals only, so the result does not
    // depend on the thread count): a normal the propagation disagrees with is reversed when its
    // neighbourhood disagrees too. A reversal only ever moves a normal to the propagation's side,
    // so the rounds end; neighbouring flipped normals (clusters) are undone from their rims in.
    std::vector<Vec3> next(n);
    for (int round = 0; round < 16; ++round) {
      std::atomic<std::size_t> changed{0};
      parallel::for_chunks(
          n, kGrain,
          [&](std::size_t b, std::size_t e) {
            std::size_t local = 0;
            for (std::size_t i = b; i < e; ++i) {
              next[i] = current[i];
              if (out.normals[i].dot(current[i]) >= 0) continue;
              double vote = 0;
              for (const std::uint32_t j : adjacent[i])
                vote += reflected(current[i], current[j], i, j);
              if (vote < 0) {
                next[i] = -current[i];
                ++local;
              }
            }
            changed += local;
          },
          ctx);
      current.swap(next);
      if (changed == 0) break;
    }
    out.normals = std::move(current);
  }

  if (report != nullptr) {
    *report = NormalReport{};
    report->components = components;
    if (given) {
      for (std::size_t i = 0; i < n; ++i)
        report->flipped += out.normals[i].dot(points.normals[i]) < 0 ? 1 : 0;
    } else {
      report->estimated = n;
    }
  }
  return out;
}

}  // namespace ramiform
