// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// All-or-nothing file output: the content goes to a temporary file in the target's directory,
/// which is renamed over the target only once it is completely written and flushed. A failed or
/// throwing write never leaves a partial output and never replaces an existing file.

#include <functional>
#include <ostream>
#include <string>

namespace ramiform {

/// How the output stream treats newlines (on POSIX systems both are identical).
enum class FileMode {
  kText,    ///< text stream
  kBinary,  ///< binary stream, bytes written unchanged
};

/// Writes the file `path` atomically: calls `writer` with a stream on a fresh temporary file
/// ("." + file name + ".tmp-..." in the same directory), flushes and syncs it, then renames it to
/// `path`, replacing any existing file.
///
/// Throws `Failure` naming `path` (with the system's error text) when the directory does not
/// exist (it is never created), the temporary file cannot be created, a write fails or the
/// rename fails. If `writer` throws, its exception propagates unchanged. In every failing case
/// the temporary file is removed and an existing `path` is left untouched.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer,
                           FileMode mode = FileMode::kText);

}  // namespace ramiform
