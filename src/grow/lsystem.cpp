// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/lsystem.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <sstream>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/text.h"
#include "ramiform/core/types.h"
#include "ramiform/grow/space_colonization.h"

namespace ramiform {
namespace {

constexpr std::uint32_t kNone = UINT32_MAX;
constexpr std::size_t kModulesPerCancelCheck = std::size_t{1} << 16;

// ---- expressions ---------------------------------------------------------------------------

enum class Op {
  kNumber, kParam, kNeg, kNot, kAdd, kSub, kMul, kDiv, kPow, kLt, kLe, kGt, kGe, kEq, kNe, kAnd,
  kOr, kSqrt, kSin, kCos, kTan, kAbs, kFloor, kMin, kMax
};

struct Expr {
  Op op = Op::kNumber;
  double value = 0;  // kNumber
  int index = 0;     // kParam
  std::vector<Expr> args;
};

double eval(const Expr& e, std::span<const double> params) {
  auto a = [&](std::size_t i) { return eval(e.args[i], params); };
  const double deg = std::numbers::pi / 180;
  switch (e.op) {
    case Op::kNumber: return e.value;
    case Op::kParam: return params[static_cast<std::size_t>(e.index)];
    case Op::kNeg: return -a(0);
    case Op::kNot: return a(0) == 0 ? 1 : 0;
    case Op::kAdd: return a(0) + a(1);
    case Op::kSub: return a(0) - a(1);
    case Op::kMul: return a(0) * a(1);
    case Op::kDiv: return a(0) / a(1);
    case Op::kPow: return pm::pow(a(0), a(1));
    case Op::kLt: return a(0) < a(1) ? 1 : 0;
    case Op::kLe: return a(0) <= a(1) ? 1 : 0;
    case Op::kGt: return a(0) > a(1) ? 1 : 0;
    case Op::kGe: return a(0) >= a(1) ? 1 : 0;
    case Op::kEq: return a(0) == a(1) ? 1 : 0;
    case Op::kNe: return a(0) != a(1) ? 1 : 0;
    case Op::kAnd: return (a(0) != 0 && a(1) != 0) ? 1 : 0;
    case Op::kOr: return (a(0) != 0 || a(1) != 0) ? 1 : 0;
    case Op::kSqrt: return std::sqrt(a(0));
    case Op::kSin: return pm::sin(a(0) * deg);
    case Op::kCos: return pm::cos(a(0) * deg);
    case Op::kTan: return pm::tan(a(0) * deg);
    case Op::kAbs: return std::abs(a(0));
    case Op::kFloor: return std::floor(a(0));
    case Op::kMin: return std::min(a(0), a(1));
    case Op::kMax: return std::max(a(0), a(1));
  }
  return 0;
}

struct ModuleTemplate {
  char symbol = 0;
  std::vector<Expr> args;
};

struct Production {
  char symbol = 0;
  std::size_t arity = 0;
  bool has_condition = false;
  Expr condition;
  std::vector<ModuleTemplate> successor;
};

struct Grammar {
  std::vector<ModuleTemplate> axiom;
  std::vector<Production> productions;
};

bool is_symbol(char c) {
  return std::isgraph(static_cast<unsigned char>(c)) != 0 && c != '(' && c != ')' && c != ',' &&
         c != '#' && c != ':';
}

// A cursor over one line; columns are 1-based byte offsets in the line.
class LineParser {
 public:
  LineParser(std::string_view line, std::size_t offset, std::size_t line_no, const std::string& source,
             const std::map<std::string, double>& constants, std::vector<std::string> params)
      : s_(line), i_(offset), line_(line_no), source_(source), constants_(constants),
        params_(std::move(params)) {}

