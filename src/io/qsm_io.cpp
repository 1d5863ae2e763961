// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/qsm_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using io_detail::LineCursor;
using io_detail::next_content;
using io_detail::split_fields;
using io_detail::strip_comment;
using io_detail::to_double;

constexpr std::int64_t kRootMarker = -1;  // the file marks the cylinder as the root
constexpr std::int64_t kNoParent = -2;    // the parent does not name another cylinder

struct Cylinder {
  Vec3 start = Vec3::Zero();
  Vec3 end = Vec3::Zero();
  double radius = 0.0;
  std::int64_t parent = kNoParent;  // index into the cylinder list, kRootMarker or kNoParent
  std::int64_t raw_parent = 0;      // as written in the file (resolved after reading all lines)
};

// A whole number written as an integer ("12") or as a floating-point number ("12.0", "1.2e1").
std::int64_t to_whole(std::string_view token, const std::string& source, std::size_t line,
                      std::string_view what) {
  std::int64_t v = 0;
  if (parse_number(token, v) == NumberStatus::kOk) return v;
  const double d = to_double(token, source, line, what);
  constexpr double kExact = 9007199254740992.0;  // 2^53: beyond it doubles skip integers
  if (d != std::floor(d) || std::abs(d) > kExact) {
    throw InputError(source, line,
                     std::string(what) + ": " + io_detail::quote(token) + " is not a whole number");
  }
  return static_cast<std::int64_t>(d);
}

double to_radius(std::string_view token, const std::string& source, std::size_t line) {
  const double r = to_double(token, source, line, "radius");
  if (!(r > 0.0)) {
    throw InputError(source, line, "radius must be > 0, got " + std::string(token));
  }
  return r;
}

Vec3 to_point(const std::vector<std::string_view>& f, std::size_t first, const std::string& source,
              std::size_t line, std::string_view what) {
  return {to_double(f[first], source, line, what), to_double(f[first + 1], source, line, what),
          to_double(f[first + 2], source, line, what)};
}

// Closest point parameter of `x` on the segment a + t (b - a), t in [0, 1].
double segment_parameter(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 u = b - a;
  const double len2 = u.squaredNorm();
  if (!(len2 > 0.0)) return 0.0;
  return std::clamp((x - a).dot(u) / len2, 0.0, 1.0);
}

