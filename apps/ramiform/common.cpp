// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "common.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <optional>

#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/numbers.h"
#include "ramiform/io/atomic_file.h"

namespace ramiform::cli {

void add_common_options(CLI::App& app, CommonOptions& options) {
  app.add_option("--threads", options.threads,
                 "worker threads (0 = all cores); results never depend on it")
      ->check(CLI::Range(0, Context::kMaxThreads));
  app.add_option("--stats", options.stats_path,
                 "write run statistics (per-stage seconds, counts, field_evals) to this JSON file");
  app.add_option_function<std::string>(
         "--max-memory",
         [&options](const std::string& text) {
           const std::optional<std::uint64_t> bytes = parse_memory_size(text);
           if (!bytes) {
             throw CLI::ValidationError(
                 "--max-memory", "expected a size such as 512M, 8G or 2GiB, got '" + text + "'");
           }
           options.max_memory = *bytes;
         },
         "memory budget: a run whose estimated peak exceeds it is refused before it starts "
         "(exit 2); e.g. 512M, 8G, 2GiB (default: the memory available when the run starts)")
      ->type_name("SIZE");
}

RunScope::RunScope(const CommonOptions& options) : context_(options.threads) {
  context_.set_max_memory(options.max_memory);
}

RunScope::~RunScope() = default;

void add_field_options(CLI::App& app, FieldFlags& flags) {
  app.add_option_function<std::string>(
         "--surface",
         [&flags](const std::string& v) {
           flags.surface = v;
           flags.surface_given = true;
         },
         "convolution (Cauchy kernel integrated along the skeleton, default), distance (kernel "
         "of the distance to each segment) or equipotential (potential of point charges along "
         "the skeleton, Gruber & Wallner 2014; the default of --method particles)")
      ->check(CLI::IsMember({"convolution", "distance", "equipotential"}));
  app.add_option("--kernel", flags.kernel,
                 "kernel: cauchy[:s*r] (convolution), wyvill, blinn[:B], metaball, "
                 "inverse-power[:alpha] (distance); default cauchy / wyvill");
  app.add_option("--iso", flags.iso, "iso value (default: the kernel's own, 0.5 or 1)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--obj-radius", flags.obj_radius,
                 "radius of every node of an OBJ skeleton (OBJ files carry no radius)")
      ->check(CLI::PositiveNumber);
  EquipotentialOptions& e = flags.equipotential;
  auto mark = [&flags](double& target) {
    return [&flags, &target](double v) {
      target = v;
      flags.equipotential_flags = true;
    };
  };
  app.add_option_function<double>(
         "--alpha", mark(e.alpha),
         with_default("equipotential: field exponent alpha, potential q / r^(alpha - 1); higher "
                      "is more cylindrical, sharper blends",
                      e.alpha, 2, 16))
      ->check(CLI::Range(2.0, 16.0));
  app.add_option_function<double>(
         "--charge-spacing", mark(e.charge_spacing),
         "equipotential: distance d_c between charges along an edge (model units); default per "
         "edge " +
             format_number(e.spacing_factor) + " times its smaller node radius")
      ->check(CLI::PositiveNumber);
  app.add_option_function<double>(
         "--charge", mark(e.charge),
         "equipotential: one charge value for every edge (the paper's figures); default per "
         "edge from the node radii (--fit-radii fits them to the radii)")
      ->check(CLI::PositiveNumber);
  app.add_option_function<double>(
         "--lambda", mark(e.lambda),
         "equipotential: the iso value lambda; default estimated by the paper's eq. 2")
      ->check(CLI::PositiveNumber);
  app.add_option_function<double>(
         "--lambda-scale", mark(e.lambda_scale),
         with_default("equipotential: multiplies lambda (the paper's Figure 4: 1, 0.5, 0.2; "
                      "smaller is thicker)",
                      e.lambda_scale))
      ->check(CLI::PositiveNumber);
  app.add_flag_function(
      "--open-ends",
      [&flags](std::int64_t) {
        flags.equipotential.open_ends = true;
        flags.equipotential_flags = true;
      },
      "equipotential: open, sharp-edged ends at every leaf (the particle mesh gets one boundary "
      "loop per leaf); a node's \"end\": \"open\" in skeleton JSON opens one");
}

SkeletonFieldOptions field_options(const FieldFlags& flags) {
  SkeletonFieldOptions o;
  if (flags.surface == "equipotential") {
    (void)equipotential_options(flags);
    return o.resolved();
  }
  o.surface = flags.surface == "distance" ? SurfaceKind::kDistance : SurfaceKind::kConvolution;
  if (!flags.kernel.empty()) {
    o.kernel = parse_kernel(flags.kernel);
  } else {
    o.kernel = Kernel{
        o.surface == SurfaceKind::kDistance ? KernelKind::kWyvill : KernelKind::kCauchy, 0.0};
  }
  if (o.surface == SurfaceKind::kConvolution && o.kernel.kind != KernelKind::kCauchy) {
    throw InvalidArgument("--kernel " + flags.kernel +
                          ": convolution surfaces use the cauchy kernel; add --surface distance "
                          "for other kernels");
  }
  o.iso = flags.iso;
  return o.resolved();
}

const EquipotentialOptions* equipotential_options(const FieldFlags& flags) {
  if (flags.surface != "equipotential") {
    if (flags.equipotential_flags) {
      throw InvalidArgument(
          "--alpha, --charge-spacing, --charge, --lambda, --lambda-scale and "
          "--open-ends apply to --surface equipotential (or --method "
          "particles) only");
    }
    return nullptr;
  }
  if (!flags.kernel.empty()) {
    throw InvalidArgument(
        "--kernel applies to convolution and distance surfaces, not to "
        "--surface equipotential");
  }
  if (flags.iso != 0.0) {
    throw InvalidArgument("--iso: the equipotential surface's iso value is --lambda");
  }
  return &flags.equipotential;
}

SkeletonReadOptions read_options(const FieldFlags& flags) {
  SkeletonReadOptions r;
  r.obj_radius = flags.obj_radius;
  return r;
}

std::string with_default(const std::string& text, double value) {
  return text + default_text(value);
}

std::string with_default(const std::string& text, double value, double min, double max) {
  return text + default_text(value, min, max);
}

StageTimer::StageTimer() : start_(Clock::now()), last_(start_) {}

void StageTimer::lap(const std::string& name) {
  const auto now = Clock::now();
  seconds_[name] = std::chrono::duration<double>(now - last_).count();
  last_ = now;
}

nlohmann::json StageTimer::seconds() const {
  nlohmann::json s = seconds_;
  s["total"] = std::chrono::duration<double>(Clock::now() - start_).count();
  return s;
}

void write_stats(const std::string& path, const nlohmann::json& stats) {
  if (path.empty()) return;
  write_file_atomically(path, [&](std::ostream& out) { out << stats.dump(2) << '\n'; });
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

void check_output_path(const std::string& path, std::span<const char* const> extensions) {
  if (path.empty()) return;
  const std::filesystem::path p(path);
  const std::string ext = lower_extension(path);
  if (!extensions.empty() &&
      std::none_of(extensions.begin(), extensions.end(), [&](const char* e) { return ext == e; })) {
    std::string list;
    for (const char* e : extensions) list += (list.empty() ? "" : ", ") + std::string(e);
    throw InvalidArgument("cannot write '" + path + "': unknown format '" + ext +
                          "' (supported: " + list + ")");
  }
  const std::filesystem::path dir =
      p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InvalidArgument("cannot write '" + path + "': directory '" + dir.string() +
                          "' does not exist");
  }
}

}  // namespace ramiform::cli
