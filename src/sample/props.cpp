// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/sample/props.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "ramiform/core/errors.h"
#include "ramiform/core/text.h"
#include "ramiform/core/numbers.h"

namespace ramiform {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

bool is_key_char(char c, bool first) {
  const auto u = static_cast<unsigned char>(c);
  if (std::isalpha(u) || c == '_') return true;
  return !first && (std::isdigit(u) || c == '-' || c == '.');
}

// File text for a message (core/text.h): non-printable bytes as "\xNN", shortened when long.
std::string printable(std::string_view text) {
  const std::string q = quoted_text(text);
  return q.substr(1, q.size() - 2);
}

std::string quote(std::string_view text) { return quoted_text(text); }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0U : 1U)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string closest_key(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string w = lower(word);
  const std::size_t limit = std::max<std::size_t>(2, w.size() / 2);
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(w, lower(c));
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

Props parse_props(std::string_view text, const std::string& source) {
  Props props;
  props.source = source;
  // A UTF-8 byte order mark (written by some editors) is not part of the first key.
  text = skip_utf8_bom(text);
  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    line = trim(line);
    if (line.empty()) {
      if (end == text.size()) break;
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string_view::npos) {
      throw InputError(source, line_no, "expected 'key = value', got " + quote(line));
    }
    const std::string_view key = trim(line.substr(0, eq));
    const std::string_view value = trim(line.substr(eq + 1));
    if (key.empty()) throw InputError(source, line_no, "missing key before '='");
    for (std::size_t i = 0; i < key.size(); ++i) {
      if (!is_key_char(key[i], i == 0)) {
        throw InputError(source, line_no, "malformed key " + quote(key));
      }
    }
    if (value.empty()) {
      throw InputError(source, line_no, "key " + quote(key) + " has no value");
    }
    const std::string k(key);
    if (const auto it = props.values.find(k); it != props.values.end()) {
      throw InputError(source, line_no,
                       "key " + quote(k) + " given twice (first on line " +
                           std::to_string(it->second.second) + ")");
    }
    props.values.emplace(k, std::make_pair(std::string(value), line_no));
    if (end == text.size()) break;
  }
  return props;
}

Props read_props(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the props file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "cannot read the props file");
  return parse_props(ss.str(), path);
}

PropsReader::PropsReader(const Props& props, std::vector<std::string> valid_keys, std::string what)
    : props_(props), valid_keys_(std::move(valid_keys)), what_(std::move(what)) {
  // Report the unknown key that comes first in the file, so the message is reproducible.
  auto first = props_.values.end();
  for (auto it = props_.values.begin(); it != props_.values.end(); ++it) {
    if (std::find(valid_keys_.begin(), valid_keys_.end(), it->first) != valid_keys_.end()) {
      continue;
    }
    if (first == props_.values.end() || it->second.second < first->second.second) first = it;
  }
  if (first != props_.values.end()) {
    std::string msg = "unknown key " + quote(first->first) + " for " + what_;
    const std::string hint = closest_key(first->first, valid_keys_);
    if (!hint.empty()) msg += " (did you mean '" + hint + "'?)";
    msg += "; valid keys:";
    for (const auto& k : valid_keys_) msg += " " + k;
    throw InputError(props_.source, first->second.second, msg);
  }
}

bool PropsReader::has(const std::string& key) const { return props_.values.count(key) != 0; }

void PropsReader::fail(const std::string& key, const std::string& problem) const {
  const auto it = props_.values.find(key);
  if (it == props_.values.end()) throw InputError(props_.source, 0, key + ": " + printable_text(problem));
  // The problem may quote the value too (e.g. LaneKernel::parse), so it is escaped as well.
  throw InputError(
      props_.source, it->second.second,
      key + " = " + printable(it->second.first) + ": " + printable_text(problem) + " (" + what_ + ")");
}

double PropsReader::number(const std::string& key, double fallback) const {
  const auto it = props_.values.find(key);
  if (it == props_.values.end()) return fallback;
  double v = 0.0;
  if (parse_number(it->second.first, v) != NumberStatus::kOk) {
    fail(key, "expected a finite number");
  }
  return v;
}

std::size_t PropsReader::count(const std::string& key, std::size_t fallback) const {
  const auto it = props_.values.find(key);
  if (it == props_.values.end()) return fallback;
  std::int64_t v = 0;
  if (parse_number(it->second.first, v) != NumberStatus::kOk || v < 0) {
    fail(key, "expected a non-negative integer");
  }
  return static_cast<std::size_t>(v);
}

bool PropsReader::flag(const std::string& key, bool fallback) const {
  const auto it = props_.values.find(key);
  if (it == props_.values.end()) return fallback;
  const std::string s = lower(it->second.first);
  if (s == "true" || s == "yes" || s == "on" || s == "1") return true;
  if (s == "false" || s == "no" || s == "off" || s == "0") return false;
  fail(key, "expected true/false, yes/no, on/off or 1/0");
}

std::string PropsReader::text(const std::string& key, const std::string& fallback) const {
  const auto it = props_.values.find(key);
  return it == props_.values.end() ? fallback : it->second.first;
}

}  // namespace ramiform