std::uint32_t find_set(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Gives every cylinder an effective parent (-1 for the one root) so that the parent links form
// one tree: the first root marker is the root; orphans (invalid parents, later root markers,
// cycles) are attached to the nearest cylinder axis outside their own subtree.
std::vector<std::int64_t> resolve_tree(const std::vector<Cylinder>& cyl, std::size_t& reattached) {
  const std::size_t n = cyl.size();
  std::vector<std::int64_t> parent(n, -1);
  std::int64_t root = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t p = cyl[i].parent;
    if (p == kRootMarker && root < 0) {
      root = static_cast<std::int64_t>(i);
    } else if (p >= 0 && static_cast<std::size_t>(p) != i) {
      parent[i] = p;
    }
  }
  std::vector<std::vector<std::uint32_t>> children(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (parent[i] >= 0) {
      children[static_cast<std::size_t>(parent[i])].push_back(static_cast<std::uint32_t>(i));
    }
  }

  // Groups: the subtree of the root (group 0) and of each orphan; cycles are cut.
  std::vector<std::uint32_t> group(n, std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t> group_root;
  std::vector<std::uint32_t> stack;
  auto fill_group = [&](std::uint32_t top) {
    const auto g = static_cast<std::uint32_t>(group_root.size());
    group_root.push_back(top);
    stack.assign(1, top);
    while (!stack.empty()) {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      group[u] = g;
      for (const std::uint32_t c : children[u]) stack.push_back(c);
    }
  };
  if (root >= 0) fill_group(static_cast<std::uint32_t>(root));
  std::vector<std::size_t> walk_stamp(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (group[i] != std::numeric_limits<std::uint32_t>::max()) continue;
    // Walk up to the top of this subtree; a parent seen before on this walk closes a cycle,
    // which is cut at the cylinder whose parent closes it.
    std::size_t u = i;
    while (parent[u] >= 0) {
      walk_stamp[u] = i + 1;
      const auto p = static_cast<std::size_t>(parent[u]);
      if (walk_stamp[p] == i + 1) {
        auto& siblings = children[p];
        siblings.erase(std::find(siblings.begin(), siblings.end(), static_cast<std::uint32_t>(u)));
        parent[u] = -1;
        break;
      }
      u = p;
    }
    if (root < 0) {  // no root marker in the file: the first subtree's top is the root
      root = static_cast<std::int64_t>(u);
    }
    fill_group(static_cast<std::uint32_t>(u));
  }

  // Attach each orphan subtree (in the order of their first cylinders) to the nearest axis of a
  // cylinder in another set; every attachment joins two sets, so the result is one tree.
  std::vector<std::uint32_t> set(group_root.size());
  std::iota(set.begin(), set.end(), 0U);
  for (std::uint32_t g = 1; g < group_root.size(); ++g) {
    const std::uint32_t o = group_root[g];
    const Vec3& x = cyl[o].start;
    const std::uint32_t own = find_set(set, g);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_k = 0;
    for (std::uint32_t k = 0; k < n; ++k) {
      if (find_set(set, group[k]) == own) continue;
      const Cylinder& c = cyl[k];
      const double t = segment_parameter(c.start, c.end, x);
      const double d = (x - (c.start + t * (c.end - c.start))).squaredNorm();
      if (d < best) {
        best = d;
        best_k = k;
      }
    }
    parent[o] = best_k;
    set[own] = find_set(set, group[best_k]);
    ++reattached;
  }
  return parent;
}

// Builds the skeleton from the cylinders and their tree (see qsm_io.h for the rules).
class SkeletonBuilder {
 public:
  SkeletonBuilder(const std::vector<Cylinder>& cyl, const std::vector<std::int64_t>& parent,
                  QsmImportReport& report)
      : cyl_(cyl), parent_(parent), report_(report) {}

  Skeleton build() {
    const std::size_t n = cyl_.size();
    std::vector<std::vector<std::uint32_t>> children(n);
    std::uint32_t root = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (parent_[i] < 0) {
        root = static_cast<std::uint32_t>(i);
      } else {
        children[static_cast<std::size_t>(parent_[i])].push_back(static_cast<std::uint32_t>(i));
      }
    }
    // Where each child meets its parent's axis (independent of the nodes built so far).
    std::vector<double> t(n, 0.0);
    std::vector<double> offset(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      if (parent_[i] < 0) continue;
      const Cylinder& p = cyl_[static_cast<std::size_t>(parent_[i])];
      t[i] = segment_parameter(p.start, p.end, cyl_[i].start);
      offset[i] = (cyl_[i].start - (p.start + t[i] * (p.end - p.start))).norm();
    }

    attach_.assign(n, 0);
    std::vector<std::uint32_t> order{root};
    order.reserve(n);
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::uint32_t i = order[k];
      build_cylinder(i, children[i], t, offset);
      for (const std::uint32_t c : children[i]) order.push_back(c);
    }

    for (std::size_t v = 0; v < skeleton_.nodes.size(); ++v) {
      const double in = in_radius_[v];
      const double out = out_radius_[v];
      skeleton_.nodes[v].radius = in > 0.0 && out > 0.0 ? 0.5 * (in + out) : std::max(in, out);
    }
    return std::move(skeleton_);
  }

 private:
  std::uint32_t add_node(const Vec3& x) {
    skeleton_.nodes.push_back({x, 0.0});
    adjacent_.emplace_back();
    in_radius_.push_back(0.0);
    out_radius_.push_back(0.0);
    return static_cast<std::uint32_t>(skeleton_.nodes.size() - 1);
  }

  void add_edge(std::uint32_t a, std::uint32_t b) {
    if (a == b) return;
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32U) | std::max(a, b);
    if (!edge_keys_.insert(key).second) return;
    skeleton_.edges.push_back({a, b});
    adjacent_[a].push_back(b);
    adjacent_[b].push_back(a);
  }

  // The neighbour of `node` closest to `x` if it lies within `tol`, else none.
  std::optional<std::uint32_t> neighbour_near(std::uint32_t node, const Vec3& x, double tol) const {
    std::optional<std::uint32_t> best;
    double best_d = tol;
    for (const std::uint32_t v : adjacent_[node]) {
      const double d = (skeleton_.nodes[v].position - x).norm();
      if (d <= best_d) {
        best_d = d;
        best = v;
      }
    }
    return best;
  }

  void build_cylinder(std::uint32_t i, std::vector<std::uint32_t>& children,
                      const std::vector<double>& t, const std::vector<double>& offset) {
    const Cylinder& c = cyl_[i];
    const double r = c.radius;
    std::uint32_t start = 0;
    if (parent_[i] < 0) {
      start = add_node(c.start);
    } else {
      const double rp = cyl_[static_cast<std::size_t>(parent_[i])].radius;
      if (offset[i] <= tol::kQsmJoin * std::min(r, rp)) {
        start = attach_[i];
      } else {
        start = add_node(c.start);
        add_edge(attach_[i], start);
        ++report_.connectors;
      }
    }
    out_radius_[start] = std::max(out_radius_[start], r);

    const double merge = tol::kQsmMerge * r;
    if ((c.end - skeleton_.nodes[start].position).norm() < merge) {
      ++report_.merged_tiny;
      in_radius_[start] = std::max(in_radius_[start], r);
      for (const std::uint32_t ch : children) attach_[ch] = start;
      return;
    }

    // Group the children's attachment points along the axis: near the start, interior groups
    // (each spanning at most `merge` from its first point), near the end.
    std::sort(children.begin(), children.end(), [&](std::uint32_t a, std::uint32_t b) {
      return t[a] < t[b] || (t[a] == t[b] && a < b);
    });
    const Vec3 axis = c.end - c.start;
    const double length = axis.norm();
    auto at = [&](double s) -> Vec3 { return c.start + s * axis; };

    std::uint32_t current = start;
    bool reused = false;
    // Moves along the axis to `x`, reusing a neighbour of the current node that is already
    // there; returns the node at `x`.
    auto step_to = [&](const Vec3& x, bool is_split) {
      std::uint32_t next = 0;
      reused = false;
      if (const auto existing = neighbour_near(current, x, merge)) {
        next = *existing;
        reused = true;
      } else {
        next = add_node(x);
        if (is_split) ++report_.split_parents;
      }
      add_edge(current, next);
      in_radius_[next] = std::max(in_radius_[next], r);
      if (is_split) out_radius_[next] = std::max(out_radius_[next], r);
      current = next;
      return next;
    };

    std::size_t k = 0;
    const std::size_t m = children.size();
    std::vector<std::uint32_t> at_end;
    while (k < m) {
      const double t0 = t[children[k]];
      std::size_t e = k + 1;
      while (e < m && (t[children[e]] - t0) * length <= merge) ++e;
      double mean = 0.0;
      for (std::size_t j = k; j < e; ++j) mean += t[children[j]];
      const Vec3 x = at(mean / static_cast<double>(e - k));
      // Nodes on the chain stay more than `merge` apart.
      std::uint32_t node = current;
      if ((x - skeleton_.nodes[current].position).norm() > merge) {
        if ((x - c.end).norm() <= merge) {
          at_end.insert(at_end.end(), children.begin() + static_cast<std::ptrdiff_t>(k),
                        children.begin() + static_cast<std::ptrdiff_t>(e));
          k = e;
          continue;
        }
        node = step_to(x, true);
      }
      for (std::size_t j = k; j < e; ++j) attach_[children[j]] = node;
      k = e;
    }
    const std::uint32_t end = step_to(c.end, false);
    for (const std::uint32_t ch : at_end) attach_[ch] = end;
    if (reused) ++report_.duplicates;  // the end node (and so the last edge) existed already
  }

  const std::vector<Cylinder>& cyl_;
  const std::vector<std::int64_t>& parent_;
  QsmImportReport& report_;
  Skeleton skeleton_;
  std::vector<std::uint32_t> attach_;  // per cylinder: the parent's node it attaches to
  std::vector<std::vector<std::uint32_t>> adjacent_;
  std::vector<double> in_radius_;   // largest radius of the cylinders ending at a node (0: none)
  std::vector<double> out_radius_;  // largest radius of the cylinders starting at a node
  std::unordered_set<std::uint64_t> edge_keys_;
};

