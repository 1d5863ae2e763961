// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Line mode of the studio (POST /api/lines): pen-and-ink drawings of a run's shape for the
// page's camera, after Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set
// Implicits" (GRAPP), §3 (drawings that follow the camera: the particles stay, only the
// view-dependent lines are found again). The particles of (run, shape, count) are spread once
// and kept, with the shape's feature lines and the particles' k-d tree and surfel radii
// (view-independent: a ParticleLookup); every camera then only draws
// with ramiform's line drawing (lines/lines.h), the defaults of `ramiform draw`, hidden lines
// removed by rays.

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ramiform/field/field.h"
#include "ramiform/lines/camera.h"
#include "ramiform/lines/lines.h"

namespace ramiform::studio {

/// The page's camera, in its +Y-up frame (the .glb's).
struct PageCamera {
  std::array<double, 3> eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 30;  ///< vertical
  int width = 800, height = 600;
};

/// What the newest drawing is doing, for the page's progress bar (GET /api/lines/progress).
struct LinesProgress {
  bool busy = false;    ///< a drawing is being made
  std::string stage;    ///< the library's stage ("particles: cells", ...), or "lines"
  double fraction = 0;  ///< of that stage, 0..1
  double seconds = 0;   ///< since the drawing started
};

class LineViews {
 public:
  /// Most particle systems kept (the oldest is dropped first).
  static constexpr std::size_t kMaxCached = 6;
  static constexpr std::size_t kMaxCount = 200'000;

  /// `scratch`: a directory for the SVG writer's file; `threads`: Context threads;
  /// `max_memory`: the memory budget of each drawing (Context::set_max_memory; 0: what is
  /// available), which refuses particle counts that cannot fit.
  LineViews(std::filesystem::path scratch, int threads, std::uint64_t max_memory = 0);
  /// Waits for the drawings asked for, then stops the drawing thread.
  ~LineViews();
  LineViews(const LineViews&) = delete;
  LineViews& operator=(const LineViews&) = delete;

  /// The SVG drawing of `field` (shape `shape` of run `run`) for `camera` with the line kinds
  /// `kinds` ("silhouette", "suggestive", "feature"), from `count` particles. Throws
  /// InvalidArgument for a bad camera, kind or count.
  /// `surfels`: hidden lines by the paper's depth buffer of disks (tens of milliseconds, may
  /// hide bits of silhouettes) instead of exact rays (the page's quick drawing while the camera
  /// moves, followed by the exact one).
  /// Drawings run one at a time, in the order asked for, on one thread of the views' own (the
  /// skeleton field keeps its candidate lists per thread: drawn on whichever of the server's
  /// request threads took the request, a camera of the studio's tree cost a third more); the
  /// calling thread waits for its drawing.
  [[nodiscard]] std::string draw(const std::string& run, const std::string& shape,
                                 const FieldPtr& field, const PageCamera& camera,
                                 const std::vector<std::string>& kinds, std::size_t count,
                                 bool surfels = false);

  /// The newest drawing's progress (the first drawing of a shape spreads its particles, which
  /// takes seconds on a large tree; later ones only draw).
  [[nodiscard]] LinesProgress progress() const;

  struct Entry;

 private:
  std::shared_ptr<Entry> entry(const std::string& key);
  // Runs `work` on the drawing thread (started on first use) and returns its result.
  std::string on_worker(const std::function<std::string()>& work);
  void serve();  // the drawing thread
  std::string render(const std::string& run, const std::string& shape, const FieldPtr& field,
                     const PageCamera& page, const LineOptions& options, const Camera& camera,
                     std::size_t count);
  // Progress of drawing `ticket`; only the newest drawing's is kept.
  void report(std::uint64_t ticket, const std::string& stage, double fraction);

  std::filesystem::path scratch_;
  int threads_;
  std::uint64_t max_memory_;
  mutable std::mutex progress_mutex_;
  std::uint64_t newest_ = 0;  // ticket of the newest drawing started
  LinesProgress progress_;
  std::chrono::steady_clock::time_point progress_start_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<Entry>>> cache_;  // newest first
  std::size_t next_file_ = 0;
  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<std::packaged_task<std::string()>> queue_;
  bool stopping_ = false;
  std::thread worker_;
};

/// The library's +Z-up point of a page (+Y-up) point: (x, y, z) -> (x, -z, y).
[[nodiscard]] Vec3 from_page(const std::array<double, 3>& p);

}  // namespace ramiform::studio
