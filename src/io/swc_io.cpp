// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/swc_io.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
constexpr std::int32_t kSomaType = 1;

// Three-point soma: the side samples may sit this far (relative to the soma radius) from
// centre -+ r along y and have radii this far from r; the NeuroMorpho files write them from the
// same rounded numbers, so a few percent covers the rounding of small somata.
constexpr double kThreePointSlack = 0.05;
// A neurite sample whose distance from the soma centre exceeds the soma radius by less than
// this fraction of its own radius counts as inside the soma (an attachment node there would
// make a needle-short edge).
constexpr double kAttachMargin = 0.05;

struct Sample {
  std::size_t line = 0;
  std::int64_t id = 0;
  std::int32_t type = 0;
  Vec3 position = Vec3::Zero();
  double radius = 0;
  std::int64_t parent_id = -1;
  std::size_t parent = kNone;  // sample index of the parent
};

std::vector<Sample> read_samples(std::string_view text, const std::string& source) {
  using namespace io_detail;
  text = skip_bom(text);
  if (is_blank(text)) throw InputError(source, 0, "file is empty");
  std::vector<Sample> samples;
  LineCursor cursor(text);
  std::vector<std::string_view> f;
  while (next_content(cursor, f)) {
    const std::size_t ln = cursor.line_number();
    if (f.size() != 7) {
      throw InputError(source, ln,
                       "expected 7 fields (index type x y z radius parent), got " +
                           std::to_string(f.size()));
    }
    Sample s;
    s.line = ln;
    s.id = to_int64(f[0], source, ln, "index");
    if (s.id < 0) throw InputError(source, ln, "index must be >= 0, got " + std::to_string(s.id));
    const std::int64_t type = to_int64(f[1], source, ln, "type");
    if (type < std::numeric_limits<std::int32_t>::min() ||
        type > std::numeric_limits<std::int32_t>::max()) {
      throw InputError(source, ln, "type " + std::to_string(type) + " is out of range");
    }
    s.type = static_cast<std::int32_t>(type);
    static constexpr const char* kAxis[3] = {"x", "y", "z"};
    for (int c = 0; c < 3; ++c) s.position[c] = to_double(f[2 + c], source, ln, kAxis[c]);
    s.radius = to_double(f[5], source, ln, "radius");
    if (!(s.radius > 0.0)) {
      throw InputError(source, ln, "radius must be > 0, got " + std::string(f[5]));
    }
    s.parent_id = to_int64(f[6], source, ln, "parent");
    if (s.parent_id < -1) {
      throw InputError(source, ln,
                       "parent must be -1 (a root) or a sample index, got " +
                           std::to_string(s.parent_id));
    }
    if (s.parent_id == s.id) {
      throw InputError(source, ln, "sample " + std::to_string(s.id) + " is its own parent");
    }
    samples.push_back(s);
  }
  if (samples.empty()) throw InputError(source, 0, "no samples (only comments or blank lines)");
  return samples;
}

// Resolves parent indices; throws for duplicates, unknown parents and cycles.
void link_parents(std::vector<Sample>& samples, const std::string& source) {
  std::unordered_map<std::int64_t, std::size_t> by_id;
  by_id.reserve(samples.size() * 2);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto [it, inserted] = by_id.emplace(samples[i].id, i);
    if (!inserted) {
      throw InputError(source, samples[i].line,
                       "duplicate index " + std::to_string(samples[i].id) + " (first on line " +
                           std::to_string(samples[it->second].line) + ")");
    }
  }
  for (Sample& s : samples) {
    if (s.parent_id == -1) continue;
    const auto it = by_id.find(s.parent_id);
    if (it == by_id.end()) {
      throw InputError(source, s.line,
                       "parent " + std::to_string(s.parent_id) + " of sample " +
                           std::to_string(s.id) + " is not in the file");
    }
    s.parent = it->second;
  }
  // Every chain of parents must end at a root: walk each chain once (0 new, 1 on the current
  // walk, 2 known to reach a root).
  std::vector<char> state(samples.size(), 0);
  std::vector<std::size_t> path;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    path.clear();
    std::size_t j = i;
    while (j != kNone && state[j] == 0) {
      state[j] = 1;
      path.push_back(j);
      j = samples[j].parent;
    }
    if (j != kNone && state[j] == 1) {
      const auto start = std::find(path.begin(), path.end(), j);
      std::size_t first = samples[j].line;
      for (auto k = start; k != path.end(); ++k) first = std::min(first, samples[*k].line);
      throw InputError(source, first,
                       "cycle of parent links through " +
                           std::to_string(static_cast<std::size_t>(path.end() - start)) +
                           " sample(s): no root (parent -1) above sample " +
                           std::to_string(samples[j].id));
    }
    for (const std::size_t k : path) state[k] = 2;
  }
}

