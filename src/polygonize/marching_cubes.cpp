// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/marching_cubes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "polygonize/edge_roots.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

#include "mc_tables.inc"

using i64 = std::int64_t;

enum class BlockState : std::uint8_t {
  kActive,   // the bound straddles iso (or bounds are not used): evaluated
  kOutside,  // bound.hi <= iso: every point outside, skipped
  kInside,   // bound.lo > iso: every point inside, skipped
};

/// The uniform grid and its split into blocks. Points are indexed (i, j, k) with 0 <= i <= n[0];
/// a point is owned by block min(i / B, nb - 1) along each axis, so the last block along an axis
/// also owns the grid's last point layer.
struct Grid {
  Vec3 origin = Vec3::Zero();
  double h = 0.0;
  std::array<i64, 3> n{};   // cells per axis
  std::array<i64, 3> nb{};  // blocks per axis
  i64 B = 16;               // cells per block side

  [[nodiscard]] i64 point_index(i64 i, i64 j, i64 k) const {
    return i + (n[0] + 1) * (j + (n[1] + 1) * k);
  }
  [[nodiscard]] Vec3 point(i64 i, i64 j, i64 k) const {
    return {origin.x() + h * static_cast<double>(i), origin.y() + h * static_cast<double>(j),
            origin.z() + h * static_cast<double>(k)};
  }
  [[nodiscard]] i64 owner(int axis, i64 i) const { return std::min(i / B, nb[axis] - 1); }
  [[nodiscard]] i64 lo(i64 b) const { return b * B; }
  /// Last point of block b's closed range along `axis`.
  [[nodiscard]] i64 hi(int axis, i64 b) const { return std::min((b + 1) * B, n[axis]); }
  /// One past the last point owned by block b along `axis`.
  [[nodiscard]] i64 owned_end(int axis, i64 b) const {
    return b == nb[axis] - 1 ? n[axis] + 1 : (b + 1) * B;
  }
  [[nodiscard]] i64 block_count() const { return nb[0] * nb[1] * nb[2]; }
  [[nodiscard]] i64 block_index(i64 bx, i64 by, i64 bz) const {
    return bx + nb[0] * (by + nb[1] * bz);
  }
  [[nodiscard]] std::array<i64, 3> block_coords(i64 b) const {
    return {b % nb[0], (b / nb[0]) % nb[1], b / (nb[0] * nb[1])};
  }
  [[nodiscard]] Aabb block_box(const std::array<i64, 3>& bc) const {
    return {point(lo(bc[0]), lo(bc[1]), lo(bc[2])),
            point(hi(0, bc[0]), hi(1, bc[1]), hi(2, bc[2]))};
  }
  /// Calls fn(block index) for every block whose closed range contains point (i, j, k).
  template <class Fn>
  void for_each_block_containing(i64 i, i64 j, i64 k, Fn&& fn) const {
    const std::array<i64, 3> p{i, j, k};
    std::array<std::array<i64, 2>, 3> cand{};
    std::array<int, 3> count{};
    for (int a = 0; a < 3; ++a) {
      const i64 o = owner(a, p[a]);
      cand[a][count[a]++] = o;
      if (o > 0 && p[a] == o * B) cand[a][count[a]++] = o - 1;
    }
    for (int z = 0; z < count[2]; ++z)
      for (int y = 0; y < count[1]; ++y)
        for (int x = 0; x < count[0]; ++x) fn(block_index(cand[0][x], cand[1][y], cand[2][z]));
  }
  /// Calls fn(block index) for every block touching block b (itself included).
  template <class Fn>
  void for_each_block_around(i64 b, Fn&& fn) const {
    const auto bc = block_coords(b);
    for (int d = 0; d < 27; ++d) {
      const i64 x = bc[0] + d % 3 - 1;
      const i64 y = bc[1] + (d / 3) % 3 - 1;
      const i64 z = bc[2] + d / 9 - 1;
      if (x < 0 || y < 0 || z < 0 || x >= nb[0] || y >= nb[1] || z >= nb[2]) continue;
      fn(block_index(x, y, z));
    }
  }
};