  [[noreturn]] void fail(const std::string& problem, std::size_t at) const {
    throw InputError(source_, line_, at + 1, printable_text(problem));
  }
  [[noreturn]] void fail(const std::string& problem) const { fail(problem, i_); }

  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])) != 0) ++i_;
  }
  bool at_end() {
    skip();
    return i_ >= s_.size();
  }
  bool accept(std::string_view tok) {
    skip();
    if (s_.substr(i_, tok.size()) == tok) {
      i_ += tok.size();
      return true;
    }
    return false;
  }
  void expect(std::string_view tok) {
    if (!accept(tok)) fail("expected '" + std::string(tok) + "'");
  }
  std::size_t pos() const { return i_; }

  std::string identifier() {
    skip();
    const std::size_t b = i_;
    if (i_ < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[i_])) != 0 || s_[i_] == '_')) {
      ++i_;
      while (i_ < s_.size() &&
             (std::isalnum(static_cast<unsigned char>(s_[i_])) != 0 || s_[i_] == '_'))
        ++i_;
    }
    if (b == i_) fail("expected a name");
    return std::string(s_.substr(b, i_ - b));
  }

  Expr expression() { return parse_or(); }

  // A module list (axiom or successor) up to the end of the line.
  std::vector<ModuleTemplate> modules() {
    std::vector<ModuleTemplate> out;
    while (!at_end()) {
      const char c = s_[i_];
      if (!is_symbol(c)) fail(std::string("unexpected '") + c + "'");
      ++i_;
      ModuleTemplate m{c, {}};
      if (i_ < s_.size() && s_[i_] == '(') {
        ++i_;
        do m.args.push_back(expression());
        while (accept(","));
        expect(")");
      }
      out.push_back(std::move(m));
    }
    return out;
  }

 private:
  static Expr node(Op op, std::vector<Expr> args) {
    Expr e;
    e.op = op;
    e.args = std::move(args);
    return e;
  }
  Expr parse_or() {
    Expr e = parse_and();
    while (accept("||")) e = node(Op::kOr, {std::move(e), parse_and()});
    return e;
  }
  Expr parse_and() {
    Expr e = parse_cmp();
    while (accept("&&")) e = node(Op::kAnd, {std::move(e), parse_cmp()});
    return e;
  }
  Expr parse_cmp() {
    Expr e = parse_add();
    static const std::pair<const char*, Op> ops[] = {{"<=", Op::kLe}, {">=", Op::kGe}, {"==", Op::kEq},
                                                      {"!=", Op::kNe}, {"<", Op::kLt},  {">", Op::kGt}};
    for (const auto& [tok, op] : ops)
      if (accept(tok)) return node(op, {std::move(e), parse_add()});
    return e;
  }
  Expr parse_add() {
    Expr e = parse_mul();
    for (;;) {
      if (accept("+")) e = node(Op::kAdd, {std::move(e), parse_mul()});
      else if (accept("-")) e = node(Op::kSub, {std::move(e), parse_mul()});
      else return e;
    }
  }
  Expr parse_mul() {
    Expr e = parse_unary();
    for (;;) {
      if (accept("*")) e = node(Op::kMul, {std::move(e), parse_unary()});
      else if (accept("/")) e = node(Op::kDiv, {std::move(e), parse_unary()});
      else return e;
    }
  }
  Expr parse_unary() {
    if (accept("-")) return node(Op::kNeg, {parse_unary()});
    if (accept("+")) return parse_unary();
    skip();
    if (s_.substr(i_, 2) != "!=" && accept("!")) return node(Op::kNot, {parse_unary()});
    Expr e = parse_primary();
    if (accept("^")) return node(Op::kPow, {std::move(e), parse_unary()});
    return e;
  }
  Expr parse_primary() {
    skip();
    if (i_ >= s_.size()) fail("expected an expression");
    const char c = s_[i_];
    if (accept("(")) {
      Expr e = expression();
      expect(")");
      return e;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.') {
      const std::size_t b = i_;
      while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) != 0 || s_[i_] == '.')) ++i_;
      if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
        std::size_t j = i_ + 1;
        if (j < s_.size() && (s_[j] == '+' || s_[j] == '-')) ++j;
        if (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j])) != 0) {
          i_ = j;
          while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_])) != 0) ++i_;
        }
      }
      const std::string_view text = std::string_view(s_).substr(b, i_ - b);
      double v = 0;
      if (parse_number(text, v) != NumberStatus::kOk)
        fail("bad number '" + std::string(text) + "'", b);
      Expr e;
      e.value = v;
      return e;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_') {
      const std::size_t b = i_;
      const std::string name = identifier();
      static const std::map<std::string, std::pair<Op, std::size_t>> functions = {
          {"sqrt", {Op::kSqrt, 1}}, {"sin", {Op::kSin, 1}},     {"cos", {Op::kCos, 1}},
          {"tan", {Op::kTan, 1}},   {"abs", {Op::kAbs, 1}},     {"floor", {Op::kFloor, 1}},
          {"min", {Op::kMin, 2}},   {"max", {Op::kMax, 2}}};
      skip();
      if (i_ < s_.size() && s_[i_] == '(') {
        const auto f = functions.find(name);
        if (f == functions.end()) fail("unknown function '" + name + "'", b);
        ++i_;
        std::vector<Expr> args;
        do args.push_back(expression());
        while (accept(","));
        expect(")");
        if (args.size() != f->second.second)
          fail("'" + name + "' takes " + std::to_string(f->second.second) + " argument(s)", b);
        return node(f->second.first, std::move(args));
      }
      for (std::size_t k = 0; k < params_.size(); ++k)
        if (params_[k] == name) {
          Expr e;
          e.op = Op::kParam;
          e.index = static_cast<int>(k);
          return e;
        }
      const auto it = constants_.find(name);
      if (it == constants_.end()) fail("undefined name '" + name + "'", b);
      Expr e;
      e.value = it->second;
      return e;
    }
    fail(std::string("unexpected '") + c + "' in expression");
  }

  std::string_view s_;
  std::size_t i_;
  std::size_t line_;
  const std::string& source_;
  const std::map<std::string, double>& constants_;
  std::vector<std::string> params_;
};

