// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_extract.h"

#include <algorithm>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform::detail::tets {
namespace {

constexpr int kBoundLevel = 4;  // levels from which region tetrahedra are pruned by the bound
// The paper's data-parallel kernels become one task per chunk of this many region tetrahedra.
constexpr std::size_t kTetsPerChunk = 32;

// What one chunk of region tetrahedra produced.
struct ChunkOutput {
  std::vector<Polygon> polygons;  // record indices local to the chunk
  // Crossing edges: (global id of the inside lattice point) << 32 | (that of the outside one).
  std::vector<std::uint64_t> records;
  // Per region tetrahedron of the chunk, bit k set when a leaf corner on its face opposite
  // corner k is inside (f > iso): the surface reaches that face.
  std::vector<std::uint8_t> face_inside;
  std::size_t leaves = 0, evaluated = 0, skipped = 0;
};

// Marching tetrahedra on one leaf with corner positions `p`, corner values `f` (inside: > iso)
// and local corner ids `id`: appends the polygon with edge slots found by `slot(in, out)`.
//
// Orientation is decided in the root tetrahedron's barycentric space (`p` holds the leaf's
// integer barycentric coordinates w1, w2, w3), where every leaf has a proper volume, and
// flipped when the root tetrahedron is negatively oriented (`flip`): an affine map preserves
// which side is inside, so the result is right even for the slivers a Delaunay
// tetrahedralization contains, where a test on the model-space corners could pick either side.
template <class Slot>
void march_leaf(const TetPoints& p, bool flip, const std::array<double, 4>& f,
                const std::array<std::uint32_t, 4>& id, double iso, Slot&& slot,
                std::vector<Polygon>& out) {
  std::array<int, 4> ins{}, outs{};
  int ni = 0, no = 0;
  for (int k = 0; k < 4; ++k) {
    if (f[k] > iso) {
      ins[ni++] = k;
    } else {
      outs[no++] = k;
    }
  }
  if (ni == 0 || no == 0) return;
  // Orientation: the normal points from the inside corners to the outside ones, decided on the
  // edge midpoints, which always span a proper cross-section of the leaf.
  Vec3 in_mean = Vec3::Zero(), out_mean = Vec3::Zero();
  for (int k = 0; k < ni; ++k) in_mean += p[ins[k]] / ni;
  for (int k = 0; k < no; ++k) out_mean += p[outs[k]] / no;
  const Vec3 outward = flip ? Vec3(in_mean - out_mean) : Vec3(out_mean - in_mean);
  auto mid = [&](int a, int c) { return 0.5 * (p[a] + p[c]); };
  auto edge = [&](int a, int c) { return slot(id[a], id[c]); };  // a inside, c outside
  Polygon poly;
  if (ni == 1 || no == 1) {
    std::array<Vec3, 3> m;
    for (int k = 0; k < 3; ++k) {
      const int in = ni == 1 ? ins[0] : ins[k];
      const int ou = ni == 1 ? outs[k] : outs[0];
      poly.record[k] = edge(in, ou);
      m[k] = mid(in, ou);
    }
    if ((m[1] - m[0]).cross(m[2] - m[0]).dot(outward) < 0)
      std::swap(poly.record[1], poly.record[2]);
  } else {
    const int a = ins[0], c = ins[1], q0 = outs[0], q1 = outs[1];
    poly.quad = true;
    poly.record = {edge(a, q0), edge(a, q1), edge(c, q1), edge(c, q0)};
    const Vec3 m0 = mid(a, q0), m1 = mid(a, q1), m2 = mid(c, q1);
    if ((m1 - m0).cross(m2 - m0).dot(outward) < 0) std::swap(poly.record[1], poly.record[3]);
  }
  out.push_back(poly);
}

// Figure 4 on barycentric leaves: four corner tetrahedra, then the octahedron of the six edge
// midpoints split along its shortest diagonal (m1m6, m2m5 or m3m4), measured in model space.
template <class At>
void split_1_to_8(const BaryTet& t, At&& at, std::vector<BaryTet>& out) {
  const Bary m1 = midpoint(t[0], t[1]), m2 = midpoint(t[0], t[2]), m3 = midpoint(t[0], t[3]);
  const Bary m4 = midpoint(t[1], t[2]), m5 = midpoint(t[1], t[3]), m6 = midpoint(t[2], t[3]);
  out.push_back({t[0], m1, m2, m3});
  out.push_back({t[1], m1, m4, m5});
  out.push_back({t[2], m2, m4, m6});
  out.push_back({t[3], m3, m5, m6});
  const double d16 = (at(m1) - at(m6)).squaredNorm();
  const double d25 = (at(m2) - at(m5)).squaredNorm();
  const double d34 = (at(m3) - at(m4)).squaredNorm();
  const Bary* a = nullptr;
  const Bary* b = nullptr;
  std::array<const Bary*, 4> ring{};  // the other four midpoints, in cyclic order
  if (d16 <= d25 && d16 <= d34) {
    a = &m1, b = &m6, ring = {&m2, &m4, &m5, &m3};
  } else if (d25 <= d34) {
    a = &m2, b = &m5, ring = {&m1, &m3, &m6, &m4};
  } else {
    a = &m3, b = &m4, ring = {&m1, &m2, &m6, &m5};
  }
  for (int k = 0; k < 4; ++k) out.push_back({*a, *b, *ring[k], *ring[(k + 1) % 4]});
}

// Per-thread scratch of a chunk: leaves, and a stamped table from lattice point to local
// corner id (no clearing between tetrahedra).
struct LatticeScratch {
  std::vector<BaryTet> leaves, next;
  std::vector<std::uint32_t> stamp, id;
  std::uint32_t generation = 0;

