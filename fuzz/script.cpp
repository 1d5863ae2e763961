// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The scene language's fuzz harness (script/script.h), compiled twice (fuzz/CMakeLists.txt):
//
// - RAMIFORM_FUZZ_SCRIPT_PARSE: every line through one session as the shell runs them
//   (an error is reported and the session goes on): tokens, quotes, parameters, command lookup,
//   arguments, options, names and the objects that primitives, operators, transforms and curves
//   define, plus eval/info/list/help. Lines of the commands that mesh, sample, grow or read
//   models (kHeavyCommands) are not run; script_run covers them.
// - RAMIFORM_FUZZ_SCRIPT_RUN: the whole input as `ramiform run` runs a script (stops at the
//   first error, then commits the outputs), every command allowed.
//
// ScriptOptions has no size limits, so the harness caps the work an input may ask for by
// reading it first (plan_script below; docs/fuzzing.md lists the caps) and skips inputs over a
// cap: no harness input may take seconds. Relative input paths resolve in the output directory,
// which starts as a copy of examples/data/ under data/ (so `data/fork.json` works, and a script
// can read what it wrote). An InputError is the documented result of a bad script; any other
// exception or crash is a finding.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "fuzz_support.h"
#include "ramiform/core/context.h"
#include "ramiform/core/numbers.h"
#include "ramiform/script/script.h"

#if defined(RAMIFORM_FUZZ_SCRIPT_PARSE)
constexpr bool kRunWhole = false;
#elif defined(RAMIFORM_FUZZ_SCRIPT_RUN)
constexpr bool kRunWhole = true;
#else
#error "compile with RAMIFORM_FUZZ_SCRIPT_PARSE or RAMIFORM_FUZZ_SCRIPT_RUN (fuzz/CMakeLists.txt)"
#endif

#ifndef RAMIFORM_FUZZ_DATA_DIR
#error "RAMIFORM_FUZZ_DATA_DIR (examples/data) is set by fuzz/CMakeLists.txt"
#endif

namespace ramiform::fuzz {
namespace {

namespace fs = std::filesystem;

// The caps (docs/fuzzing.md). Sizes are those of the script after parameter substitution.
constexpr std::size_t kMaxBytes = 4096;      // script size
constexpr std::size_t kMaxLines = 64;        // lines (also bounds transform chains and depth)
constexpr std::size_t kMaxTokens = 64;       // tokens per line (curve points, operator inputs)
constexpr std::size_t kMaxTokenChars = 256;  // a token after `$NAME` substitution
constexpr std::size_t kMaxLeaves = 32;       // primitives a shape's DAG reaches, counted per path
constexpr double kMaxMagnitude = 1e4;        // |number| anywhere (script_run)
constexpr double kMaxScaleProduct = 1e6;     // product of all `scale` factors (script_run)
constexpr int kMaxResolution = 16;           // save_mesh resolution= (required with mc)
constexpr int kMaxLevels = 0;                // save_mesh levels= (required with tets)
constexpr int kMaxCount = 100;               // point_set_gen / point_set_mesh count= (required)
constexpr int kMaxGrowIterations = 30;       // grow max_iterations= (required)
constexpr int kMaxLsystemIterations = 3;     // lsystem iterations= (required)

// Distributions of point_set_gen whose fixed cost (grids at their defaults, which a script
// cannot change without a .props file) is over a second under ASan + UBSan: skipped.
const std::set<std::string> kSlowDistributions = {"boundary", "near_surface"};

// Commands script_parse does not run (they mesh, sample, grow, read or write models).
const std::set<std::string> kHeavyCommands = {"save_mesh",      "eval_points",
                                              "point_set_gen",  "save_point_set",
                                              "point_set_thin", "load_point_set",
                                              "point_set_mesh", "grow",
                                              "lsystem",        "save_skeleton",
                                              "skeleton",       "mesh_shape",
                                              "mesh",           "rbf",
                                              "variational"};

// Operators: their last positional argument is the result, made of all the others.
const std::set<std::string> kOperators = {"blend",        "sum",  "union",      "intersect",
                                          "intersection", "diff", "difference", "copy"};

// The lines of a script as ScriptSession::run_text splits them: at '\n', the last one possibly
// empty; number() is the 1-based number of the line next() gave last.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (start_ > text_.size()) return false;
    std::size_t end = text_.find('\n', start_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(start_, end - start_);
    start_ = end + 1;
    ++number_;
    return true;
  }
  [[nodiscard]] std::size_t number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t start_ = 0;
  std::size_t number_ = 0;
};

// The scene language's tokenizer (script/session.cpp): blanks separate, "..." quotes, '#'
// outside quotes ends the line. False for an unterminated quote (the line is an error).
bool tokenize(std::string_view line, std::vector<std::string>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    const char c = line[i];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      ++i;
      continue;
    }
    if (c == '#') break;
    if (c == '"') {
      const std::size_t close = line.find('"', i + 1);
      if (close == std::string_view::npos) return false;
      out.emplace_back(line.substr(i + 1, close - i - 1));
      i = close + 1;
    } else {
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' &&
             line[i] != '\n' && line[i] != '#')
        ++i;
      out.emplace_back(line.substr(start, i - start));
    }
  }
  return true;
}

