// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Bracketed parametric L-systems (Prusinkiewicz & Lindenmayer, "The Algorithmic Beauty of
/// Plants" (ABOP), ch. 1-2) and a 3-D turtle that turns a derivation into a `Skeleton`.
///
/// Text format (full description and examples in docs/growth.md), one statement per line:
///
///     # a comment (also after a statement)
///     #define r1 0.9                 constant (an expression of numbers and earlier constants)
///     axiom: A(1, 0.1)               exactly one axiom
///     A(l,w) : l > 0.1 -> F(l,w)[+(30)A(l*r1,w*0.7)][-(30)A(l*r1,w*0.7)]
///     F -> F[+F]F[-F]F               production without parameters or condition
///
/// A module is one non-blank character other than `( ) , # :` optionally followed by an argument
/// list. Productions are `predecessor [: condition] -> successor`; the predecessor is one module
/// with formal parameter names; the condition (`*` or absent = always) and arguments are
/// expressions with + - * / ^, unary -, parentheses, comparisons < <= > >= == !=, && || !, and the
/// functions sqrt, sin, cos, tan (degrees), abs, floor, min, max. In each step every module is
/// replaced by the successor of the first production (in text order) whose symbol and parameter
/// count match and whose condition holds; otherwise it is kept. Context-sensitive and stochastic
/// productions are not supported.
///
/// Turtle (ABOP §1.5, 3-D): heading H starts along +z, left L along -x, up U = H x L.
/// F(l[,w]) draws a segment of length l (default `step`) and width w (default: current width);
/// f(l) moves without drawing (the next F starts a new, separate tree); + - turn left/right
/// about U, & ^ pitch down/up about L, \ / roll left/right about H, each by the argument in
/// degrees (default `angle_deg`); | turns around; $ rolls H so that L is horizontal; [ ] push and
/// pop the state; !(w) sets the width, ! without argument multiplies it by `width_factor`. Every
/// other module is ignored by the turtle. Angles that are multiples of 90 degrees rotate exactly.

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// How node radii are set.
enum class LSystemRadius {
  kWidth,  ///< radius = width / 2 of the segment ending at the node (start nodes: current width)
  kPipe,   ///< pipe model from the tips (`tip_radius`, `pipe_exponent`), see assign_pipe_radii
};

/// Options of L-system derivation and interpretation; validated at entry (InvalidArgument).
struct LSystemOptions {
  static constexpr double kMinPipeExponent = 2.0;  ///< smallest `pipe_exponent`
  static constexpr double kMaxPipeExponent = 3.0;  ///< largest `pipe_exponent`

  static constexpr int kMaxIterations = 100;  ///< most `iterations` (max_modules stops far earlier)
  int iterations = 5;                         ///< derivation steps, 0..kMaxIterations
  double angle_deg = 25;    ///< default turn angle of + - & ^ \ / (degrees), finite
  double step = 1;          ///< default length of F and f, model units, finite
  double width = 0.1;       ///< initial width (diameter), model units, > 0
  double width_factor = 0.7;       ///< `!` without argument multiplies the width by this, > 0
  LSystemRadius radius = LSystemRadius::kWidth;  ///< how radii are set
  double tip_radius = 0.02;        ///< kPipe: radius of every tip, > 0
  double pipe_exponent = 2.5;      ///< kPipe: exponent, kMinPipeExponent..kMaxPipeExponent
  std::size_t max_modules = 20'000'000;  ///< a derivation longer than this throws InvalidArgument

  void validate() const;
};

/// One module of a derivation: a symbol and its actual parameters.
struct LSystemModule {
  char symbol = 0;
  std::vector<double> params;
};

/// Parses `text` and derives `iterations` steps. A leading UTF-8 byte order mark is skipped
/// (columns count from after it). Throws InputError "source:line:column: problem" on a syntax
/// error, an undefined name or a wrong argument count (bytes of the text outside printable ASCII
/// appear in `problem` as "\xNN"), InvalidArgument when iterations < 0 or the derivation
/// exceeds `max_modules`, Cancelled when `ctx` is cancelled (checked once per step and per 65536
/// modules).
[[nodiscard]] std::vector<LSystemModule> lsystem_derive(std::string_view text,
                                                        const std::string& source, int iterations,
                                                        std::size_t max_modules = 20'000'000,
                                                        const Context* ctx = nullptr);

/// The derivation as text: symbols with their parameters, e.g. "F(1,0.5)[+(30)A(0.7)]".
/// Parameters are printed with up to 6 significant digits.
[[nodiscard]] std::string lsystem_string(std::span<const LSystemModule> modules);

/// Interprets a derivation with the turtle. Every F of non-zero length adds an edge; nodes are
/// shared where a branch starts ([ keeps the node the turtle stands on). Node 0 is the start of
/// the first F. Throws InvalidArgument when nothing is drawn, on bad options, or on unbalanced
/// brackets; Cancelled when `ctx` is cancelled (checked per 65536 modules).
[[nodiscard]] Skeleton lsystem_interpret(std::span<const LSystemModule> modules,
                                         const LSystemOptions& options,
                                         const Context* ctx = nullptr);

/// Parses, derives options.iterations steps and interprets (the errors of the three calls above).
[[nodiscard]] Skeleton lsystem_skeleton(std::string_view text, const std::string& source,
                                        const LSystemOptions& options,
                                        const Context* ctx = nullptr);

/// Ready-made systems from ABOP as name -> text (the same texts as in docs/growth.md). Each
/// text's first comment line gives the recommended iterations.
[[nodiscard]] std::vector<std::pair<std::string, std::string>> lsystem_examples();

}  // namespace ramiform