Grammar parse(std::string_view text, const std::string& source) {
  Grammar g;
  std::map<std::string, double> constants;
  bool have_axiom = false;
  // A UTF-8 byte order mark, which some editors write at the start of a text file, is no part
  // of the first line; columns count from after it.
  text = skip_utf8_bom(text);
  std::size_t line_no = 0, start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++line_no;
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    std::size_t first = 0;
    while (first < line.size() && std::isspace(static_cast<unsigned char>(line[first])) != 0) ++first;
    if (line.substr(first, 7) == "#define") {
      std::string_view body = line.substr(0, std::min(line.size(), line.find('#', first + 1)));
      LineParser p(body, first + 7, line_no, source, constants, {});
      const std::size_t at = p.pos();
      if (at >= body.size() || std::isspace(static_cast<unsigned char>(body[at])) == 0)
        p.fail("expected a space and a name after #define", at);
      const std::string name = p.identifier();
      const Expr e = p.expression();
      if (!p.at_end()) p.fail("unexpected text after the value");
      constants[name] = eval(e, {});
      continue;
    }
    line = line.substr(0, std::min(line.size(), line.find('#')));
    LineParser p(line, first, line_no, source, constants, {});
    if (p.at_end()) continue;
    if (p.accept("axiom")) {
      const std::size_t at = first;
      p.expect(":");
      if (have_axiom) p.fail("a second axiom", at);
      g.axiom = p.modules();
      if (g.axiom.empty()) p.fail("the axiom is empty", at);
      have_axiom = true;
      continue;
    }
    const std::size_t arrow = line.find("->");
    if (arrow == std::string_view::npos)
      p.fail("expected 'axiom: ...', '#define NAME VALUE' or a production 'A -> ...'");
    // Predecessor (symbol and formal parameters) and optional condition.
    Production prod;
    std::string_view left = line.substr(0, arrow);
    LineParser lp(left, first, line_no, source, constants, {});
    const char c = line[first];
    if (!is_symbol(c) || c == '-') lp.fail("expected a module symbol");
    prod.symbol = c;
    std::vector<std::string> formals;
    LineParser fp(left, first + 1, line_no, source, constants, {});
    if (first + 1 < left.size() && left[first + 1] == '(') {
      fp.expect("(");
      do {
        const std::size_t at = fp.pos();
        std::string name = fp.identifier();
        for (const auto& f : formals)
          if (f == name) fp.fail("parameter '" + name + "' repeated", at);
        formals.push_back(std::move(name));
      } while (fp.accept(","));
      fp.expect(")");
    }
    prod.arity = formals.size();
    LineParser cp(left, fp.pos(), line_no, source, constants, formals);
    if (cp.accept(":")) {
      if (!cp.accept("*")) {
        prod.condition = cp.expression();
        prod.has_condition = true;
      }
    }
    if (!cp.at_end()) cp.fail("expected ':' condition or '->'");
    LineParser sp(line, arrow + 2, line_no, source, constants, formals);
    prod.successor = sp.modules();
    g.productions.push_back(std::move(prod));
  }
  if (!have_axiom) throw InputError(source, line_no, "no 'axiom:' line");
  return g;
}