  // Ready for lattices of `side` points per edge.
  void reserve(std::size_t side) {
    if (stamp.size() < side * side * side) {
      stamp.assign(side * side * side, 0);
      id.assign(side * side * side, 0);
      generation = 0;
    }
  }
  // Forgets every point registered so far.
  void next_generation() {
    if (++generation == 0) {  // stamps wrapped: clear once
      std::fill(stamp.begin(), stamp.end(), 0);
      generation = 1;
    }
  }
};

// The leaves of a chunk's live region tetrahedra (those with lattice points on both sides):
// their corners, numbered per tetrahedron in order of first use.
struct ChunkLeaves {
  std::vector<std::uint32_t> gid;      // global ids of the corners of every live tetrahedron
  std::vector<std::size_t> gid_begin;  // per live tetrahedron, its first corner in gid
  std::vector<std::array<std::uint32_t, 4>> leaf_ids;  // local corner ids of every leaf
  std::vector<std::uint8_t> corner_faces;              // per corner, the faces it lies on (bits)
  std::vector<Vec3> corner_bary;                       // per corner, its (w1, w2, w3)
  std::vector<char> live_flip;                         // per live tetrahedron, negatively oriented
  std::vector<std::size_t> live_slot;  // per live tetrahedron, its index in the chunk
};

// The lattice points of one region tetrahedron, each registered (global id looked up, appended
// to the chunk's corners) on first use through the stamped table.
struct LatticeIndex {
  LatticeScratch& sc;
  std::size_t side;
  const Lattice& lattice;
  std::size_t slot;
  const Tet& tet;
  ChunkLeaves& cl;
  std::size_t base;