/// Everything one block produces. Only needed blocks hold data.
struct BlockData {
  FieldPtr restricted;               // the field restricted to the block's box
  std::vector<double> owned_values;  // values at owned points (NaN where not evaluated)
  std::vector<std::uint8_t> cases;   // case index per cell (active blocks)
  std::vector<std::uint64_t> keys;   // owned crossing edges, ascending edge keys
  std::vector<std::uint32_t> slots;  // per key: 3 * (local closed-range point) + axis
  std::vector<Vec3> vertices;        // one position per key
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t base = 0;  // global id of the first owned vertex
  i64 evaluations = 0;
  i64 root_evaluations = 0;
  i64 overrides = 0;
};

/// Block data of the z-slabs of blocks currently in flight (at most three: the one being
/// triangulated, the one being classified and the one above it); other slabs hold nothing.
class BlockStore {
 public:
  explicit BlockStore(const Grid& g)
      : per_slab_(g.nb[0] * g.nb[1]), slabs_(static_cast<std::size_t>(g.nb[2])) {}
  BlockData& operator[](i64 b) { return slab(b / per_slab_)[slot(b)]; }
  const BlockData& operator[](i64 b) const {
    return slabs_[static_cast<std::size_t>(b / per_slab_)][slot(b)];
  }
  /// Allocates (empty) data for slab z.
  std::vector<BlockData>& slab(i64 z) {
    auto& s = slabs_[static_cast<std::size_t>(z)];
    if (s.empty()) s.resize(static_cast<std::size_t>(per_slab_));
    return s;
  }
  void release(i64 z) { std::vector<BlockData>().swap(slabs_[static_cast<std::size_t>(z)]); }

