// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal helpers shared by the text readers (OBJ, OFF, point lists, PLY headers and ASCII
// bodies): whole-file loading, line iteration with 1-based line numbers, field splitting and
// strict number parsing, and shortest round-trip number formatting for the writers.

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/numbers.h"

namespace ramiform::io_detail {

/// The whole file as bytes. Throws InputError(path) when it cannot be opened or read.
std::string read_whole_file(const std::string& path);

/// Lower-case extension with its dot (".ply"), or "" when the file name has none.
std::string lower_extension(const std::string& path);

/// Iterates over the lines of a text; '\n' ends a line and a '\r' before it is dropped.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text, std::size_t offset = 0, std::size_t first_line = 1)
      : text_(text), pos_(offset), next_line_(first_line) {}

  /// Sets `line` to the next line and returns true, or returns false at the end of the text.
  bool next(std::string_view& line);
  /// 1-based number of the line last returned by next().
  [[nodiscard]] std::size_t line_number() const { return next_line_ - 1; }
  /// Byte offset just past the line last returned (past its '\n').
  [[nodiscard]] std::size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t next_line_ = 1;
};

/// The line without a '#' comment and without surrounding spaces and tabs.
std::string_view strip_comment(std::string_view line);
/// True when the text holds only spaces, tabs, line breaks, '\f' and '\v' (or nothing).
bool is_blank(std::string_view line);

/// The text without a leading UTF-8 byte order mark (EF BB BF), which some editors and
/// spreadsheets write at the start of text files.
std::string_view skip_bom(std::string_view text);

/// Splits `line` into fields separated by runs of spaces and tabs, and, when `allow_commas`, by
/// single commas (with optional blanks around them). Returns false when a comma leaves an empty
/// field ("1,,2", "1,2,", ",1"). `fields` is cleared first. Blanks and carriage returns at the
/// ends of the line are dropped; a carriage return inside it is part of a field (a file with
/// lone '\r' line breaks is one long line, not one line of many fields).
bool split_fields(std::string_view line, std::vector<std::string_view>& fields,
                  bool allow_commas = false);

/// Reads lines until one has fields (space- and tab-separated) after removing a '#' comment and
/// sets `fields` to them; returns false at the end of the text. The line's number is then
/// cursor.line_number().
bool next_content(LineCursor& cursor, std::vector<std::string_view>& fields);

/// Strict parsers (core/numbers.h) that throw InputError(source, line, "<what>: ...") naming the
/// token.
double to_double(std::string_view token, const std::string& source, std::size_t line,
                 std::string_view what);
std::int64_t to_int64(std::string_view token, const std::string& source, std::size_t line,
                      std::string_view what);

/// The text with every byte outside printable ASCII (control characters, DEL, bytes >= 0x80)
/// written as "\xNN", so that a message about a binary or mis-encoded file shows what is there
/// (an invisible byte order mark, a NUL) and cannot send control sequences to a terminal.
std::string printable(std::string_view text);

/// The token in quotes for an error message, shortened when long, as printable() text.
std::string quote(std::string_view token);

/// Appends the shortest decimal text that reads back as exactly `value` (core/numbers.h).
inline void append_double(std::string& out, double value) { append_shortest(out, value); }
/// Appends the decimal text of `value`.
void append_uint(std::string& out, std::uint64_t value);

/// Collects output text and writes it to a stream in large blocks.
class TextSink {
 public:
  explicit TextSink(std::ostream& out) : out_(out) { text_.reserve(kBlock + 256); }
  ~TextSink() = default;
  TextSink(const TextSink&) = delete;
  TextSink& operator=(const TextSink&) = delete;

  /// The pending text; append to it, then call line_done().
  std::string& text() { return text_; }
  /// Writes the pending text when a block is full.
  void line_done() {
    if (text_.size() >= kBlock) flush();
  }
  /// Writes all pending text.
  void flush() {
    out_.write(text_.data(), static_cast<std::streamsize>(text_.size()));
    text_.clear();
  }

 private:
  static constexpr std::size_t kBlock = std::size_t{1} << 20;
  std::ostream& out_;
  std::string text_;
};

}  // namespace ramiform::io_detail