  std::uint32_t id(const Bary& w) {
    const std::size_t key = (w[1] * side + w[2]) * side + w[3];
    if (sc.stamp[key] != sc.generation) {
      sc.stamp[key] = sc.generation;
      sc.id[key] = static_cast<std::uint32_t>(cl.gid.size() - base);
      cl.gid.push_back(lattice.id(slot, tet, w));
      cl.corner_bary.emplace_back(w[1], w[2], w[3]);
      cl.corner_faces.push_back(static_cast<std::uint8_t>(
          (w[0] == 0 ? 1 : 0) | (w[1] == 0 ? 2 : 0) | (w[2] == 0 ? 4 : 0) | (w[3] == 0 ? 8 : 0)));
    }
    return sc.id[key];
  }
  const Vec3& at(const Bary& w) { return lattice.position(cl.gid[base + id(w)]); }
};

// One round's region tetrahedra: `region` (indices into tz.tets) in lattice slots
// first_slot + r; live[r]: 1 to extract, 0 skipped as wholly outside, 2 skipped as wholly
// inside (field bound).
struct RoundJob {
  const Tetrahedralization& tz;
  const std::vector<std::uint32_t>& region;
  const std::vector<char>& live;
  const Lattice& lattice;
  std::size_t first_slot;
  int levels;
  double iso;
};

// The leaves of one region tetrahedron, subdivided `levels` times from its root.
void subdivide(const RoundJob& job, std::size_t r, LatticeScratch& sc, ChunkLeaves& cl) {
  const int m = 1 << job.levels;
  const std::size_t side = static_cast<std::size_t>(m) + 1;
  const Tet& t = job.tz.tets[job.region[r]];
  sc.next_generation();
  const std::size_t base = cl.gid.size();
  cl.gid_begin.push_back(base);
  LatticeIndex index{sc, side, job.lattice, job.first_slot + r, t, cl, base};
  auto at = [&](const Bary& w) { return index.at(w); };
  BaryTet root{};
  for (int k = 0; k < 4; ++k) root[k][k] = static_cast<std::uint8_t>(m);
  sc.leaves.assign(1, root);
  for (int level = 0; level < job.levels; ++level) {
    sc.next.clear();
    for (const auto& l : sc.leaves) split_1_to_8(l, at, sc.next);
    std::swap(sc.leaves, sc.next);
  }
  for (const auto& l : sc.leaves) {
    cl.leaf_ids.push_back({index.id(l[0]), index.id(l[1]), index.id(l[2]), index.id(l[3])});
  }
}

// Subdivides the region tetrahedra [begin, end) that hold a piece of the surface; the others
// get their face flags (all faces or none) and, if skipped by the bound, count as skipped.
ChunkLeaves subdivide_chunk(const RoundJob& job, std::size_t begin, std::size_t end,
                            ChunkOutput& out) {
  thread_local LatticeScratch sc;
  sc.reserve(static_cast<std::size_t>(1 << job.levels) + 1);
  ChunkLeaves cl;
  out.face_inside.assign(end - begin, 0);
  for (std::size_t r = begin; r < end; ++r) {
    if (job.live[r] != 1) {
      ++out.skipped;
      if (job.live[r] == 2) out.face_inside[r - begin] = 0xF;  // wholly inside: every face
      continue;
    }
    // A tetrahedron whose lattice points all lie on one side holds no surface: only its faces'
    // inside flags matter (all or none), and its leaves need not be built.
    const Tet& t = job.tz.tets[job.region[r]];
    if (bool inside = false; job.lattice.one_sided(job.first_slot + r, t, job.iso, inside)) {
      if (inside) out.face_inside[r - begin] = 0xF;
      continue;
    }
    const TetPoints c = job.tz.corners(job.region[r]);
    cl.live_slot.push_back(r - begin);
    cl.live_flip.push_back((c[1] - c[0]).cross(c[2] - c[0]).dot(c[3] - c[0]) < 0 ? 1 : 0);
    subdivide(job, r, sc, cl);
  }
  cl.gid_begin.push_back(cl.gid.size());
  out.leaves += cl.leaf_ids.size();
  return cl;
}

// The face flags of the live tetrahedra: the faces that an inside corner lies on.
void flag_faces(const ChunkLeaves& cl, const std::vector<double>& values, double iso,
                ChunkOutput& out) {
  for (std::size_t k = 0; k + 1 < cl.gid_begin.size(); ++k) {
    std::uint8_t flags = 0;
    for (std::size_t v = cl.gid_begin[k]; v < cl.gid_begin[k + 1]; ++v) {
      if (values[v] > iso) flags |= cl.corner_faces[v];
    }
    out.face_inside[cl.live_slot[k]] = flags;
  }
}

// Scratch of march_tetrahedron, reused across a chunk's tetrahedra.
struct MarchScratch {
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> order, rank;
};

// Marching tetrahedra on the leaves of the k-th live tetrahedron, with its crossing edges made
// unique locally. Polygons first refer to their edges by position in `keys`; the sorted unique
// keys then become this tetrahedron's records (the global ids of the edge's inside and outside
// lattice points) and the polygons are renumbered to them.
void march_tetrahedron(const ChunkLeaves& cl, const std::vector<double>& values, std::size_t k,
                       std::size_t leaves_per_tet, double iso, MarchScratch& ms, ChunkOutput& out) {
  const std::size_t base = cl.gid_begin[k];
  const std::size_t first_leaf = k * leaves_per_tet;
  const bool flip = cl.live_flip[k] != 0;
  auto leaf_points = [&](std::size_t l) {
    const auto& id = cl.leaf_ids[l];
    return TetPoints{cl.corner_bary[base + id[0]], cl.corner_bary[base + id[1]],
                     cl.corner_bary[base + id[2]], cl.corner_bary[base + id[3]]};
  };
  auto leaf_values = [&](std::size_t l) {
    const auto& id = cl.leaf_ids[l];
    return std::array<double, 4>{values[base + id[0]], values[base + id[1]], values[base + id[2]],
                                 values[base + id[3]]};
  };
  auto mixed = [&](const std::array<double, 4>& f) {
    const int in = (f[0] > iso) + (f[1] > iso) + (f[2] > iso) + (f[3] > iso);
    return in > 0 && in < 4;
  };
  ms.keys.clear();
  const std::size_t first_polygon = out.polygons.size();
  auto collect = [&](std::uint32_t in, std::uint32_t ou) {
    ms.keys.push_back((std::uint64_t{in} << 32U) | ou);
    return static_cast<std::uint32_t>(ms.keys.size() - 1);
  };
  for (std::size_t l = first_leaf; l < first_leaf + leaves_per_tet; ++l) {
    const auto f = leaf_values(l);
    if (mixed(f)) march_leaf(leaf_points(l), flip, f, cl.leaf_ids[l], iso, collect, out.polygons);
  }
  if (ms.keys.empty()) return;
  const auto& keys = ms.keys;
  ms.order.resize(keys.size());
  for (std::uint32_t i = 0; i < ms.order.size(); ++i) ms.order[i] = i;
  std::sort(ms.order.begin(), ms.order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  ms.rank.resize(keys.size());
  for (std::size_t i = 0; i < ms.order.size(); ++i) {
    const std::uint64_t key = keys[ms.order[i]];
    if (i == 0 || key != keys[ms.order[i - 1]]) {
      out.records.push_back((std::uint64_t{cl.gid[base + (key >> 32U)]} << 32U) |
                            cl.gid[base + (key & 0xffffffffU)]);
    }
    ms.rank[ms.order[i]] = static_cast<std::uint32_t>(out.records.size() - 1);
  }
  for (std::size_t q = first_polygon; q < out.polygons.size(); ++q) {
    Polygon& poly = out.polygons[q];
    const int corners = poly.quad ? 4 : 3;
    for (int c = 0; c < corners; ++c) poly.record[c] = ms.rank[poly.record[c]];
  }
}

// Subdivides and marches the region tetrahedra [begin, end) of the round into `out`.
void extract_chunk(const RoundJob& job, std::size_t begin, std::size_t end, ChunkOutput& out) {
  const ChunkLeaves cl = subdivide_chunk(job, begin, end, out);
  if (cl.gid.empty()) return;
  std::vector<double> values(cl.gid.size());
  for (std::size_t v = 0; v < cl.gid.size(); ++v) values[v] = job.lattice.value(cl.gid[v]);
  flag_faces(cl, values, job.iso, out);
  const auto leaves_per_tet = static_cast<std::size_t>(1) << (3 * job.levels);
  MarchScratch ms;
  for (std::size_t k = 0; k + 1 < cl.gid_begin.size(); ++k) {
    march_tetrahedron(cl, values, k, leaves_per_tet, job.iso, ms, out);
  }
}

// Per region tetrahedron: 1 to extract, 0 wholly outside, 2 wholly inside by the field bound.
// The region hugs the surface, so the bound almost never excludes a region tetrahedron
// (measured: 2 % at level 3, 0.7 % at level 2) and costs more than it saves below level 4
// (969 lattice points per tetrahedron); above, a skipped tetrahedron saves a lot.
std::vector<char> live_by_bound(const Field& field, const Tetrahedralization& tz,
                                const std::vector<std::uint32_t>& list, int levels,
                                const Context* ctx) {
  std::vector<char> live(list.size(), 1);
  if (levels < kBoundLevel) return live;
  parallel::for_each(
      list.size(), 256,
      [&](std::size_t r) {
        const Interval bound = field.bound(box_of(tz.corners(list[r])));
        if (!bound.straddles(field.iso())) live[r] = bound.lo > field.iso() ? 2 : 0;
      },
      ctx);
  return live;
}

// One round over the region tetrahedra `list`: the bound test, the new lattice points' field
// values, then chunks in parallel, outputs in chunk order.
std::vector<ChunkOutput> extract_list(const Field& field, const Tetrahedralization& tz,
                                      const std::vector<std::uint32_t>& list, Lattice& lattice,
                                      const TetrahedralOptions& o, const Context* ctx) {
  const std::vector<char> live = live_by_bound(field, tz, list, o.levels, ctx);
  const std::size_t first_slot = lattice.slots();
  const std::size_t evaluated = lattice.evaluated();
  lattice.add_round(field, list, live, ctx);
  const RoundJob job{tz, list, live, lattice, first_slot, o.levels, field.iso()};
  std::vector<ChunkOutput> outs((list.size() + kTetsPerChunk - 1) / kTetsPerChunk);
  parallel::for_chunks(
      list.size(), kTetsPerChunk,
      [&](std::size_t b, std::size_t e) { extract_chunk(job, b, e, outs[b / kTetsPerChunk]); },
      ctx);
  if (!outs.empty()) outs[0].evaluated = lattice.evaluated() - evaluated;
  return outs;
}

// Appends the chunk outputs to the extraction (record indices rebased) and adds their counts.
void merge_outputs(std::vector<ChunkOutput>& outs, TetrahedralStats& st, Extraction& ex,
                   const Context* ctx) {
  std::vector<std::size_t> poly_at(outs.size() + 1, ex.polygons.size());
  std::vector<std::size_t> rec_at(outs.size() + 1, ex.records.size());
  for (std::size_t i = 0; i < outs.size(); ++i) {
    poly_at[i + 1] = poly_at[i] + outs[i].polygons.size();
    rec_at[i + 1] = rec_at[i] + outs[i].records.size();
    st.leaf_tets += outs[i].leaves;
    st.vertices_evaluated += outs[i].evaluated;
    st.skipped_tets += outs[i].skipped;
  }
  ex.polygons.resize(poly_at.back());
  ex.records.resize(rec_at.back());
  parallel::for_chunks(
      outs.size(), 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const auto base = static_cast<std::uint32_t>(rec_at[i]);
          std::size_t w = poly_at[i];
          for (Polygon p : outs[i].polygons) {
            for (auto& r : p.record) r += base;
            ex.polygons[w++] = p;
          }
          std::copy(outs[i].records.begin(), outs[i].records.end(),
                    ex.records.begin() + static_cast<std::ptrdiff_t>(rec_at[i]));
          outs[i] = ChunkOutput{};
        }
      },
      ctx);
}

