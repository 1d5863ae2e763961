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

/// Staged files: files a run has written but not yet published (write_file_atomically's
/// temporary files while they are written, a script's outputs until the script has succeeded).
/// Registering them lets a signal handler remove them, so that a run stopped by SIGTERM or
/// SIGINT leaves nothing behind. Thread-safe; at most kMaxStagedFiles are registered at once
/// (beyond that a file is simply not registered) and paths longer than kMaxStagedPath bytes are
/// not registered.
inline constexpr int kMaxStagedFiles = 256;
inline constexpr int kMaxStagedPath = 4095;
void register_staged_file(const std::string& path);
/// Forgets `path` (after it was renamed into place or removed); unknown paths are ignored.
void unregister_staged_file(const std::string& path);
/// Removes every registered staged file (unlink) and forgets them. Async-signal-safe: meant for
/// a SIGTERM/SIGINT handler (the CLI installs one); uses no lock and allocates nothing.
void remove_staged_files_for_signal() noexcept;

}  // namespace ramiform