void instantiate(const std::vector<ModuleTemplate>& templates, std::span<const double> params,
                 std::vector<LSystemModule>& out) {
  for (const auto& t : templates) {
    LSystemModule m{t.symbol, {}};
    m.params.reserve(t.args.size());
    for (const auto& a : t.args) m.params.push_back(eval(a, params));
    out.push_back(std::move(m));
  }
}

// ---- turtle ----------------------------------------------------------------------------------

// cos and sin of an angle in degrees, exact at multiples of 90 degrees.
std::pair<double, double> cos_sin_deg(double a) {
  double r = std::fmod(a, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0) return {1, 0};
  if (r == 90) return {0, 1};
  if (r == 180) return {-1, 0};
  if (r == 270) return {0, -1};
  const double rad = r * std::numbers::pi / 180;
  return {pm::cos(rad), pm::sin(rad)};
}

// Rotates a toward b by angle (degrees) in the plane of the orthonormal pair (a, b).
void rotate(Vec3& a, Vec3& b, double angle) {
  const auto [c, s] = cos_sin_deg(angle);
  const Vec3 na = a * c + b * s;
  const Vec3 nb = b * c - a * s;
  a = na;
  b = nb;
}

struct Turtle {
  Vec3 pos = Vec3::Zero();
  Vec3 h = Vec3::UnitZ();
  Vec3 l = -Vec3::UnitX();
  Vec3 u = Vec3(0, -1, 0);  // H x L
  double width = 0;
  std::uint32_t node = kNone;
};

void check_option(bool ok, const std::string& what) {
  if (!ok) throw InvalidArgument("L-system: " + what);
}

}  // namespace

void LSystemOptions::validate() const {
  check_option(iterations >= 0 && iterations <= kMaxIterations,
               "iterations must be in " + range_text(0, kMaxIterations));
  check_option(std::isfinite(angle_deg), "angle_deg must be finite");
  check_option(std::isfinite(step), "step must be finite");
  check_option(std::isfinite(width) && width > 0, "width must be finite and > 0");
  check_option(std::isfinite(width_factor) && width_factor > 0, "width_factor must be finite and > 0");
  check_option(std::isfinite(tip_radius) && tip_radius > 0, "tip_radius must be finite and > 0");
  check_option(pipe_exponent >= kMinPipeExponent && pipe_exponent <= kMaxPipeExponent,
               "pipe_exponent must be in " + range_text(kMinPipeExponent, kMaxPipeExponent));
  check_option(max_modules > 0, "max_modules must be > 0");
}