Skeleton cylinders_to_skeleton(const std::vector<Cylinder>& cyl, const std::string& source,
                               QsmImportReport* report) {
  if (cyl.empty()) throw InputError(source, 0, "no cylinders");
  QsmImportReport r;
  r.cylinders = cyl.size();
  const std::vector<std::int64_t> parent = resolve_tree(cyl, r.reattached);
  Skeleton s = SkeletonBuilder(cyl, parent, r).build();
  validate(s, source);
  if (report != nullptr) *report = r;
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& ch : out) {
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  }
  return out;
}

}  // namespace

Skeleton parse_treeqsm(std::string_view text, const std::string& source_name,
                       QsmImportReport* report) {
  const std::string& source = source_name;
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = io_detail::skip_bom(text);
  if (io_detail::is_blank(text)) throw InputError(source, 0, "file is empty");
  std::vector<Cylinder> cyl;
  LineCursor cursor(text);
  std::vector<std::string_view> f;
  bool first = true;
  while (next_content(cursor, f)) {
    const std::size_t ln = cursor.line_number();
    if (first) {
      first = false;
      double v = 0.0;
      if (parse_number(f[0], v) == NumberStatus::kMalformed) continue;  // a header line
    }
    if (f.size() < 9) {
      throw InputError(source, ln,
                       "expected at least 9 columns (radius, length, start x y z, axis x y z, "
                       "parent), got " +
                           std::to_string(f.size()));
    }
    Cylinder c;
    c.radius = to_radius(f[0], source, ln);
    const double length = to_double(f[1], source, ln, "length");
    if (length < 0.0) {
      throw InputError(source, ln, "length must be >= 0, got " + std::string(f[1]));
    }
    c.start = to_point(f, 2, source, ln, "start point");
    const Vec3 axis = to_point(f, 5, source, ln, "axis direction");
    const double norm = axis.stableNorm();  // no overflow to inf for large components
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      throw InputError(source, ln, "the axis direction must be a non-zero vector");
    }
    c.end = c.start + (length / norm) * axis;
    if (!is_finite(c.end)) throw InputError(source, ln, "the cylinder's end is not finite");
    c.raw_parent = to_whole(f[8], source, ln, "parent");
    cyl.push_back(c);
  }
  const auto n = static_cast<std::int64_t>(cyl.size());
  for (std::int64_t i = 0; i < n; ++i) {
    Cylinder& c = cyl[static_cast<std::size_t>(i)];
    // 1-based row numbers, 0 = root.
    if (c.raw_parent == 0) {
      c.parent = kRootMarker;
    } else if (c.raw_parent >= 1 && c.raw_parent <= n && c.raw_parent - 1 != i) {
      c.parent = c.raw_parent - 1;
    } else {
      c.parent = kNoParent;
    }
  }
  return cylinders_to_skeleton(cyl, source, report);
}

