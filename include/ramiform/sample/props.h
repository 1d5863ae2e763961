// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// `.props` files: the parameter files of the point-set commands of Kochhar 2010, *Application
/// of implicit methods to the interactive modeling of trees* (M.Sc. thesis, University of
/// Calgary), §7.0.1 (`point_set_gen s poisson poisson.props`). One `key = value` per line; `#`
/// starts a comment (whole line or after a value); blank lines are ignored; keys are letters,
/// digits, `_`, `-` and `.`, starting with a letter or `_`. See docs/sampling.md for the keys of
/// each distribution.

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ramiform {

/// A parsed `.props` file.
struct Props {
  std::string source;  ///< file name used in messages (may be empty for in-memory text)
  /// key -> (value text, 1-based line number)
  std::map<std::string, std::pair<std::string, std::size_t>> values;
};

/// Parses `.props` text. Throws InputError(source, line, ...) for a line without `=`, an empty
/// or malformed key, an empty value, or a key given twice (naming the first line).
[[nodiscard]] Props parse_props(std::string_view text, const std::string& source);

/// Reads and parses a `.props` file; InputError(path, 0, ...) when it cannot be read.
[[nodiscard]] Props read_props(const std::string& path);

/// Typed, checked access to a `Props` for one consumer that knows its valid keys.
class PropsReader {
 public:
  /// Throws InputError(props.source, line, ...) for the first key (in file order) that is not
  /// in `valid_keys`, naming `what` (e.g. "distribution 'poisson'") and the closest valid key.
  PropsReader(const Props& props, std::vector<std::string> valid_keys, std::string what);

  /// True when the key is present.
  [[nodiscard]] bool has(const std::string& key) const;
  /// A finite number (parse_number of core/numbers.h: decimal, optional leading '+'); `fallback`
  /// when absent. InputError (file, line, key, value) otherwise.
  [[nodiscard]] double number(const std::string& key, double fallback) const;
  /// A non-negative decimal integer up to 2^63 - 1 (optional leading '+'); `fallback` when
  /// absent. InputError (file, line, key, value) otherwise.
  [[nodiscard]] std::size_t count(const std::string& key, std::size_t fallback) const;
  /// true/false, yes/no, on/off, 1/0; `fallback` when absent.
  [[nodiscard]] bool flag(const std::string& key, bool fallback) const;
  /// The raw text; `fallback` when absent.
  [[nodiscard]] std::string text(const std::string& key, const std::string& fallback) const;
  /// Throws InputError at the key's line: "KEY = VALUE: problem" (for checks done by callers).
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

 private:
  const Props& props_;
  std::vector<std::string> valid_keys_;
  std::string what_;
};

/// The candidate closest to `word` by edit distance (case-insensitive), or "" when none is
/// within max(2, |word| / 2) edits.
[[nodiscard]] std::string closest_key(const std::string& word,
                                      const std::vector<std::string>& candidates);

}  // namespace ramiform