// `$NAME` / `${NAME}` substitution as the session does it. False when a parameter is unknown or
// a brace is open (the line is an error) or the result is over kMaxTokenChars (`too_big`).
bool substitute(const std::string& t, const std::map<std::string, std::string>& params,
                std::string& out, bool& too_big) {
  out.clear();
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] != '$') {
      out += t[i++];
    } else {
      std::size_t start = i + 1;
      std::size_t end = start;
      const bool braced = start < t.size() && t[start] == '{';
      if (braced) {
        end = t.find('}', start);
        if (end == std::string::npos) return false;
        ++start;
      } else {
        while (end < t.size() &&
               (std::isalnum(static_cast<unsigned char>(t[end])) != 0 || t[end] == '_'))
          ++end;
      }
      const auto it = params.find(t.substr(start, end - start));
      if (it == params.end()) return false;
      out += it->second;
      i = braced ? end + 1 : end;
    }
    if (out.size() > kMaxTokenChars) {
      too_big = true;
      return false;
    }
  }
  return true;
}

bool number_of(const std::string& text, double& v) {
  return parse_number(text, v) == NumberStatus::kOk;
}

// True when every number in `text` (comma-separated parts too) is within kMaxMagnitude.
bool small_numbers(const std::string& text) {
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t comma = text.find(',', start);
    if (comma == std::string::npos) comma = text.size();
    double v = 0;
    if (number_of(text.substr(start, comma - start), v) && !(std::abs(v) <= kMaxMagnitude))
      return false;
    start = comma + 1;
  }
  return true;
}

// An integer option that must be given and be at most `max`.
bool capped_option(const std::map<std::string, std::string>& options, const std::string& key,
                   int max) {
  const auto it = options.find(key);
  double v = 0;
  return it != options.end() && number_of(it->second, v) && v <= max;
}

// Reads the script as the session would and decides whether it is within the caps. Conservative:
// the estimate of a shape's size never falls below what the session builds.
bool within_caps(std::string_view text) {
  if (text.size() > kMaxBytes) return false;
  std::map<std::string, std::string> params;
  std::map<std::string, std::size_t> leaves;  // object name -> primitives reached, per path
  double scale_product = 1;
  std::vector<std::string> raw;
  Lines lines(text);
  std::string_view line;
  while (lines.next(line)) {
    if (lines.number() > kMaxLines) return false;
    if (!tokenize(line, raw)) {
      if (kRunWhole) return true;  // the run stops at this line
      continue;
    }
    if (raw.empty()) continue;
    if (raw.size() > kMaxTokens) return false;
    const std::string& command = raw.front();
    // Arguments after substitution, split as the session splits them ('=' after the first
    // character makes an option).
    std::vector<std::string> positional;
    std::map<std::string, std::string> options;
    bool line_fails = false;
    for (std::size_t i = 1; i < raw.size(); ++i) {
      std::string t;
      bool too_big = false;
      if (!substitute(raw[i], params, t, too_big)) {
        if (too_big) return false;
        line_fails = true;
        break;
      }
      const std::size_t eq = t.find('=');
      if (eq != std::string::npos && eq > 0) {
        options[t.substr(0, eq)] = t.substr(eq + 1);
      } else {
        positional.push_back(t);
      }
    }
    if (line_fails) {
      if (kRunWhole) return true;
      continue;
    }
    if (command == "param") {
      if (positional.size() == 2 && options.empty() && params.count(positional[0]) == 0)
        params[positional[0]] = positional[1];
      continue;
    }
    const bool heavy = kHeavyCommands.count(command) != 0;
    if (!kRunWhole && heavy) continue;  // not run by script_parse
    if (kRunWhole) {
      // Hostile magnitudes (the grid overflows of issue 15 are known) and paths out of the
      // sandbox (absolute paths could name /proc or /dev files).
      const auto tame = [](const std::string& t) {
        return small_numbers(t) && !t.starts_with('/') && t.find("..") == std::string::npos;
      };
      for (const std::string& t : positional) {
        if (!tame(t)) return false;
      }
      for (const auto& [key, value] : options) {
        if (!tame(value)) return false;
      }
      if (command == "scale") {
        double factor = 1;
        for (std::size_t i = 1; i < positional.size(); ++i) {
          double v = 0;
          if (number_of(positional[i], v)) factor = std::max(factor, std::abs(v));
        }
        scale_product *= factor;
        if (!(scale_product <= kMaxScaleProduct)) return false;
      }
      if (command == "save_mesh") {
        if (options.count("cell") != 0) return false;
        const auto method = options.find("method");
        const bool tets = method != options.end() && method->second == "tets";
        if (tets ? !capped_option(options, "levels", kMaxLevels)
                 : !capped_option(options, "resolution", kMaxResolution))
          return false;
      }
      if (command == "point_set_gen" && positional.size() > 1 &&
          kSlowDistributions.count(positional[1]) != 0)
        return false;
      if ((command == "point_set_gen" || command == "point_set_mesh") &&
          !capped_option(options, "count", kMaxCount))
        return false;
      if (command == "grow" && !capped_option(options, "max_iterations", kMaxGrowIterations))
        return false;
      if (command == "lsystem" && !capped_option(options, "iterations", kMaxLsystemIterations))
        return false;
    }
    // Shape sizes: an operator's result reaches every input's primitives; any other command
    // gives names it has not seen before the sum of the known names it mentions (at least 1).
    std::size_t sum = 0;
    for (const std::string& t : positional) {
      if (const auto it = leaves.find(t); it != leaves.end()) sum += it->second;
    }
    for (const auto& [key, value] : options) {
      if (const auto it = leaves.find(value); it != leaves.end()) sum += it->second;
    }
    if (sum > kMaxLeaves) return false;
    if (kOperators.count(command) != 0 && !positional.empty()) {
      leaves[positional.back()] = std::max<std::size_t>(sum, 1);
    } else {
      for (const std::string& t : positional) leaves.try_emplace(t, std::max<std::size_t>(sum, 1));
    }
  }
  return true;
}

