// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "io/text_scan.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "ramiform/core/errors.h"
#include "ramiform/core/text.h"

namespace ramiform::io_detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

}  // namespace

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "is a directory");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw InputError(path, 0, std::string("cannot open file: ") + std::strerror(errno));
  }
  std::string data;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) data.reserve(static_cast<std::size_t>(size));
  // Reading in large blocks also copes with files whose size is unknown (pipes, /proc).
  char block[1 << 16];
  for (;;) {
    const std::size_t got = std::fread(block, 1, sizeof block, file);
    data.append(block, got);
    if (got < sizeof block) break;
  }
  const bool failed = std::ferror(file) != 0;
  const int err = errno;
  std::fclose(file);
  if (failed) throw InputError(path, 0, std::string("read error: ") + std::strerror(err));
  return data;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return ext;
}

bool LineCursor::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++next_line_;
  return true;
}

std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
  while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
  return line;
}

bool is_blank(std::string_view line) {
  for (char c : line) {
    if (!is_space(c) && c != '\n') return false;
  }
  return true;
}

bool next_content(LineCursor& cursor, std::vector<std::string_view>& fields) {
  std::string_view line;
  while (cursor.next(line)) {
    split_fields(strip_comment(line), fields);
    if (!fields.empty()) return true;
  }
  return false;
}

std::string_view skip_bom(std::string_view text) { return skip_utf8_bom(text); }

bool split_fields(std::string_view line, std::vector<std::string_view>& fields, bool allow_commas) {
  fields.clear();
  // Only a carriage return at the end of the line is line-break debris; inside the line it
  // belongs to a field, so that "0 0 0\r1 1 1" (lone '\r' line breaks) is not read as one
  // point with a normal.
  const auto separates = [](char c) { return is_space(c) && c != '\r'; };
  while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
  const char* p = line.data();
  const char* const end = p + line.size();
  bool need_field = false;  // a comma was just read: the next field must not be empty
  for (;;) {
    while (p < end && separates(*p)) ++p;
    if (p == end) return !need_field;
    if (allow_commas && *p == ',') return false;  // empty field before this comma
    const char* start = p;
    while (p < end && !separates(*p) && !(allow_commas && *p == ',')) ++p;
    fields.emplace_back(start, static_cast<std::size_t>(p - start));
    while (p < end && separates(*p)) ++p;
    need_field = false;
    if (allow_commas && p < end && *p == ',') {
      ++p;
      need_field = true;
    }
  }
}

std::string printable(std::string_view text) { return printable_text(text); }

std::string quote(std::string_view token) { return quoted_text(token); }

double to_double(std::string_view token, const std::string& source, std::size_t line,
                 std::string_view what) {
  double value = 0.0;
  switch (parse_number(token, value)) {
    case NumberStatus::kOk:
      return value;
    case NumberStatus::kNotFinite:
      throw InputError(source, line,
                       std::string(what) + ": " + quote(token) + " is not a finite number");
    case NumberStatus::kOutOfRange:
      throw InputError(source, line, std::string(what) + ": " + quote(token) + " is out of range");
    case NumberStatus::kMalformed:
      break;
  }
  throw InputError(source, line, std::string(what) + ": expected a number, got " + quote(token));
}

std::int64_t to_int64(std::string_view token, const std::string& source, std::size_t line,
                      std::string_view what) {
  std::int64_t value = 0;
  switch (parse_number(token, value)) {
    case NumberStatus::kOk:
      return value;
    case NumberStatus::kOutOfRange:
      throw InputError(source, line, std::string(what) + ": " + quote(token) + " is out of range");
    default:
      break;
  }
  throw InputError(source, line, std::string(what) + ": expected an integer, got " + quote(token));
}

void append_uint(std::string& out, std::uint64_t value) {
  char buf[24];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, static_cast<std::size_t>(ptr - buf));
}

}  // namespace ramiform::io_detail
