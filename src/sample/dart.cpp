// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/dart.h"

#include <vector>

#include "sample/candidate_blocks.h"
#include "sample/point_grid.h"

namespace ramiform::sample_detail {

namespace {

/// What a candidate needs before the acceptance pass.
enum class State : std::uint8_t {
  kReject = 0,    ///< the cache rules it out
  kEvaluate = 1,  ///< its value decides
  kAccept = 2,    ///< in a full cell or cube: in the target without evaluation
};

/// One block of dart throwing: draw and pre-classify the candidates, evaluate those that need
/// it in parallel, then accept in candidate order. The buffers live across blocks.
class DartBlock {
 public:
  DartBlock(const Field& field, const Region& region, const DartSpec& spec, Context* ctx,
            SampleStats& st)
      : field_(field),
        region_(region),
        spec_(spec),
        ctx_(ctx),
        st_(st),
        needs_value_(static_cast<bool>(spec.density)),
        cand_(kBlock),
        coin_(kBlock),
        state_(kBlock),
        too_close_(kBlock),
        value_(kBlock) {}

  bool operator()(Rng& rng, std::size_t n, PointGrid& near, PointSet& out) {
    draw(rng, n, near);
    evaluate_parallel(field_, eval_points_, eval_values_, nullptr, ctx_);
    for (std::size_t e = 0; e < eval_index_.size(); ++e) value_[eval_index_[e]] = eval_values_[e];
    return accept(n, near, out);
  }

 private:
  [[nodiscard]] State cache_state(const Vec3& p) const {
    switch (spec_.cache->classify(p)) {
      case FieldCache::Verdict::kReject:
        return State::kReject;
      case FieldCache::Verdict::kAccept:
        return State::kAccept;
      case FieldCache::Verdict::kEvaluate:
        break;
    }
    return State::kEvaluate;
  }

  void draw(Rng& rng, std::size_t n, const PointGrid& near) {
    eval_points_.clear();
    eval_index_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      bool full = false;
      cand_[i] = region_.draw(rng, full);
      coin_[i] = rng.uniform();
      // Points accepted before this block are fixed: a candidate too close to them fails
      // whatever its value, so it needs no evaluation (same outcome as testing in order).
      too_close_[i] = near.has_near(cand_[i]) ? 1 : 0;
      state_[i] = full ? State::kAccept : State::kEvaluate;
      if (too_close_[i] == 0 && state_[i] == State::kEvaluate && spec_.cache != nullptr) {
        state_[i] = cache_state(cand_[i]);
      }
      if (too_close_[i] == 0 &&
          (state_[i] == State::kEvaluate || (state_[i] == State::kAccept && needs_value_))) {
        eval_index_.push_back(static_cast<std::uint32_t>(i));
        eval_points_.push_back(cand_[i]);
      }
    }
  }

  /// Counts a too-close candidate; true when that saturates the run.
  bool fail() {
    if (spec_.max_failures != 0 && ++failures_ >= spec_.max_failures) {
      st_.saturated = true;
      return true;
    }
    return false;
  }

  bool accept(std::size_t n, PointGrid& near, PointSet& out) {
    bool stop = false;
    for (std::size_t i = 0; i < n && !stop; ++i) {
      if (too_close_[i] != 0) {
        stop = fail();
        continue;
      }
      if (state_[i] == State::kReject) continue;
      if (state_[i] == State::kEvaluate && !spec_.target.contains(value_[i])) continue;
      if (needs_value_ && !(coin_[i] < spec_.density(value_[i]))) continue;
      // Points accepted earlier in this block were not known when draw() looked.
      if (near.has_near(cand_[i])) {
        stop = fail();
        continue;
      }
      failures_ = 0;
      near.add(cand_[i]);
      out.positions.push_back(cand_[i]);
      if (out.positions.size() == spec_.count) stop = true;
    }
    return stop;
  }

  const Field& field_;
  const Region& region_;
  const DartSpec& spec_;
  Context* ctx_;
  SampleStats& st_;
  bool needs_value_;
  std::size_t failures_ = 0;  ///< consecutive too-close candidates, across blocks
  std::vector<Vec3> cand_;
  std::vector<double> coin_;
  std::vector<State> state_;
  std::vector<std::uint8_t> too_close_;
  std::vector<double> value_;
  std::vector<Vec3> eval_points_;
  std::vector<double> eval_values_;
  std::vector<std::uint32_t> eval_index_;
};

}  // namespace

PointSet run_dart(const Field& field, const Region& region, const Aabb& box, const DartSpec& spec,
                  std::uint64_t seed, Context* ctx, SampleStats& st) {
  DartBlock block(field, region, spec, ctx, st);
  return run_blocks(region, box, spec.min_distance, spec.count, spec.max_attempts, seed,
                    spec.stream, ctx, st, block);
}

double estimate_volume(const Field& field, const Region& region, const Target& target,
                       std::uint64_t seed, Context* ctx) {
  if (region.is_empty()) return 0.0;
  constexpr std::size_t kPilot = 8192;
  Rng rng = Rng(seed).split(0x70696c6f74ULL);  // "pilot"
  std::vector<Vec3> pts;
  std::size_t full_count = 0;
  for (std::size_t i = 0; i < kPilot; ++i) {
    bool full = false;
    const Vec3 p = region.draw(rng, full);
    if (full) {
      ++full_count;
    } else {
      pts.push_back(p);
    }
  }
  std::vector<double> values;
  evaluate_parallel(field, pts, values, nullptr, ctx);
  std::size_t in = full_count;
  for (const double v : values) in += target.contains(v) ? 1 : 0;
  return region.volume() * double(in) / double(kPilot);
}

}  // namespace ramiform::sample_detail
