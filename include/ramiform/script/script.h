// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The scene language (`.rf` scripts): line-based commands in the style of the thesis's command
/// editor (Kochhar 2010, "Application of implicit methods to the interactive modeling of trees"
/// (M.Sc. thesis), §4.1, §7.0.1) — `COMMAND NAME ARGS...`, named objects, `#` comments:
///
///     sphere s1
///     line s2
///     diff s1 s2 s3
///
/// Every named shape is a node of a BlobTree (a DAG: one node may feed several operators).
/// Arguments are positional, followed by optional `key=value` options; `$NAME` is replaced by
/// the value of a `param`. The commands and their arguments are documented in docs/language.md
/// and listed by `help`.
///
/// Errors are `InputError`s naming the file, line and column, the command and what was expected;
/// unknown commands and object names suggest the closest known one. Files written by a script
/// are staged next to their targets and only renamed into place by `commit()`, so a script that
/// fails leaves no partial output (`discard()` removes the staged files). Outputs must lie inside
/// the output directory unless `allow_any_path` is set.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"

namespace ramiform {

/// Options of a script session.
struct ScriptOptions {
  std::string out_dir = ".";  ///< directory every output path is relative to (must exist)
  /// Directory that relative input paths (skeletons, curve files, ...) are relative to; empty =
  /// the directory of the script file (run_file) or the working directory (execute_line).
  std::string input_dir;
  bool allow_any_path = false;  ///< let outputs leave out_dir (absolute paths, "..")
  std::uint64_t seed = 1;       ///< seed of every random choice a script makes
  /// Values for `param` declarations (`--set name=value`); a name that the script never
  /// declares is an error at the end of run_file.
  std::map<std::string, std::string> params;
  /// A draft run, for quick previews (the studio while a `param` slider is dragged;
  /// `ramiform run --draft`): `save_mesh` meshes method=tets at the paper's base lattice
  /// (levels 0, no refinement to a tolerance, no levels of detail) and method=mc at a
  /// resolution of at most kDraftResolution; `draw` writes nothing. Every other command runs as
  /// usual, so a draft shows the same shapes, skeletons and points, coarsely meshed.
  bool draft = false;
  /// Called by `save_mesh` with the shape's name and its finest mesh as soon as it is
  /// polygonized, before normals, bark UVs and the files, which can take as long again (the
  /// studio shows the new surface while they are made). The mesh is the geometry the files
  /// will hold (the seam copies of bark UVs aside); the callback must not keep the reference.
  /// A mesh made to a tolerance is sent before its deviation is measured; in the rare case the
  /// measure asks for a second refinement pass, the same shape is sent again with that pass's
  /// mesh (the last call holds the files' geometry).
  /// Runs on the session's thread; an exception from it ends the command.
  std::function<void(const std::string& shape, const TriMesh& mesh)> on_mesh;
};

/// The finest marching-cubes resolution of a draft run (ScriptOptions::draft).
inline constexpr int kDraftResolution = 48;

/// What one command did.
struct CommandResult {
  std::string command;  ///< the command's name ("" for blank and comment lines)
  std::string message;  ///< one human-readable line (may be empty)
  /// True for commands whose message is the point of running them (eval, save_*, info, list,
  /// help); `ramiform run` prints only these.
  bool is_report = false;
  /// Machine-readable facts of the result, for programs that run scripts (the studio):
  /// save_mesh sets vertices, triangles, components, boundary_edges and watertight (1 when
  /// closed, oriented and manifold, else 0) of its finest mesh.
  std::map<std::string, double> facts;
  /// The shape whose surface the command's output shows (save_mesh: the shape it meshed), so
  /// that a program can map what it displays back to the script's names; empty otherwise.
  std::string shape;
};

/// A `param NAME VALUE [min=A] [max=B] [step=S]` line as the session ran it (for sliders).
struct ScriptParam {
  std::string name;
  std::string value;                     ///< the value in effect (from `--set` when given there)
  std::optional<double> min, max, step;  ///< only where the line gave them
};

/// A command of the language as `help` documents it.
struct CommandInfo {
  std::string name;
  std::string synopsis;
  std::string description;
  std::vector<std::string> options;  ///< the option keys it accepts
};

/// An interpreter session: the named objects and staged outputs of one script or shell.
class ScriptSession {
 public:
  explicit ScriptSession(ScriptOptions options, Context* ctx = nullptr);
  ~ScriptSession();
  ScriptSession(const ScriptSession&) = delete;
  ScriptSession& operator=(const ScriptSession&) = delete;

  /// Runs one line; `file` and `line` only label errors. Throws InputError (file, line, column)
  /// for a bad command, InvalidArgument/Failure from the library pass through re-labelled as
  /// InputError of that line.
  CommandResult execute_line(std::string_view text, const std::string& file = "<shell>",
                             std::size_t line = 1);
  /// Runs every line of `text` (named `file` in messages) and checks that every `--set`
  /// parameter was declared. Stops at the first error (throws); does not commit.
  std::vector<CommandResult> run_text(std::string_view text, const std::string& file);
  /// Reads and runs a script file (InputError when it cannot be read). Does not commit.
  std::vector<CommandResult> run_file(const std::string& path);

  /// Moves every staged output to its final path; returns the final paths in the order written.
  std::vector<std::string> commit();
  /// Removes every staged output (after a failure). Never throws.
  void discard() noexcept;

  /// The field of the shape `name` defined so far (for `ramiform particles SCRIPT.rf:NAME`);
  /// throws InvalidArgument for an unknown name (suggesting the closest) or an object that is
  /// not a shape.
  [[nodiscard]] FieldPtr shape(const std::string& name) const;

  /// The names of the shapes defined so far, in the order of their (last) definition: the last
  /// one is the shape the script defined last.
  [[nodiscard]] std::vector<std::string> shape_names() const;
  /// The `param` lines run so far, in order.
  [[nodiscard]] const std::vector<ScriptParam>& params() const;
  /// The final paths of the outputs staged so far (not yet committed), in the order written.
  [[nodiscard]] std::vector<std::string> staged_outputs() const;

  /// Every command (aliases not repeated), sorted by name.
  [[nodiscard]] static std::vector<CommandInfo> commands();
  /// Names of all commands, sorted.
  [[nodiscard]] static std::vector<std::string> command_names();
  /// The documentation of one command (synopsis, description, example); throws InvalidArgument
  /// for an unknown name, suggesting the closest.
  [[nodiscard]] static std::string command_help(const std::string& name);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Runs a script file and commits its outputs; on any error discards them and rethrows.
std::vector<CommandResult> run_script(const std::string& path, const ScriptOptions& options,
                                      Context* ctx = nullptr);

/// The closest of `candidates` to `word` by edit distance, or "" when none is within
/// max(2, |word| / 2) edits (case-insensitive) (for "did you mean" hints).
[[nodiscard]] std::string closest_name(const std::string& word,
                                       const std::vector<std::string>& candidates);

}  // namespace ramiform