// Samples ordered so that every parent comes before its children (roots in file order, then
// breadth first).
std::vector<std::size_t> parents_first(const std::vector<Sample>& samples) {
  std::vector<std::vector<std::size_t>> children(samples.size());
  std::vector<std::size_t> order;
  order.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].parent == kNone) {
      order.push_back(i);
    } else {
      children[samples[i].parent].push_back(i);
    }
  }
  for (std::size_t k = 0; k < order.size(); ++k) {
    for (const std::size_t c : children[order[k]]) order.push_back(c);
  }
  return order;
}

struct SomaGroup {
  std::vector<std::size_t> members;  // sample indices, file order
  SwcSomaKind kind = SwcSomaKind::kSinglePoint;
  Vec3 center = Vec3::Zero();
  double radius = 0;
  std::uint32_t node = 0;
};

bool is_three_point(const std::vector<Sample>& s, const SomaGroup& g) {
  if (g.members.size() != 3) return false;
  for (const std::size_t c : g.members) {
    std::vector<std::size_t> sides;
    for (const std::size_t m : g.members) {
      if (m != c && s[m].parent == c) sides.push_back(m);
    }
    if (sides.size() != 2) continue;
    const double r = s[c].radius;
    const Vec3 dy(0, r, 0);
    const Vec3 a = s[sides[0]].position - s[c].position;
    const Vec3 b = s[sides[1]].position - s[c].position;
    const bool placed = ((a + dy).norm() <= kThreePointSlack * r &&
                         (b - dy).norm() <= kThreePointSlack * r) ||
                        ((a - dy).norm() <= kThreePointSlack * r &&
                         (b + dy).norm() <= kThreePointSlack * r);
    const bool radii = std::abs(s[sides[0]].radius - r) <= kThreePointSlack * r &&
                       std::abs(s[sides[1]].radius - r) <= kThreePointSlack * r;
    if (placed && radii) return true;
  }
  return false;
}

// Classifies a soma group of two or more samples that is not a three-point soma: a closed
// outline (a chain of >= 4 samples whose ends are as close as its neighbours) or samples whose
// spheres do not overlap along their links is a contour; otherwise a stack of cylinders.
SwcSomaKind multi_point_kind(const std::vector<Sample>& s, const SomaGroup& g,
                             const std::vector<std::size_t>& group_of) {
  std::unordered_map<std::size_t, int> degree;
  bool overlapping = true;
  double spacing = 0;
  for (const std::size_t m : g.members) {
    const std::size_t p = s[m].parent;
    if (p == kNone || group_of[p] != group_of[m]) continue;
    ++degree[m];
    ++degree[p];
    const double len = (s[m].position - s[p].position).norm();
    spacing = std::max(spacing, len);
    if (len > s[m].radius + s[p].radius) overlapping = false;
  }
  if (!overlapping) return SwcSomaKind::kContour;
  std::vector<std::size_t> ends;
  bool chain = true;
  for (const std::size_t m : g.members) {
    const int d = degree[m];
    if (d > 2) chain = false;
    if (d <= 1) ends.push_back(m);
  }
  if (chain && g.members.size() >= 4 && ends.size() == 2 &&
      (s[ends[0]].position - s[ends[1]].position).norm() <= 1.5 * spacing) {
    return SwcSomaKind::kContour;
  }
  return SwcSomaKind::kCylinders;
}

}  // namespace

