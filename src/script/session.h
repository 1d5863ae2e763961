// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internals of the scene language: tokens, objects, the session state and the `Call` through
// which a command reads its arguments. Commands live in commands_*.cpp, one group per file,
// each registering its specs in `command_table()`.

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/geometry.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/types.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/field/curves.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/field.h"
#include "ramiform/particles/surface_particles.h"
#include "ramiform/script/script.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::script {

// Limits that keep a hostile script from asking for unbounded memory (docs/language.md,
// "Limits"). The nesting depth of shapes is the library's kMaxFieldDepth (field/operators.h).

/// Longest a line may grow to when its `$NAME` parameters are substituted (bytes).
constexpr std::size_t kMaxSubstitutedLine = std::size_t{1} << 20;
/// Most bytes all `param` values of a session may hold together.
constexpr std::size_t kMaxParameterBytes = std::size_t{16} << 20;
/// Longest object name (bytes).
constexpr std::size_t kMaxNameLength = 256;
/// Longest summary an object keeps (bytes); a longer one is cut and ends in "...". Transforms
/// append to the summary while it has room, and are only counted after that.
constexpr std::size_t kMaxSummary = 240;
/// Most objects `list` names; the rest are counted.
constexpr std::size_t kMaxListed = 1000;

struct Token {
  std::string text;
  std::size_t column = 1;  // 1-based, of the token's first character in the source line
};

/// A token of the script as shown in messages: every byte outside printable ASCII (control
/// bytes, DEL, bytes >= 0x80 such as UTF-8 or a byte order mark) as "\xNN", cut after 48
/// characters with "...".
std::string shown(std::string_view text);

/// The text without a leading UTF-8 byte order mark (EF BB BF).
std::string_view without_bom(std::string_view text);

/// Splits a line into whitespace-separated tokens; `"..."` quotes keep spaces, `#` outside
/// quotes starts a comment. Throws InputError on an unterminated quote.
std::vector<Token> tokenize(std::string_view text, const std::string& file, std::size_t line);

enum class ObjectKind { kShape, kCurve2, kCurve3, kDeformation };
std::string kind_name(ObjectKind kind);

/// A named object of a script.
struct Object {
  ObjectKind kind = ObjectKind::kShape;
  FieldPtr field;                    // kShape
  std::optional<Skeleton> skeleton;  // kShape straight from `skeleton` (for method=tets)
  // kShape with surface=equipotential: its charges and lambda (`field` is its field); dropped
  // with `skeleton` (save_mesh method=particles puts its rings at the charges).
  std::shared_ptr<const Equipotential> equipotential;
  Curve2 curve2;                    // kCurve2
  Curve3 curve3;                    // kCurve3
  Deformation deformation;          // kDeformation (field/anisotropic.h)
  std::string summary;              // one line for `info` and `list` (<= kMaxSummary bytes)
  std::size_t more_transforms = 0;  // transforms left out of the full summary
};

/// The object's summary as shown by `info`, `list` and the commands that define it.
std::string summary_text(const Object& object);

struct Staged {
  std::string final_path;
  std::string staged_path;
};

}  // namespace ramiform::script

namespace ramiform {

struct ScriptSession::Impl {
  ScriptOptions options;
  Context* ctx = nullptr;
  std::map<std::string, script::Object> objects;
  std::vector<std::string> shape_order;  // shape names, each where it was last defined
  std::map<std::string, std::string> params;  // declared parameters and their values
  std::vector<ScriptParam> param_list;         // the `param` lines in order, with their ranges
  std::size_t param_bytes = 0;                // their values' sizes added up
  std::set<std::string> declared;
  std::vector<script::Staged> staged;
  std::vector<std::string> shown;  // staged outputs named for the current command to read back
  std::map<std::string, PointSet> point_sets;  // by name (point_set_gen names them after the shape)
  std::string current_points;                  // the point set made or changed last
  std::string input_dir;                       // resolved base of relative input paths
};

}  // namespace ramiform

namespace ramiform::script {

class Call;
using Handler = std::function<CommandResult(Call&)>;

/// One command of the language.
struct CommandSpec {
  std::string name;
  std::string synopsis;              // "sphere NAME [RADIUS] [center=X,Y,Z] [kernel=K]"
  std::string description;           // one paragraph
  std::string example;               // lines of script
  std::vector<std::string> options;  // accepted option keys
  Handler run;
  std::vector<std::string> aliases;
};

/// Every command, by name (aliases included).
const std::map<std::string, const CommandSpec*>& command_table();
/// Registration per group (called once by command_table()).
void add_shape_commands(std::vector<CommandSpec>& out);
void add_curve_commands(std::vector<CommandSpec>& out);
void add_output_commands(std::vector<CommandSpec>& out);
void add_growth_commands(std::vector<CommandSpec>& out);
void add_skeletal_commands(std::vector<CommandSpec>& out);
void add_point_commands(std::vector<CommandSpec>& out);
void add_draw_commands(std::vector<CommandSpec>& out);

/// The arguments of one command line, with typed accessors that throw InputError pointing at
/// the offending token.
class Call {
 public:
  Call(ScriptSession::Impl& session, const CommandSpec& spec, std::vector<Token> tokens,
       std::string file, std::size_t line);
  /// Takes away the names that input_path gave staged outputs read back by this command.
  ~Call();
  Call(const Call&) = delete;
  Call& operator=(const Call&) = delete;

  ScriptSession::Impl& session() const { return session_; }
  const CommandSpec& spec() const { return spec_; }

