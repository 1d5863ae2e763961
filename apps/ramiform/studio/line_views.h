// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Line mode of the studio (POST /api/lines): pen-and-ink drawings of a run's shape for the
// page's camera, after Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set
// Implicits" (GRAPP), §3 (drawings that follow the camera: the particles stay, only the
// view-dependent lines are found again). The particles of (run, shape, count) are spread once
// and kept, with the shape's feature lines (view-independent); every camera then only draws
// with ramiform's line drawing (lines/lines.h), the defaults of `ramiform draw`, hidden lines
// removed by rays.

#include <array>
#include <cstddef>
#include <filesystem>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ramiform/field/field.h"

namespace ramiform::studio {

/// The page's camera, in its +Y-up frame (the .glb's).
struct PageCamera {
  std::array<double, 3> eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 30;  ///< vertical
  int width = 800, height = 600;
};

class LineViews {
 public:
  /// Most particle systems kept (the oldest is dropped first).
  static constexpr std::size_t kMaxCached = 6;
  static constexpr std::size_t kMaxCount = 200'000;

  /// `scratch`: a directory for the SVG writer's file; `threads`: Context threads.
  LineViews(std::filesystem::path scratch, int threads);

  /// The SVG drawing of `field` (shape `shape` of run `run`) for `camera` with the line kinds
  /// `kinds` ("silhouette", "suggestive", "feature"), from `count` particles. Throws
  /// InvalidArgument for a bad camera, kind or count.
  [[nodiscard]] std::string draw(const std::string& run, const std::string& shape,
                                 const FieldPtr& field, const PageCamera& camera,
                                 const std::vector<std::string>& kinds, std::size_t count);

  struct Entry;

 private:
  std::shared_ptr<Entry> entry(const std::string& key);

  std::filesystem::path scratch_;
  int threads_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<Entry>>> cache_;  // newest first
  std::size_t next_file_ = 0;
};

/// The library's +Z-up point of a page (+Y-up) point: (x, y, z) -> (x, -z, y).
[[nodiscard]] Vec3 from_page(const std::array<double, 3>& p);

}  // namespace ramiform::studio