// The data every script may read (examples/data/, copied once per process).
const fs::path& pristine_data() {
  static const fs::path* const dir = [] {
    auto* d = new fs::path(scratch_dir() / "pristine");
    fs::create_directories(*d);
    for (const auto& entry : fs::directory_iterator(RAMIFORM_FUZZ_DATA_DIR)) {
      if (entry.is_regular_file()) fs::copy_file(entry.path(), *d / entry.path().filename());
    }
    return d;
  }();
  return *dir;
}

// A fresh output directory holding data/ (hard links to the pristine copy: the session's
// writes are staged and renamed, so they never change a linked file).
fs::path fresh_run_dir() {
  const fs::path run = scratch_dir() / "run";
  std::error_code ec;
  fs::remove_all(run, ec);
  fs::create_directories(run / "data");
  for (const auto& entry : fs::directory_iterator(pristine_data())) {
    const fs::path to = run / "data" / entry.path().filename();
    fs::create_hard_link(entry.path(), to, ec);
    if (ec) fs::copy_file(entry.path(), to);
  }
  return run;
}

ScriptOptions options_for(const fs::path& dir) {
  ScriptOptions options;
  options.out_dir = dir.string();
  options.input_dir = dir.string();
  options.seed = 1;
  return options;
}

void run(std::string_view text) {
  Context ctx(1);  // one thread: the harness's time is the fuzzer's
  if constexpr (kRunWhole) {
    const fs::path dir = fresh_run_dir();
    expect_input_errors_only([&] {
      ScriptSession session(options_for(dir), &ctx);
      (void)session.run_text(text, "fuzz.rf");
      const std::vector<std::string> written = session.commit();
      if (verbose()) std::fprintf(stderr, "  ran; %zu outputs\n", written.size());
    });
  } else {
    static const fs::path dir = fresh_run_dir();  // never written: save_* are not run
    ScriptSession session(options_for(dir), &ctx);
    std::vector<std::string> tokens;
    Lines lines(text);
    std::string_view line;
    while (lines.next(line)) {
      if (tokenize(line, tokens) && !tokens.empty() && kHeavyCommands.count(tokens.front()) != 0)
        continue;
      expect_input_errors_only(
          [&] { (void)session.execute_line(line, "fuzz.rf", lines.number()); });
    }
  }
}

}  // namespace
}  // namespace ramiform::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (!ramiform::fuzz::within_caps(text)) {
    if (ramiform::fuzz::verbose()) std::fprintf(stderr, "  skipped: over a cap\n");
    return 0;
  }
  ramiform::fuzz::run(text);
  return 0;
}