  /// Number of positional arguments (tokens after the command that are not key=value).
  std::size_t count() const { return positional_.size(); }
  const Token& arg(std::size_t i) const;
  /// Requires between `min` and `max` positional arguments.
  void expect_count(std::size_t min, std::size_t max, const std::string& what) const;

  /// A new object name (letters, digits, '_', '-', '.'; not starting with a digit).
  std::string new_name(std::size_t i) const;
  double number(std::size_t i, const std::string& what) const;
  double positive(std::size_t i, const std::string& what) const;
  int integer(std::size_t i, const std::string& what) const;
  /// An existing object of `kind`; unknown names suggest the closest.
  const Object& object(std::size_t i, ObjectKind kind) const;
  const Object& object_named(const Token& token, ObjectKind kind) const;
  /// An input path resolved against the session's input directory (must exist).
  std::string input_path(std::size_t i) const;
  std::string input_path(const Token& token) const;
  /// A file this script wrote earlier under this name (relative to out_dir), else input_path.
  std::string written_or_input_path(std::size_t i) const;
  std::string written_or_input_path(const Token& token) const;
  /// An output path resolved against out_dir (inside it unless allow_any_path), staged: the
  /// returned path is where to write now (a held file, io/atomic_file.h: unnamed until read
  /// back or published); commit() publishes it under the final path.
  std::string output_path(std::size_t i);
  /// The same for the file `name` (an output derived from the argument `token`, e.g. one
  /// level of detail of it); messages point at `token`.
  std::string output_path(const Token& token, const std::string& name);

  bool has_option(const std::string& key) const;
  double option_number(const std::string& key, double fallback) const;
  double option_positive(const std::string& key, double fallback) const;
  int option_integer(const std::string& key, int fallback, int min, int max) const;
  Vec3 option_vec3(const std::string& key, const Vec3& fallback) const;
  std::string option_word(const std::string& key, const std::string& fallback,
                          const std::vector<std::string>& allowed) const;
  const Token* option_token(const std::string& key) const;

  /// Parses "X,Y,Z" (for option values and `vec` positional arguments).
  Vec3 parse_vec3(const Token& token, const std::string& what) const;
  double parse_number(const Token& token, const std::string& what) const;

  [[noreturn]] void fail(const Token& token, const std::string& problem) const;
  [[noreturn]] void fail(const std::string& problem) const;  // at the command itself

  /// Stores an object under `name` (replacing an existing one).
  void define(const std::string& name, Object object);

  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }

 private:
  ScriptSession::Impl& session_;
  const CommandSpec& spec_;
  Token command_;
  std::vector<Token> positional_;
  std::vector<std::pair<std::string, Token>> options_;  // key, value token (column of value)
  std::string file_;
  std::size_t line_;
};

/// A shape object with its field and its one-line summary.
Object shape(FieldPtr field, std::string summary);
/// The result line of a command that defined `name`: "NAME: summary".
CommandResult defined(const Call& call, const std::string& name);

/// The seed of a named random choice: seed= when given (an integer >= 0), else the session seed
/// mixed with `name`, so that two point sets of one script differ and each stays the same when
/// other commands change.
std::uint64_t seed_for(const Call& c, const std::string& name);

/// The particle options a command's options give (per_cell, count, iterations, cell_depth,
/// flatness; the seed from seed_for(c, seed_name)), shared by `particles` and `draw`.
ParticleOptions particle_options(const Call& c, std::size_t default_count,
                                 const std::string& seed_name);

/// Particles saved by `particles ... state=FILE` (earlier in the script, or an input file) at
/// `token`; fails at the token when the file is malformed or lies on another iso value than `iso`.
ParticleSystem saved_particles(const Call& c, const Token& token, double iso);

/// The kernel and weight options of a distance primitive (kernel=K weight=W; the Cauchy kernel
/// is refused at its token).
DistancePrimitiveOptions primitive_options(const Call& call);

/// The deformation function named by option `key` (def=, def_u=, def_v=): a `deform` object's
/// name or an inline text (parse_deformation); identity when the option is absent.
Deformation deformation_option(const Call& c, const std::string& key);

/// "1,2,3" for messages (numbers as ramiform::format_number).
std::string format_vec3(const Vec3& v);

/// The option keys of the equipotential surface (Gruber & Wallner 2014) that `skeleton`, `grow`
/// and `lsystem` take with surface=equipotential: alpha, charge, charge_spacing, lambda,
/// lambda_scale, open_ends, fit_radii.
const std::vector<std::string>& equipotential_keys();

/// The equipotential surface a command asked for.
struct EquipotentialRequest {
  EquipotentialOptions options;
  bool fit_radii = false;  ///< fit one charge value per edge to the radii (fit_charges)
};

/// With `equipotential`, the equipotential options of `c` (each checked at its token); without,
/// fails at the first equipotential option given ("... applies to surface=equipotential, not to
/// surface=`surface`").
std::optional<EquipotentialRequest> equipotential_request(const Call& c, bool equipotential,
                                                          const std::string& surface);

/// The equipotential surface of `skeleton` as `request` says (charge values fitted to the radii
/// with fit_radii), and `summary` gets its figures (", equipotential surface (alpha A, ...)").
std::shared_ptr<const Equipotential> build_equipotential(const Call& c, const Skeleton& skeleton,
                                                         const EquipotentialRequest& request,
                                                         std::string& summary);

/// The sentence of help texts and docs/language.md that describes the equipotential options
/// (with their defaults, default_text style).
std::string equipotential_help();

// Help texts state an options struct's default and range with ramiform::default_text
// (core/numbers.h); docs/language.md writes them the same way, after the option's name in
// backquotes; tests/cli/help_docs_test.cpp reads both.

}  // namespace ramiform::script