 private:
  [[nodiscard]] std::size_t slot(i64 b) const { return static_cast<std::size_t>(b % per_slab_); }
  i64 per_slab_;
  std::vector<std::vector<BlockData>> slabs_;
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Grid make_grid(const Field& field, const MarchingCubesOptions& options, bool& empty) {
  empty = false;
  Aabb box = options.box;
  const bool padded = box.isEmpty();
  if (padded) {
    box = field.bounds();
    if (box.isEmpty()) {
      empty = true;
      return {};
    }
    if (!box.min().allFinite() || !box.max().allFinite()) {
      throw InvalidArgument(
          "marching_cubes: field.bounds() is not finite; set MarchingCubesOptions.box");
    }
  }
  const double longest = box.sizes().maxCoeff();
  double h = options.cell_size;
  if (h == 0.0) {
    if (!(longest > 0.0)) {
      throw InvalidArgument(
          "marching_cubes: the box has zero extent; set MarchingCubesOptions.cell_size");
    }
    h = longest / options.resolution;
  }
  if (padded) {
    box.min().array() -= h;
    box.max().array() += h;
  }
  Grid g;
  g.origin = box.min();
  g.h = h;
  g.B = options.block_cells;
  double total = 1.0;
  for (int a = 0; a < 3; ++a) {
    // The small relative slack keeps an exact multiple of h from adding a sliver cell.
    const double cells = std::ceil(box.sizes()[a] / h * (1.0 - 1e-12));
    total *= std::max(cells, 1.0);
    if (!(total <= static_cast<double>(options.max_cells))) {
      throw InvalidArgument(
          "marching_cubes: the grid needs more than MarchingCubesOptions."
          "max_cells = " +
          std::to_string(options.max_cells) + " cells (cell size " + std::to_string(h) + ")");
    }
    g.n[a] = std::max<i64>(1, static_cast<i64>(cells));
    g.nb[a] = (g.n[a] + g.B - 1) / g.B;
  }
  return g;
}

/// Forces the value at a point to agree with every skipped block containing it (their bounds
/// say the whole closed block is on one side). Returns true when the value changed.
bool force_sign(const Grid& g, const std::vector<BlockState>& state, double iso, i64 i, i64 j,
                i64 k, double& v) {
  bool outside = false;
  bool inside = false;
  g.for_each_block_containing(i, j, k, [&](i64 b) {
    outside = outside || state[b] == BlockState::kOutside;
    inside = inside || state[b] == BlockState::kInside;
  });
  // Skipped blocks sharing a point never disagree (conflicting pairs were activated).
  if (outside && v > iso) {
    v = iso;
    return true;
  }
  if (!outside && inside && !(v > iso)) {
    v = std::nextafter(iso, std::numeric_limits<double>::infinity());
    return true;
  }
  return false;
}

/// True when some block touching block b (itself included) was skipped by its bound: only then
/// may a point of b need its sign forced.
bool touches_skipped(const Grid& g, const std::vector<BlockState>& state, i64 b) {
  bool skipped = false;
  g.for_each_block_around(b, [&](i64 nbr) {
    skipped = skipped || state[static_cast<std::size_t>(nbr)] != BlockState::kActive;
  });
  return skipped;
}

/// Phase 2: evaluates the points owned by block b that some active block needs.
void evaluate_owned(const Field& field, const Grid& g, const std::vector<BlockState>& state, i64 b,
                    BlockData& data) {
  const auto bc = g.block_coords(b);
  std::array<i64, 3> lo{};
  std::array<i64, 3> size{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = g.lo(bc[a]);
    size[a] = g.owned_end(a, bc[a]) - lo[a];
  }
  const bool active = state[static_cast<std::size_t>(b)] == BlockState::kActive;
  const auto count = static_cast<std::size_t>(size[0] * size[1] * size[2]);
  const double iso = field.iso();
  const bool may_force = touches_skipped(g, state, b);
  auto settle = [&](std::uint32_t s, double& v) {
    if (std::isnan(v)) v = iso;  // a NaN value counts as outside (and cannot break bracketing)
    if (!may_force) return;
    const i64 x = s % size[0];
    const i64 y = (s / size[0]) % size[1];
    const i64 z = s / (size[0] * size[1]);
    // Points off the lower faces belong to this block only (active, or skipped and then
    // never evaluated).
    if (x != 0 && y != 0 && z != 0 && active) return;
    if (force_sign(g, state, iso, lo[0] + x, lo[1] + y, lo[2] + z, v)) ++data.overrides;
  };
  std::vector<Vec3> points;
  if (active) {
    // Every owned point, evaluated straight into the store.
    points.reserve(count);
    for (i64 z = 0; z < size[2]; ++z)
      for (i64 y = 0; y < size[1]; ++y)
        for (i64 x = 0; x < size[0]; ++x)
          points.push_back(g.point(lo[0] + x, lo[1] + y, lo[2] + z));
    data.owned_values.resize(count);
    data.restricted = field.restrict(g.block_box(bc));
    data.restricted->evaluate(points, data.owned_values);
    data.evaluations += static_cast<i64>(count);
    for (std::size_t q = 0; q < count; ++q)
      settle(static_cast<std::uint32_t>(q), data.owned_values[q]);
    return;
  }
  // An inactive block: only points on its lower faces can be shared with an active block.
  data.owned_values.assign(count, kNaN);
  std::vector<std::uint32_t> slots;  // owned-point index of each evaluated point
  std::uint32_t slot = 0;
  for (i64 z = 0; z < size[2]; ++z) {
    for (i64 y = 0; y < size[1]; ++y) {
      for (i64 x = 0; x < size[0]; ++x, ++slot) {
        if (x != 0 && y != 0 && z != 0) continue;
        const i64 i = lo[0] + x;
        const i64 j = lo[1] + y;
        const i64 k = lo[2] + z;
        bool needed = false;
        g.for_each_block_containing(i, j, k, [&](i64 nbr) {
          needed = needed || state[static_cast<std::size_t>(nbr)] == BlockState::kActive;
        });
        if (!needed) continue;
        points.push_back(g.point(i, j, k));
        slots.push_back(slot);
      }
    }
  }
  if (points.empty()) return;
  data.restricted = field.restrict(g.block_box(bc));
  std::vector<double> values(points.size());
  data.restricted->evaluate(points, values);
  data.evaluations += static_cast<i64>(points.size());
  for (std::size_t q = 0; q < points.size(); ++q) {
    settle(slots[q], values[q]);
    data.owned_values[slots[q]] = values[q];
  }
}

/// Copies the values of block b's closed point range (c[0] x c[1] x c[2], x fastest) from the
/// owner blocks, row by row.
void gather_values(const Grid& g, const BlockStore& blocks, const std::array<i64, 3>& bc,
                   const std::array<i64, 3>& c, std::vector<double>& v) {
  v.resize(static_cast<std::size_t>(c[0] * c[1] * c[2]));
  const i64 lo0 = g.lo(bc[0]);
  double* out = v.data();
  for (i64 z = 0; z < c[2]; ++z) {
    const i64 k = g.lo(bc[2]) + z;
    const i64 oz = g.owner(2, k);
    for (i64 y = 0; y < c[1]; ++y) {
      const i64 j = g.lo(bc[1]) + y;
      const i64 oy = g.owner(1, j);
      // A row spans at most two owners along x: this block and the next.
      for (i64 i = lo0; i < lo0 + c[0];) {
        const i64 ox = g.owner(0, i);
        const i64 end = std::min(lo0 + c[0], g.owned_end(0, ox));
        const BlockData& d = blocks[g.block_index(ox, oy, oz)];
        const i64 sx = g.owned_end(0, ox) - g.lo(ox);
        const i64 sy = g.owned_end(1, oy) - g.lo(oy);
        const double* src =
            d.owned_values.data() + ((i - g.lo(ox)) + sx * ((j - g.lo(oy)) + sy * (k - g.lo(oz))));
        out = std::copy(src, src + (end - i), out);
        i = end;
      }
    }
  }
}

/// Phase 3: cell cases, owned crossing edges and their vertices of an active block.
void classify_block(const Grid& g, const BlockStore& blocks, double iso, int root_steps, i64 b,
                    BlockData& data) {
  const auto bc = g.block_coords(b);
  std::array<i64, 3> lo{};
  std::array<i64, 3> c{};   // closed-range point counts
  std::array<i64, 3> oe{};  // owned end (exclusive), local
  for (int a = 0; a < 3; ++a) {
    lo[a] = g.lo(bc[a]);
    c[a] = g.hi(a, bc[a]) - lo[a] + 1;
    oe[a] = g.owned_end(a, bc[a]) - lo[a];
  }
  std::vector<double> v;
  gather_values(g, blocks, bc, c, v);
  std::vector<std::uint8_t> in(v.size());
  for (std::size_t p = 0; p < v.size(); ++p) in[p] = v[p] > iso ? 1 : 0;
  const i64 sy = c[0];
  const i64 sz = c[0] * c[1];

  // Cell cases.
  const i64 cx = c[0] - 1;
  const i64 cy = c[1] - 1;
  const i64 cz = c[2] - 1;
  data.cases.resize(static_cast<std::size_t>(cx * cy * cz));
  std::uint8_t* out = data.cases.data();
  for (i64 z = 0; z < cz; ++z) {
    for (i64 y = 0; y < cy; ++y) {
      const std::uint8_t* r0 = in.data() + y * sy + z * sz;  // corners 0, 1
      const std::uint8_t* r1 = r0 + sy;                      // corners 2, 3
      const std::uint8_t* r2 = r0 + sz;                      // corners 4, 5
      const std::uint8_t* r3 = r2 + sy;                      // corners 6, 7
      for (i64 x = 0; x < cx; ++x) {
        *out++ = static_cast<std::uint8_t>(r0[x] | (r0[x + 1] << 1) | (r1[x] << 2) |
                                           (r1[x + 1] << 3) | (r2[x] << 4) | (r2[x + 1] << 5) |
                                           (r3[x] << 6) | (r3[x + 1] << 7));
      }
    }
  }

  // Owned crossing edges, in ascending key order (point index, then axis): from p0 along dir.
  std::vector<Vec3> p0;
  std::vector<Vec3> dir;
  std::vector<double> fa;
  std::vector<double> fb;
  const std::array<i64, 3> step{1, sy, sz};
  for (i64 z = 0; z < oe[2]; ++z) {
    for (i64 y = 0; y < oe[1]; ++y) {
      const bool inner_yz = y + 1 < c[1] && z + 1 < c[2];
      for (i64 x = 0; x < oe[0]; ++x) {
        const i64 l = x + y * sy + z * sz;
        // Fast reject when all three edges from this point exist and none crosses.
        if (inner_yz && x + 1 < c[0] && in[l] == in[l + 1] && in[l] == in[l + sy] &&
            in[l] == in[l + sz]) {
          continue;
        }
        const std::array<i64, 3> p{lo[0] + x, lo[1] + y, lo[2] + z};
        for (int a = 0; a < 3; ++a) {
          if (p[a] >= g.n[a] || in[l] == in[l + step[a]]) continue;
          data.keys.push_back(static_cast<std::uint64_t>(g.point_index(p[0], p[1], p[2])) * 3 +
                              static_cast<std::uint64_t>(a));
          data.slots.push_back(static_cast<std::uint32_t>(3 * l + a));
          p0.push_back(g.point(p[0], p[1], p[2]));
          dir.push_back(Vec3::Unit(a) * g.h);
          fa.push_back(v[l]);
          fb.push_back(v[l + step[a]]);
        }
      }
    }
  }
  std::uint64_t evaluations = 0;
  data.vertices = detail::find_edge_roots_along(*data.restricted, p0, dir, std::move(fa),
                                                std::move(fb), root_steps, evaluations);
  data.root_evaluations = static_cast<i64>(evaluations);
}

/// Phase 5: the triangles of an active block, with global vertex ids.
void triangulate_block(const Grid& g, const BlockStore& blocks, i64 b, BlockData& data) {
  const auto bc = g.block_coords(b);
  std::array<i64, 3> lo{};
  std::array<i64, 3> c{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = g.lo(bc[a]);
    c[a] = g.hi(a, bc[a]) - lo[a] + 1;
  }
  const i64 sy = c[0];
  const i64 sz = c[0] * c[1];
  // Vertex id per (local closed-range point, axis): this block's own edges directly, edges owned
  // by an upper neighbour looked up (once) in its sorted keys.
  constexpr std::uint32_t kUnknown = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> vid(static_cast<std::size_t>(3 * sz * c[2]), kUnknown);
  const std::size_t own_base = data.base;
  for (std::size_t q = 0; q < data.slots.size(); ++q)
    vid[data.slots[q]] = static_cast<std::uint32_t>(own_base + q);
  auto lookup = [&](i64 l, int a) -> std::uint32_t {
    std::uint32_t& id = vid[static_cast<std::size_t>(3 * l + a)];
    if (id != kUnknown) return id;
    const i64 i = lo[0] + l % sy;
    const i64 j = lo[1] + (l / sy) % c[1];
    const i64 k = lo[2] + l / sz;
    const std::uint64_t key =
        static_cast<std::uint64_t>(g.point_index(i, j, k)) * 3 + static_cast<std::uint64_t>(a);
    const BlockData& owner = blocks[g.block_index(g.owner(0, i), g.owner(1, j), g.owner(2, k))];
    const auto& keys = owner.keys;
    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
    if (it == keys.end() || *it != key) {
      throw Failure("marching_cubes: internal error: crossing edge without a vertex");
    }
    id = static_cast<std::uint32_t>(owner.base + static_cast<std::size_t>(it - keys.begin()));
    return id;
  };
  // Local offset of each cell corner.
  std::array<i64, 8> corner{};
  for (int q = 0; q < 8; ++q) corner[q] = (q & 1) + ((q >> 1) & 1) * sy + (q >> 2) * sz;
  const i64 cx = c[0] - 1;
  const i64 cy = c[1] - 1;
  const i64 cz = c[2] - 1;
  const std::uint8_t* cs = data.cases.data();
  for (i64 z = 0; z < cz; ++z) {
    for (i64 y = 0; y < cy; ++y) {
      for (i64 x = 0; x < cx; ++x) {
        const unsigned cube = *cs++;
        const int count = kMcTriangleCount[cube];
        if (count == 0) continue;
        const i64 l = x + y * sy + z * sz;
        for (int t = 0; t < count; ++t) {
          std::array<std::uint32_t, 3> tri{};
          for (int k = 0; k < 3; ++k) {
            // Entries below the count are edge ids 0..11 (the -1 padding is never read).
            // NOLINTNEXTLINE(bugprone-signed-char-misuse)
            const int e = kMcTriangles[cube][3 * t + k];
            tri[k] = lookup(l + corner[kMcEdgeCorners[e][0]], e / 4);
          }
          data.triangles.push_back(tri);
        }
      }
    }
  }
  data.cases.clear();
  data.cases.shrink_to_fit();
}

}  // namespace

