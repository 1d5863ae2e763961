// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Shared pieces of the subcommands: thread and stats options, field options from flags, timers,
// and the JSON stats file.

#include <CLI/CLI.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "ramiform/core/context.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform::cli {

/// Options every subcommand takes.
struct CommonOptions {
  int threads = 0;               ///< --threads N (0 = all cores)
  std::string stats_path;        ///< --stats FILE.json
  std::uint64_t max_memory = 0;  ///< --max-memory SIZE in bytes (0 = the available memory)
};
void add_common_options(CLI::App& app, CommonOptions& options);

/// The Context of one command run: --threads and --max-memory, passed to every library call (no
/// global setting).
class RunScope {
 public:
  explicit RunScope(const CommonOptions& options);
  ~RunScope();
  RunScope(const RunScope&) = delete;
  RunScope& operator=(const RunScope&) = delete;
  Context& context() { return context_; }

 private:
  Context context_;
};

/// Options that pick the field built from a skeleton: --surface, --kernel, --iso, --obj-radius,
/// and for --surface equipotential --alpha, --charge-spacing, --charge, --lambda,
/// --lambda-scale, --open-ends.
struct FieldFlags {
  std::string surface = "convolution";
  std::string kernel;  // empty: cauchy for convolution, wyvill for distance
  double iso = 0.0;
  double obj_radius = 0.0;
  EquipotentialOptions equipotential;  // --surface equipotential
  bool surface_given = false;          // --surface was on the command line
  bool equipotential_flags = false;    // one of the equipotential options was given
};
void add_field_options(CLI::App& app, FieldFlags& flags);
/// Throws InvalidArgument naming the flag on a bad value. For --surface equipotential the
/// result is unused (the surface is described by equipotential_options()).
[[nodiscard]] SkeletonFieldOptions field_options(const FieldFlags& flags);
/// The equipotential surface's options with --surface equipotential, else null (InvalidArgument
/// when equipotential options come without it, or --kernel/--iso with it).
[[nodiscard]] const EquipotentialOptions* equipotential_options(const FieldFlags& flags);
[[nodiscard]] SkeletonReadOptions read_options(const FieldFlags& flags);

/// `text` + " (default D)" or " (default D, MIN–MAX)": the one way an option's help states the
/// default and the range of its options struct. docs/cli.md writes them the same way, and
/// tests/cli/help_docs_test.cpp reads both. Numbers print in their shortest exact form.
[[nodiscard]] std::string with_default(const std::string& text, double value);
[[nodiscard]] std::string with_default(const std::string& text, double value, double min,
                                       double max);

/// Wall-clock stage timer collecting seconds per stage into a JSON object.
class StageTimer {
 public:
  StageTimer();
  /// Ends the current stage under `name` and starts the next one.
  void lap(const std::string& name);
  /// {"stage": seconds, ..., "total": seconds}.
  [[nodiscard]] nlohmann::json seconds() const;

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_, last_;
  nlohmann::json seconds_ = nlohmann::json::object();
};

/// The output formats of write_skeleton and write_mesh, for check_output_path.
inline constexpr std::array<const char*, 3> kSkeletonFormats{".json", ".ply", ".obj"};
inline constexpr std::array<const char*, 4> kMeshFormats{".ply", ".obj", ".off", ".glb"};

/// The extension of `path` in lower case, with its dot (".ply"; "" when there is none).
[[nodiscard]] std::string lower_extension(const std::string& path);

/// Checked before the work starts, so that a long run does not end in a failed write:
/// throws InvalidArgument when `path`'s directory does not exist or (with `extensions`, lower
/// case with the dot) its extension is none of them. An empty path passes.
void check_output_path(const std::string& path, std::span<const char* const> extensions = {});

/// part / whole, 0 for an empty whole (e.g. the share of triangles below an angle).
[[nodiscard]] inline double share(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

/// Writes `stats` to `path` (atomically) unless path is empty.
void write_stats(const std::string& path, const nlohmann::json& stats);

}  // namespace ramiform::cli
