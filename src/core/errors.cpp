// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/errors.h"

#include <cstdio>

#include <utility>

namespace ramiform {
namespace {

std::string located(const std::string& file, std::size_t line, const std::string& problem,
                    std::size_t column = 0) {
  std::string where = file.empty() ? std::string("<input>") : file;
  if (line > 0) where += ":" + std::to_string(line);
  if (line > 0 && column > 0) where += ":" + std::to_string(column);
  return where + ": " + problem;
}

}  // namespace

InputError::InputError(std::string file, std::size_t line, const std::string& problem)
    : std::runtime_error(located(file, line, problem)),
      file_(std::move(file)),
      line_(line),
      problem_(problem) {}

InputError::InputError(std::string file, std::size_t line, std::size_t column,
                       const std::string& problem)
    : std::runtime_error(located(file, line, problem, column)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      problem_(problem) {}

InputError::InputError(std::string file, const std::string& element, std::size_t element_index,
                       const std::string& problem)
    : std::runtime_error(located(file, 0, element + " " + std::to_string(element_index) + ": " +
                                              problem)),
      file_(std::move(file)),
      problem_(element + " " + std::to_string(element_index) + ": " + problem) {}

std::string format_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace ramiform