void MarchingCubesOptions::validate() const {
  if (!std::isfinite(cell_size) || cell_size < 0.0) {
    throw InvalidArgument("MarchingCubesOptions.cell_size must be finite and >= 0, got " +
                          std::to_string(cell_size));
  }
  if (resolution < kMinResolution || resolution > kMaxResolution) {
    throw InvalidArgument("MarchingCubesOptions.resolution must be in " +
                          range_text(kMinResolution, kMaxResolution) + ", got " +
                          std::to_string(resolution));
  }
  if (!box.isEmpty() && (!box.min().allFinite() || !box.max().allFinite())) {
    throw InvalidArgument("MarchingCubesOptions.box must be finite");
  }
  if (root_steps < 0 || root_steps > 64) {
    throw InvalidArgument("MarchingCubesOptions.root_steps must be in [0, 64], got " +
                          std::to_string(root_steps));
  }
  if (block_cells < 2 || block_cells > 64) {
    throw InvalidArgument("MarchingCubesOptions.block_cells must be in [2, 64], got " +
                          std::to_string(block_cells));
  }
  if (max_cells < 1) {
    throw InvalidArgument("MarchingCubesOptions.max_cells must be >= 1, got " +
                          std::to_string(max_cells));
  }
}

TriMesh marching_cubes(const Field& field, const MarchingCubesOptions& options, Context* ctx) {
  return marching_cubes(field, options, ctx, nullptr);
}

