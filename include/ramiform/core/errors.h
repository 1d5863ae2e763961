// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The error hierarchy. The library throws these and never prints; the CLI maps them to exit
/// codes (InvalidArgument, InputError -> 2; Cancelled, Failure -> 3).

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>

namespace ramiform {

/// A caller passed a value that violates a documented precondition (the message names it).
class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Bad input data: a file or an in-memory element that cannot be used. `what()` is the full
/// message "FILE:LINE: problem" (or "FILE: element K: problem"); the parts are kept separately.
class InputError : public std::runtime_error {
 public:
  /// `file` may be empty (in-memory data); `line` is 1-based, 0 when unknown.
  InputError(std::string file, std::size_t line, const std::string& problem);
  /// An error at a 1-based line and column: "FILE:LINE:COLUMN: problem".
  InputError(std::string file, std::size_t line, std::size_t column, const std::string& problem);
  /// An error about the element `element_index` (0-based) of kind `element` (e.g. "edge").
  InputError(std::string file, const std::string& element, std::size_t element_index,
             const std::string& problem);

  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] std::size_t line() const { return line_; }  ///< 1-based, 0 when unknown
  [[nodiscard]] std::size_t column() const { return column_; }  ///< 1-based, 0 when unknown
  [[nodiscard]] const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::size_t line_ = 0;
  std::size_t column_ = 0;
  std::string problem_;
};

/// A request that would need more memory than the budget allows (core/memory.h). It is an
/// InvalidArgument (the caller asked for too much), so the CLI exits with 2.
class ResourceLimit : public InvalidArgument {
 public:
  /// `needed` and `budget` in bytes.
  ResourceLimit(const std::string& message, double needed, double budget)
      : InvalidArgument(message), needed_(needed), budget_(budget) {}
  [[nodiscard]] double needed() const { return needed_; }  ///< estimated peak, bytes
  [[nodiscard]] double budget() const { return budget_; }  ///< the budget it exceeds, bytes

 private:
  double needed_;
  double budget_;
};

/// A long operation was cancelled through its Context.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

/// An operation could not complete for reasons other than bad input (I/O failure, resources).
class Failure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A number for messages: six significant digits ("%.6g", the same text as a default
/// std::ostream), e.g. "0.004", "1e-300", "2.5e+07".
[[nodiscard]] std::string format_number(double v);

}  // namespace ramiform
