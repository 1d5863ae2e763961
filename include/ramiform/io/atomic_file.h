// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// All-or-nothing file output: the content is written next to the target and appears under the
/// target's name only once it is completely written and flushed, replacing an existing file
/// atomically. A failed or throwing write never leaves a partial output and never replaces an
/// existing file.
///
/// On Linux the content goes to an unnamed file (O_TMPFILE) in the target's directory, which is
/// linked under its name when complete (linkat through /proc/self/fd): a process killed while
/// writing, even by SIGKILL, leaves nothing behind. Where the file system has no O_TMPFILE (or
/// on other systems) a named temporary file is used instead; a SIGKILL can leave that one.

#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace ramiform {

/// How the output stream treats newlines (on POSIX systems both are identical).
enum class FileMode {
  kText,    ///< text stream
  kBinary,  ///< binary stream, bytes written unchanged
};

/// Writes the file `path` atomically: calls `writer` with a stream on a fresh file in the same
/// directory, flushes and syncs it, then publishes it as `path`, replacing any existing file.
/// The fresh file is unnamed where Linux allows (see above), otherwise "." + file name +
/// ".tmp-..." (a staged file, see below); replacing an existing target gives the unnamed file
/// such a name for the moment between link and rename. Permissions are those of any new file:
/// 0666 minus the process's umask.
/// If `path` is held (hold_file), the content is kept back instead of being published.
///
/// Throws `Failure` naming `path` (with the system's error text) when the directory does not
/// exist (it is never created), the file cannot be created, a write fails or publishing fails.
/// If `writer` throws, its exception propagates unchanged. In every failing case the written
/// file is removed and an existing `path` is left untouched.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer,
                           FileMode mode = FileMode::kText);

/// Staged files: named files a run has written but not yet published (the named temporary files
/// of write_file_atomically, held files kept under a name). Registering them lets a signal
/// handler remove them, so that a run stopped by SIGTERM or SIGINT leaves nothing behind.
/// Thread-safe; at most kMaxStagedFiles are registered at once (beyond that a file is simply not
/// registered) and paths longer than kMaxStagedPath bytes are not registered.
inline constexpr int kMaxStagedFiles = 256;
inline constexpr int kMaxStagedPath = 4095;
void register_staged_file(const std::string& path);
/// Forgets `path` (after it was renamed into place or removed); unknown paths are ignored.
void unregister_staged_file(const std::string& path);
/// Removes every registered staged file (unlink) and forgets them. Async-signal-safe: meant for
/// a SIGTERM/SIGINT handler (the CLI installs one); uses no lock and allocates nothing.
void remove_staged_files_for_signal() noexcept;

/// Held files: outputs written now and published later, together (a script's outputs until the
/// whole script has succeeded). `path` is a private staging name in the target's directory (the
/// script uses ".rf-staged-N-NAME"). After hold_file(path), write_file_atomically(path, ...)
/// keeps the complete content back: in an unnamed file on Linux, so that no name exists and a
/// killed run (SIGKILL included) leaves nothing; where there is no O_TMPFILE, or when
/// kMaxStagedFiles held files already keep one open, as a file under `path` itself, registered
/// as a staged file. A later write of the same path replaces the kept content. Thread-safe.
void hold_file(const std::string& path);
/// Publishes the content last written to held `path` as `target` (replacing an existing target
/// atomically; `target` must be on `path`'s file system, e.g. in its directory) and forgets
/// `path`. Throws `Failure` naming both when nothing was written, or
/// naming `target` when linking or renaming fails (then `path` stays held).
void publish_held_file(const std::string& path, const std::string& target);
/// Forgets held `path` and deletes its content (unknown paths are ignored). Never throws.
void drop_held_file(const std::string& path) noexcept;
/// Makes the content last written to held `path` readable under `path` until
/// hide_held_file(path) (for reading an output back before it is published): copies the unnamed
/// file there. While shown it is a named staged file: a stop signal removes it, a SIGKILL can
/// leave it. No-op when the content already has that name or nothing was written. Throws
/// `Failure` when the copy fails.
void show_held_file(const std::string& path);
/// Removes the copy show_held_file made (the content stays held). Never throws.
void hide_held_file(const std::string& path) noexcept;

/// A group of outputs published together: add() gives, for each target, a held staging path in
/// the target's directory (".rf-held-N-NAME") to write with write_file_atomically; publish()
/// makes them all appear under their targets; a group destroyed before publish() (a later
/// step failed) drops every held content, so a run that fails half-way leaves no output of the
/// group (e.g. the views of `ramiform draw --views N`). Not thread-safe.
class HeldOutputs {
 public:
  HeldOutputs() = default;
  HeldOutputs(const HeldOutputs&) = delete;
  HeldOutputs& operator=(const HeldOutputs&) = delete;
  ~HeldOutputs();

  /// The staging path to write `target` to (the same one when `target` was added before).
  [[nodiscard]] std::string add(const std::string& target);
  /// Publishes every held output under its target, in the order they were added, and empties
  /// the group. Throws `Failure` as publish_held_file does; outputs not yet published are then
  /// dropped when the group is destroyed.
  void publish();

 private:
  std::vector<std::pair<std::string, std::string>> outputs_;  ///< (staged, target)
};

}  // namespace ramiform