std::vector<LSystemModule> lsystem_derive(std::string_view text, const std::string& source,
                                          int iterations, std::size_t max_modules,
                                          const Context* ctx) {
  check_option(iterations >= 0, "iterations must be >= 0");
  const Grammar g = parse(text, source);
  std::vector<LSystemModule> cur;
  instantiate(g.axiom, {}, cur);
  std::map<char, std::vector<const Production*>> by_symbol;
  for (const auto& p : g.productions) by_symbol[p.symbol].push_back(&p);
  for (int it = 0; it < iterations; ++it) {
    std::vector<LSystemModule> next;
    next.reserve(cur.size() * 2);
    for (std::size_t k = 0; k < cur.size(); ++k) {
      if (k % kModulesPerCancelCheck == 0) check_cancel(ctx);
      LSystemModule& m = cur[k];
      const Production* use = nullptr;
      if (auto f = by_symbol.find(m.symbol); f != by_symbol.end())
        for (const Production* p : f->second)
          if (p->arity == m.params.size() && (!p->has_condition || eval(p->condition, m.params) != 0)) {
            use = p;
            break;
          }
      if (use == nullptr) next.push_back(std::move(m));
      else instantiate(use->successor, m.params, next);
      check_option(next.size() <= max_modules,
                   "the derivation exceeds max_modules (" + std::to_string(max_modules) +
                       ") at iteration " + std::to_string(it + 1));
    }
    cur = std::move(next);
  }
  return cur;
}

std::string lsystem_string(std::span<const LSystemModule> modules) {
  std::ostringstream s;
  s.precision(6);
  for (const auto& m : modules) {
    s << m.symbol;
    if (!m.params.empty()) {
      s << '(';
      for (std::size_t k = 0; k < m.params.size(); ++k) s << (k ? "," : "") << m.params[k];
      s << ')';
    }
  }
  return s.str();
}

Skeleton lsystem_interpret(std::span<const LSystemModule> modules, const LSystemOptions& options,
                           const Context* ctx) {
  options.validate();
  Skeleton s;
  std::vector<std::uint32_t> starts;
  std::vector<Turtle> stack;
  Turtle t;
  t.width = options.width;
  auto new_node = [&](const Vec3& p, std::size_t k) {
    check_option(std::isfinite(t.width) && t.width > 0,
                 "the width must stay finite and > 0 (module " + std::to_string(k) + ")");
    check_option(is_finite(p), "the turtle left finite space (module " + std::to_string(k) + ")");
    s.nodes.push_back({p, t.width / 2});
    return static_cast<std::uint32_t>(s.nodes.size() - 1);
  };
  for (std::size_t k = 0; k < modules.size(); ++k) {
    if (k % kModulesPerCancelCheck == 0) check_cancel(ctx);
    const LSystemModule& m = modules[k];
    const auto arg = [&](std::size_t i, double fallback) {
      return m.params.size() > i ? m.params[i] : fallback;
    };
    switch (m.symbol) {
      case 'F': {
        if (m.params.size() > 1) t.width = m.params[1];
        const double len = arg(0, options.step);
        if (len == 0) break;
        if (t.node == kNone) {
          t.node = new_node(t.pos, k);
          starts.push_back(t.node);
        }
        t.pos += len * t.h;
        const std::uint32_t v = new_node(t.pos, k);
        s.edges.push_back({t.node, v});
        t.node = v;
        break;
      }
      case 'f':
        t.pos += arg(0, options.step) * t.h;
        t.node = kNone;
        break;
      case '+': rotate(t.h, t.l, arg(0, options.angle_deg)); break;
      case '-': rotate(t.h, t.l, -arg(0, options.angle_deg)); break;
      case '&': rotate(t.h, t.u, -arg(0, options.angle_deg)); break;
      case '^': rotate(t.h, t.u, arg(0, options.angle_deg)); break;
      case '\\': rotate(t.l, t.u, arg(0, options.angle_deg)); break;
      case '/': rotate(t.l, t.u, -arg(0, options.angle_deg)); break;
      case '|':
        t.h = -t.h;
        t.l = -t.l;
        break;
      case '$': {
        const Vec3 side = Vec3::UnitZ().cross(t.h);
        if (side.norm() > 1e-12) {  // heading not vertical
          t.l = side.normalized();
          t.u = t.h.cross(t.l);
        }
        break;
      }
      case '!': t.width = m.params.empty() ? t.width * options.width_factor : m.params[0]; break;
      case '[':
        // Branches share the node the turtle stands on.
        if (t.node == kNone) {
          t.node = new_node(t.pos, k);
          starts.push_back(t.node);
        }
        stack.push_back(t);
        break;
      case ']':
        check_option(!stack.empty(), "unbalanced ']' (module " + std::to_string(k) + ")");
        t = stack.back();
        stack.pop_back();
        break;
      default: break;
    }
  }
  check_option(stack.empty(), "unbalanced '[': " + std::to_string(stack.size()) + " left open");
  check_option(!s.edges.empty(), "the derivation draws no segment (no F of non-zero length)");
  // Drop nodes created for a '[' whose branches drew nothing.
  std::vector<std::uint32_t> deg(s.nodes.size(), 0), remap(s.nodes.size(), kNone);
  for (const auto& e : s.edges) ++deg[e[0]], ++deg[e[1]];
  std::vector<SkeletonNode> kept;
  for (std::uint32_t v = 0; v < s.nodes.size(); ++v)
    if (deg[v] > 0) {
      remap[v] = static_cast<std::uint32_t>(kept.size());
      kept.push_back(s.nodes[v]);
    }
  s.nodes = std::move(kept);
  for (auto& e : s.edges) e = {remap[e[0]], remap[e[1]]};
  if (options.radius == LSystemRadius::kPipe) {
    std::vector<std::uint32_t> roots;
    for (const std::uint32_t v : starts)
      if (remap[v] != kNone) roots.push_back(remap[v]);
    assign_pipe_radii(s, roots, options.tip_radius, options.pipe_exponent);
  }
  return s;
}