bool looks_like_simpleforest(std::string_view text) {
  LineCursor cursor(io_detail::skip_bom(text));
  std::string_view line;
  std::vector<std::string_view> f;
  while (cursor.next(line)) {
    if (!split_fields(strip_comment(line), f, true)) return false;
    if (f.empty()) continue;
    bool parent = false;
    bool start = false;
    for (const auto name : f) {
      const std::string l = lower(name);
      parent = parent || l == "parentid";
      start = start || l == "startx";
    }
    return parent && start;
  }
  return false;
}

Skeleton parse_simpleforest(std::string_view text, const std::string& source_name,
                            QsmImportReport* report) {
  const std::string& source = source_name;
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  text = io_detail::skip_bom(text);
  if (io_detail::is_blank(text)) throw InputError(source, 0, "file is empty");
  static constexpr const char* kColumns[] = {"ID",   "parentID", "startX", "startY", "startZ",
                                             "endX", "endY",     "endZ",   "radius"};
  constexpr std::size_t kUsed = std::size(kColumns);
  std::size_t column[kUsed];
  std::size_t field_count = 0;
  std::size_t header_line = 0;
  std::vector<Cylinder> cyl;
  std::vector<std::size_t> line_of;  // per cylinder
  std::unordered_map<std::int64_t, std::size_t> index_of_id;

  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> f;
  while (cursor.next(line)) {
    const std::size_t ln = cursor.line_number();
    if (!split_fields(strip_comment(line), f, true)) {
      throw InputError(source, ln, "empty field (two commas in a row, or a comma at an end)");
    }
    if (f.empty()) continue;
    if (header_line == 0) {
      header_line = ln;
      field_count = f.size();
      for (std::size_t k = 0; k < kUsed; ++k) {
        const std::string want = lower(kColumns[k]);
        const auto it = std::find_if(f.begin(), f.end(),
                                     [&](std::string_view name) { return lower(name) == want; });
        if (it == f.end()) {
          throw InputError(source, ln,
                           std::string("missing column '") + kColumns[k] +
                               "' (a SimpleForest header names ID, parentID, startX, startY, "
                               "startZ, endX, endY, endZ, radius)");
        }
        column[k] = static_cast<std::size_t>(it - f.begin());
      }
      continue;
    }
    if (f.size() != field_count) {
      throw InputError(source, ln,
                       "expected " + std::to_string(field_count) +
                           " fields like the header (line " + std::to_string(header_line) +
                           "), got " + std::to_string(f.size()));
    }
    Cylinder c;
    const std::int64_t id = to_whole(f[column[0]], source, ln, "ID");
    c.raw_parent = to_whole(f[column[1]], source, ln, "parentID");
    for (int a = 0; a < 3; ++a) {
      c.start[a] = to_double(f[column[2 + a]], source, ln, kColumns[2 + a]);
      c.end[a] = to_double(f[column[5 + a]], source, ln, kColumns[5 + a]);
    }
    c.radius = to_radius(f[column[8]], source, ln);
    const auto [it, fresh] = index_of_id.emplace(id, cyl.size());
    if (!fresh) {
      throw InputError(source, ln,
                       "ID " + std::to_string(id) + " repeats the ID of line " +
                           std::to_string(line_of[it->second]));
    }
    cyl.push_back(c);
    line_of.push_back(ln);
  }
  for (std::size_t i = 0; i < cyl.size(); ++i) {
    Cylinder& c = cyl[i];
    if (c.raw_parent < 0) {
      c.parent = kRootMarker;
      continue;
    }
    const auto it = index_of_id.find(c.raw_parent);
    c.parent = it != index_of_id.end() && it->second != i ? static_cast<std::int64_t>(it->second)
                                                          : kNoParent;
  }
  return cylinders_to_skeleton(cyl, source, report);
}

Skeleton read_treeqsm(const std::string& path, QsmImportReport* report) {
  return parse_treeqsm(io_detail::read_whole_file(path), path, report);
}

Skeleton read_simpleforest(const std::string& path, QsmImportReport* report) {
  return parse_simpleforest(io_detail::read_whole_file(path), path, report);
}

}  // namespace ramiform
