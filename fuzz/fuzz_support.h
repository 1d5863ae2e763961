// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// What every harness shares (docs/fuzzing.md): a scratch directory of its own, the input written
// to a file there (the readers take paths), and the rule that the library's documented
// exceptions are results while everything else is a finding.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <typeinfo>

#include "ramiform/core/errors.h"

namespace ramiform::fuzz {

/// The process's scratch directory, `$TMPDIR/ramiform-fuzz-<pid>` (made on first use, removed
/// at exit).
const std::filesystem::path& scratch_dir();

/// Writes `size` bytes to `path` (truncating it); aborts when it cannot, since a harness that
/// cannot write its input tests nothing.
void write_file(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size);

/// True when RAMIFORM_FUZZ_VERBOSE is set: harnesses then say on stderr what each input did
/// (its InputError, or the cap that skipped it), for checking a corpus by hand.
bool verbose();

/// Reports a finding on stderr and aborts, which libFuzzer and the replay both count as a crash.
[[noreturn]] void finding(const std::string& what);

/// Runs `body`. `InputError`, the exception every reader and the scene language document for
/// bad input, is a normal result; any other exception is a finding (ramiform's
/// InvalidArgument, Failure and Cancelled are not documented for these inputs: the harnesses
/// pass valid options and never cancel).
template <class Body>
void expect_input_errors_only(Body&& body) {
  try {
    body();
  } catch (const InputError& e) {
    if (verbose()) std::fprintf(stderr, "  InputError: %s\n", e.what());  // the documented result
  } catch (const std::exception& e) {
    finding(std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("unexpected exception of a non-std type");
  }
}

/// Runs `body`, in which any exception is a finding (checks of a result that was read).
template <class Body>
void expect_no_exception(Body&& body) {
  try {
    body();
  } catch (const std::exception& e) {
    finding(std::string("exception while checking a result ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("exception of a non-std type while checking a result");
  }
}

/// Reads a value with `read` (an InputError is a result), then, when it was read, checks it with
/// `check` (any exception is a finding).
template <class Read, class Check>
void read_then_check(Read&& read, Check&& check) {
  std::optional<decltype(read())> value;
  expect_input_errors_only([&] { value.emplace(read()); });
  if (value) expect_no_exception([&] { check(*value); });
}

/// Aborts with `what` when `condition` is false (a documented guarantee does not hold).
inline void require(bool condition, const char* what) {
  if (!condition) finding(std::string("guarantee broken: ") + what);
}

}  // namespace ramiform::fuzz