Skeleton lsystem_skeleton(std::string_view text, const std::string& source,
                          const LSystemOptions& options, const Context* ctx) {
  options.validate();
  const auto modules = lsystem_derive(text, source, options.iterations, options.max_modules, ctx);
  return lsystem_interpret(modules, options, ctx);
}

std::vector<std::pair<std::string, std::string>> lsystem_examples() {
  return {
      {"bush-2d",
       "# ABOP Fig. 1.24a (edge rewriting), recommended iterations: 5\n"
       "#define a 25.7\n"
       "axiom: F\n"
       "F -> F[+(a)F]F[-(a)F]F\n"},
      {"plant-2d",
       "# ABOP Fig. 1.24f (node rewriting), recommended iterations: 5\n"
       "#define a 22.5\n"
       "axiom: X\n"
       "X -> F-(a)[[X]+(a)X]+(a)F[+(a)FX]-(a)X\n"
       "F -> FF\n"},
      {"bush-3d",
       "# ABOP Fig. 1.25 without leaves, recommended iterations: 6\n"
       "#define a 22.5\n"
       "axiom: A\n"
       "A -> [&(a)F!A]/(5*a)[&(a)F!A]/(7*a)[&(a)F!A]\n"
       "F -> S/(5*a)F\n"
       "S -> F\n"},
      {"monopodial",
       "# ABOP Fig. 2.6a (Honda's monopodial tree), widths in model units,\n"
       "# recommended iterations: 10\n"
       "#define r1 0.9    # contraction ratio of the trunk\n"
       "#define r2 0.6    # contraction ratio of the branches\n"
       "#define a0 45     # branching angle from the trunk\n"
       "#define a2 45     # branching angle of lateral axes\n"
       "#define d 137.5   # divergence angle\n"
       "#define wr 0.707  # width decrease rate\n"
       "axiom: A(1, 0.1)\n"
       "A(l,w) -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"
       "B(l,w) -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"
       "C(l,w) -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n"},
      {"binary",
       "# A parametric binary tree with a stop condition, recommended iterations: 8\n"
       "axiom: A(1, 0.1)\n"
       "A(l,w) : l > 0.1 -> F(l,w)[+(30)/(90)A(l*0.7,w*0.7)][-(30)/(90)A(l*0.7,w*0.7)]\n"},
  };
}

}  // namespace ramiform