TriMesh marching_cubes(const Field& field, const MarchingCubesOptions& options, Context* ctx,
                       MarchingCubesStats* stats) {
  options.validate();
  MarchingCubesStats st;
  bool empty = false;
  const Grid g = make_grid(field, options, empty);
  TriMesh mesh;
  if (empty) {
    if (stats != nullptr) *stats = st;
    return mesh;
  }
  const double iso = field.iso();
  const i64 nblocks = g.block_count();
  const auto nbu = static_cast<std::size_t>(nblocks);
  // The least this run holds at once: a state and a wake flag per block, and three slabs of
  // block records (the values, cases and vertices of active blocks come on top).
  check_memory(ctx,
               2.0 * static_cast<double>(nblocks) +
                   3.0 * static_cast<double>(g.nb[0] * g.nb[1]) * sizeof(BlockData),
               "marching_cubes: a grid of " + std::to_string(g.n[0]) + " x " +
                   std::to_string(g.n[1]) + " x " + std::to_string(g.n[2]) + " cells",
               "use a lower resolution or a larger cell size");
  const auto start_budget = static_cast<double>(memory_budget(ctx));
  auto progress = [&](double f) {
    if (ctx != nullptr) ctx->report("marching cubes", f);
  };
  progress(0.0);

  // Phase 1: which blocks can hold the surface.
  std::vector<BlockState> state(nbu, BlockState::kActive);
  if (options.use_bounds) {
    parallel::for_each(
        nbu, 16,
        [&](std::size_t b) {
          const Interval r = field.bound(g.block_box(g.block_coords(static_cast<i64>(b))));
          if (r.straddles(iso)) return;
          state[b] = r.hi <= iso ? BlockState::kOutside : BlockState::kInside;
        },
        ctx);
  }
  // Two touching skipped blocks of opposite sides contradict each other (their shared points
  // cannot be both inside and outside): only a non-conservative bound does that. Evaluate both,
  // so that every point shared with a skipped block has one forced side.
  i64 conflicts = 0;
  {
    std::vector<char> wake(nbu, 0);
    parallel::for_each(
        nbu, 64,
        [&](std::size_t b) {
          if (state[b] == BlockState::kActive) return;
          g.for_each_block_around(static_cast<i64>(b), [&](i64 nbr) {
            const BlockState other = state[static_cast<std::size_t>(nbr)];
            if (other != BlockState::kActive && other != state[b]) wake[b] = 1;
          });
        },
        ctx);
    for (std::size_t b = 0; b < nbu; ++b) {
      if (wake[b] == 0) continue;
      state[b] = BlockState::kActive;
      ++conflicts;
    }
  }
  // A block must evaluate its owned points when it or a lower neighbour sharing them is active.
  auto is_active = [&](i64 b) { return state[static_cast<std::size_t>(b)] == BlockState::kActive; };
  auto is_needed = [&](i64 b) {
    const auto bc = g.block_coords(b);
    for (int d = 0; d < 8; ++d) {
      const i64 x = bc[0] - (d & 1);
      const i64 y = bc[1] - ((d >> 1) & 1);
      const i64 z = bc[2] - (d >> 2);
      if (x >= 0 && y >= 0 && z >= 0 && is_active(g.block_index(x, y, z))) return true;
    }
    return false;
  };
  const i64 per_slab = g.nb[0] * g.nb[1];
  auto slab_blocks = [&](i64 z, auto&& keep) {
    std::vector<i64> list;
    for (i64 b = z * per_slab; b < (z + 1) * per_slab; ++b)
      if (keep(b)) list.push_back(b);
    return list;
  };

  progress(0.1);

  // Slab pipeline along z. Slab z is classified once the values of slabs z and z + 1 exist, and
  // triangulated once slab z + 1 is classified (its edges' ids are then known); ids are given
  // in block order, which is slab order. Only three slabs of block data are alive at a time.
  BlockStore blocks(g);
  std::size_t nverts = 0;
  i64 active_blocks = 0;
  auto evaluate_slab = [&](i64 z) {
    const std::vector<i64> list = slab_blocks(z, is_needed);
    blocks.slab(z);
    parallel::for_each(
        list.size(), 1,
        [&](std::size_t q) { evaluate_owned(field, g, state, list[q], blocks[list[q]]); }, ctx);
  };
  auto classify_slab = [&](i64 z) {
    const std::vector<i64> list = slab_blocks(z, is_active);
    parallel::for_each(
        list.size(), 1,
        [&](std::size_t q) {
          classify_block(g, blocks, iso, options.root_steps, list[q], blocks[list[q]]);
        },
        ctx);
    for (const i64 b : list) {
      BlockData& d = blocks[b];
      d.base = nverts;
      nverts += d.keys.size();
      const auto bc = g.block_coords(b);
      st.cells_visited += (g.hi(0, bc[0]) - g.lo(bc[0])) * (g.hi(1, bc[1]) - g.lo(bc[1])) *
                          (g.hi(2, bc[2]) - g.lo(bc[2]));
    }
    active_blocks += static_cast<i64>(list.size());
    if (nverts >= std::numeric_limits<std::uint32_t>::max()) {
      throw Failure("marching_cubes: more than 2^32 - 1 vertices; use a coarser cell size");
    }
    // The mesh so far (a position and about two triangles per vertex) against the budget of
    // the start: a surface too fine for the memory stops here, not in the system's OOM killer.
    const double mesh_bytes = 48.0 * static_cast<double>(nverts);
    if (start_budget > 0 && mesh_bytes > start_budget) {
      check_memory(ctx, mesh_bytes,
                   "marching_cubes: the mesh of " + std::to_string(nverts) + " vertices so far",
                   "use a lower resolution or a larger cell size");
    }
  };
  auto finish_slab = [&](i64 z) {
    const std::vector<i64> list = slab_blocks(z, is_active);
    parallel::for_each(
        list.size(), 1,
        [&](std::size_t q) { triangulate_block(g, blocks, list[q], blocks[list[q]]); }, ctx);
    for (i64 b = z * per_slab; b < (z + 1) * per_slab; ++b) {
      const BlockData& d = blocks[b];
      mesh.positions.insert(mesh.positions.end(), d.vertices.begin(), d.vertices.end());
      mesh.triangles.insert(mesh.triangles.end(), d.triangles.begin(), d.triangles.end());
      st.corner_evaluations += d.evaluations;
      st.root_evaluations += d.root_evaluations;
      st.sign_overrides += d.overrides;
    }
    blocks.release(z);
  };
  const i64 nbz = g.nb[2];
  evaluate_slab(0);
  for (i64 z = 0; z < nbz; ++z) {
    if (z + 1 < nbz) evaluate_slab(z + 1);
    classify_slab(z);
    // Slab z's values are no longer needed (slab z - 1 was classified before).
    for (i64 b = z * per_slab; b < (z + 1) * per_slab; ++b) {
      BlockData& d = blocks[b];
      std::vector<double>().swap(d.owned_values);
      d.restricted.reset();
    }
    if (z > 0) finish_slab(z - 1);
    progress(0.1 + 0.9 * static_cast<double>(z + 1) / static_cast<double>(nbz));
  }
  finish_slab(nbz - 1);

  st.cell_size = g.h;
  for (int a = 0; a < 3; ++a) st.grid_cells[a] = g.n[a];
  st.cells_total = g.n[0] * g.n[1] * g.n[2];
  st.cells_skipped = st.cells_total - st.cells_visited;
  st.blocks_total = nblocks;
  st.blocks_skipped = nblocks - active_blocks;
  st.crossing_edges = static_cast<i64>(nverts);
  st.bound_conflicts = conflicts;
  if (stats != nullptr) *stats = st;
  progress(1.0);
  return mesh;
}

}  // namespace ramiform