// The tetrahedra behind the faces of `list` that the surface reaches and that are not yet in
// the region (added to `keep`); a reached face on the hull sets holes_left.
std::vector<std::uint32_t> tetrahedra_behind(const Tetrahedralization& tz,
                                             const std::vector<std::uint32_t>& list,
                                             const std::vector<ChunkOutput>& outs,
                                             std::vector<char>& keep, TetrahedralStats& st) {
  std::vector<std::uint32_t> next;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::uint8_t flags = outs[i / kTetsPerChunk].face_inside[i % kTetsPerChunk];
    for (int k = 0; k < 4; ++k) {
      if ((flags & (1U << k)) == 0) continue;
      const std::uint32_t nb = tz.neighbors[4 * list[i] + k];
      if (nb == kNone) {
        st.holes_left = true;  // the surface reaches the hull of the far box
      } else if (keep[nb] == 0) {
        keep[nb] = 1;
        next.push_back(nb);
      }
    }
  }
  return next;
}

}  // namespace

// Holes are verified, not hoped away: the mesh can only open where a leaf corner on the
// region's boundary is inside, so growing the region across every such face until none is left
// closes the extracted mesh by construction.
Extraction extract_surface(const Field& field, const Tetrahedralization& tz,
                           std::vector<char>& keep, Lattice& lattice,
                           const TetrahedralOptions& options, const Context* ctx,
                           TetrahedralStats& st) {
  std::vector<std::uint32_t> list;
  for (std::uint32_t t = 0; t < tz.tets.size(); ++t) {
    if (keep[t] != 0) list.push_back(t);
  }
  Extraction ex;
  while (!list.empty()) {
    std::vector<ChunkOutput> outs = extract_list(field, tz, list, lattice, options, ctx);
    std::vector<std::uint32_t> next = tetrahedra_behind(tz, list, outs, keep, st);
    merge_outputs(outs, st, ex, ctx);
    if (!next.empty()) {
      if (st.growth_rounds == options.max_growth_rounds) {
        st.holes_left = true;
        break;
      }
      ++st.growth_rounds;
      st.grown_tets += next.size();
    }
    list = std::move(next);
    check_cancel(ctx);
  }
  return ex;
}

}  // namespace ramiform::detail::tets
