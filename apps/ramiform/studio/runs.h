// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// The studio's script runs (docs/studio_api.md): one at a time in a background thread, the
// latest wins; each a fresh ScriptSession writing into OUT/runs/rN/ with the CLI's sandbox, a
// time and memory budget, progress and cancel through its Context. A finished run lists its
// outputs and the objects the page can show (meshes as .glb, skeletons and points as JSON,
// drawings as SVG), and keeps the fields of its shapes for line drawings.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/field/field.h"

namespace ramiform::studio {

/// How runs are made.
struct RunSettings {
  std::filesystem::path out_dir;    ///< OUT: runs go to OUT/runs/rN/, view files to OUT/cache/
  std::filesystem::path input_dir;  ///< relative input paths of scripts
  std::string script_name = "script.rf";  ///< the file name errors and logs use
  double timeout_seconds = 300;           ///< a run longer than this is cancelled (failed)
  std::uint64_t max_memory = 0;           ///< Context::set_max_memory (0: what is available)
  int threads = 0;                        ///< Context threads (0: all cores)
};

/// What the view of an object is: a file to send or bytes made in memory.
struct ViewData {
  std::string mime;
  std::string body;
};

class RunManager {
 public:
  /// Most runs remembered (older ones answer 404; their directories stay, but for drafts', which
  /// are removed: a dragged slider makes many).
  static constexpr std::size_t kMaxRuns = 64;
  /// Most runs whose shapes are kept for line drawings.
  static constexpr std::size_t kMaxRunsWithShapes = 4;

  explicit RunManager(RunSettings settings);
  ~RunManager();
  RunManager(const RunManager&) = delete;
  RunManager& operator=(const RunManager&) = delete;

  /// Queues a run of `script` with `params` as `--set`, cancelling the running or queued one;
  /// returns its id ("r7").
  /// `draft`: ScriptOptions::draft (a coarse preview while a slider is dragged).
  std::string submit(std::string script, std::map<std::string, std::string> params,
                     bool draft = false);
  /// The run's state as GET /api/run/ID answers it; nullopt for an unknown id.
  [[nodiscard]] std::optional<nlohmann::json> status(const std::string& id) const;
  /// Cancels the run; returns its state afterwards ("cancelled" or the final state); nullopt for
  /// an unknown id.
  std::optional<std::string> cancel(const std::string& id);
  /// The view of object `object` of run `id`; nullopt when either is unknown.
  [[nodiscard]] std::optional<ViewData> view(const std::string& id,
                                             const std::string& object) const;
  /// The output file PATH of run `id`, only when it resolves to a regular file inside the run's
  /// directory.
  [[nodiscard]] std::optional<std::filesystem::path> file(const std::string& id,
                                                          const std::string& path) const;
  /// The field of shape `name` of a finished run (nullptr: unknown run or shape, or a run whose
  /// shapes were released).
  [[nodiscard]] FieldPtr shape(const std::string& id, const std::string& name) const;

  [[nodiscard]] const RunSettings& settings() const { return settings_; }

  struct Run;

 private:
  [[nodiscard]] std::shared_ptr<Run> find(const std::string& id) const;
  void work();
  void watch();
  void execute(Run& run);

  RunSettings settings_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::shared_ptr<Run>> runs_;
  std::deque<std::string> order_;  // ids, oldest first
  std::shared_ptr<Run> pending_;
  std::shared_ptr<Run> current_;
  int next_number_ = 1;
  bool stopping_ = false;
  std::thread worker_;
  std::thread watchdog_;
};

}  // namespace ramiform::studio