Skeleton parse_swc(std::string_view text, const std::string& source_name,
                   const SwcReadOptions& options) {
  const std::string& source = source_name;
  std::vector<Sample> samples = read_samples(text, source);
  link_parents(samples, source);
  const std::size_t n = samples.size();

  Aabb box;
  for (const Sample& s : samples) box.extend(s.position);
  const double coincident = tol::kCoincident * std::max(box.diagonal().norm(), 1.0);
  const auto is_soma = [&](std::size_t i) {
    return options.soma_regions && samples[i].type == kSomaType;
  };

  // Soma groups: type-1 samples joined by type-1 parent links.
  std::vector<std::size_t> group_of(n, kNone);
  std::vector<SomaGroup> groups;
  const std::vector<std::size_t> order = parents_first(samples);
  for (const std::size_t i : order) {
    if (!is_soma(i)) continue;
    const std::size_t p = samples[i].parent;
    if (p != kNone && is_soma(p)) {
      group_of[i] = group_of[p];
    } else {
      group_of[i] = groups.size();
      groups.emplace_back();
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (group_of[i] != kNone) groups[group_of[i]].members.push_back(i);
  }
  for (SomaGroup& g : groups) {
    if (g.members.size() == 1) {
      g.kind = SwcSomaKind::kSinglePoint;
    } else if (is_three_point(samples, g)) {
      g.kind = SwcSomaKind::kThreePoint;
    } else {
      g.kind = multi_point_kind(samples, g, group_of);
    }
    if (g.kind == SwcSomaKind::kSinglePoint) {
      g.center = samples[g.members[0]].position;
      g.radius = samples[g.members[0]].radius;
    } else if (g.kind == SwcSomaKind::kThreePoint) {
      for (const std::size_t m : g.members) {  // the centre is the parent of the other two
        if (samples[m].parent == kNone || group_of[samples[m].parent] != group_of[m]) {
          g.center = samples[m].position;
          g.radius = samples[m].radius;
        }
      }
    } else if (g.kind == SwcSomaKind::kContour) {
      Vec3 sum = Vec3::Zero();
      for (const std::size_t m : g.members) sum += samples[m].position;
      g.center = sum / static_cast<double>(g.members.size());
      double mean = 0;
      for (const std::size_t m : g.members) mean += (samples[m].position - g.center).norm();
      g.radius = mean / static_cast<double>(g.members.size());
      if (!(g.radius > coincident)) {
        throw InputError(source, samples[g.members[0]].line,
                         "the soma outline starting here has no extent");
      }
    } else {
      g.center = samples[g.members[0]].position;
      for (const std::size_t m : g.members) g.radius = std::max(g.radius, samples[m].radius);
    }
  }
  const auto sphere_soma = [&](std::size_t i) {
    return group_of[i] != kNone && groups[group_of[i]].kind != SwcSomaKind::kCylinders;
  };

  // A sample whose position equals its parent's is merged into it (rep = the sample that
  // stands for it); soma samples are only merged into soma samples.
  std::vector<std::size_t> rep(n);
  for (std::size_t i = 0; i < n; ++i) rep[i] = i;
  std::size_t merged = 0;
  for (const std::size_t i : order) {
    const std::size_t p = samples[i].parent;
    if (p == kNone || sphere_soma(i) || is_soma(i) != is_soma(p)) continue;
    if ((samples[i].position - samples[rep[p]].position).norm() <= coincident) {
      rep[i] = rep[p];
      ++merged;
    }
  }

  Skeleton skel;
  std::vector<std::uint32_t> node_of(n, 0);
  skel.nodes.reserve(n);
  skel.node_types.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (sphere_soma(i)) {
      SomaGroup& g = groups[group_of[i]];
      if (g.members[0] == i) {
        g.node = static_cast<std::uint32_t>(skel.nodes.size());
        skel.nodes.push_back({g.center, g.radius});
        skel.node_types.push_back(kSomaType);
      }
      continue;
    }
    if (rep[i] != i) continue;
    node_of[i] = static_cast<std::uint32_t>(skel.nodes.size());
    skel.nodes.push_back({samples[i].position, samples[i].radius});
    skel.node_types.push_back(samples[i].type);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (sphere_soma(i)) {
      node_of[i] = groups[group_of[i]].node;
    } else if (rep[i] != i) {
      node_of[i] = node_of[rep[i]];
    }
  }

  std::size_t attachments = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = samples[i].parent;
    if (p == kNone || rep[i] != i) continue;
    const bool soma_i = is_soma(i);
    const bool soma_p = is_soma(p);
    if (soma_i && soma_p) {
      if (!sphere_soma(i)) skel.edges.push_back({node_of[p], node_of[i]});
      continue;
    }
    if (soma_i == soma_p) {
      skel.edges.push_back({node_of[p], node_of[i]});
      continue;
    }
    // A neurite leaving a soma: it starts on the soma's surface with its own radius (an edge
    // from the soma centre would be a cone from the soma radius down to the neurite's).
    const std::size_t soma = soma_i ? i : p;
    const std::size_t neurite = soma_i ? p : i;
    Vec3 center = samples[soma].position;
    double radius = samples[soma].radius;
    if (sphere_soma(soma)) {
      center = groups[group_of[soma]].center;
      radius = groups[group_of[soma]].radius;
    }
    const Sample& nb = samples[rep[neurite]];
    const Vec3 out = nb.position - center;
    const double d = out.norm();
    if (d <= radius + kAttachMargin * nb.radius) continue;  // starts inside the soma
    const auto a = static_cast<std::uint32_t>(skel.nodes.size());
    skel.nodes.push_back({center + (radius / d) * out, nb.radius});
    skel.node_types.push_back(nb.type);
    skel.edges.push_back({a, node_of[neurite]});
    ++attachments;
  }

  validate(skel, source);
  if (options.report != nullptr) {
    SwcReport& r = *options.report;
    r = SwcReport{};
    r.samples = n;
    for (const Sample& s : samples) r.roots += s.parent == kNone ? 1 : 0;
    for (const SomaGroup& g : groups) {
      SwcSoma soma;
      soma.kind = g.kind;
      soma.node = g.kind == SwcSomaKind::kCylinders ? node_of[g.members[0]] : g.node;
      soma.center = g.center;
      soma.radius = g.radius;
      soma.samples = g.members.size();
      soma.line = samples[g.members[0]].line;
      r.somata.push_back(soma);
    }
    r.sample_node = std::move(node_of);
    r.attachments = attachments;
    r.merged = merged;
  }
  return skel;
}

Skeleton read_swc(const std::string& path, const SwcReadOptions& options) {
  return parse_swc(io_detail::read_whole_file(path), path, options);
}

}  // namespace ramiform
