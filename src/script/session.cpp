// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "session.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/text.h"
#include "ramiform/io/atomic_file.h"

namespace ramiform {
namespace script {
namespace {

namespace fs = std::filesystem;

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
}

std::string join(const std::vector<std::string>& words, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) out += (i > 0 ? sep : "") + words[i];
  return out;
}

// A library message without a leading "COMMAND: " that the location prefix repeats
// ("union: union: ..." reads "union: ...").
std::string without_prefix(const std::string& message, const std::string& command) {
  const std::string prefix = command + ": ";
  return message.compare(0, prefix.size(), prefix) == 0 ? message.substr(prefix.size()) : message;
}

std::string hint(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string best = closest_name(word, candidates);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

// Replaces $NAME and ${NAME} by declared parameter values. `room`: how many bytes the
// substituted token may have, so that the whole line stays within kMaxSubstitutedLine.
std::string substitute(const Token& token, const ScriptSession::Impl& session,
                       const std::string& command, const std::string& file, std::size_t line,
                       std::size_t room) {
  const std::string& t = token.text;
  if (t.find('$') == std::string::npos) return t;
  std::string out;
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] != '$') {
      out += t[i++];
      continue;
    }
    std::size_t start = i + 1;
    std::size_t end = start;
    const bool braced = start < t.size() && t[start] == '{';
    if (braced) {
      end = t.find('}', start);
      if (end == std::string::npos) {
        throw InputError(file, line, token.column + i, "unterminated '${' in '" + shown(t) + "'");
      }
      ++start;
    } else {
      while (end < t.size() &&
             (std::isalnum(static_cast<unsigned char>(t[end])) != 0 || t[end] == '_'))
        ++end;
    }
    const std::string name = t.substr(start, end - start);
    const auto it = session.params.find(name);
    if (it == session.params.end()) {
      std::vector<std::string> known;
      for (const auto& [k, v] : session.params) known.push_back(k);
      throw InputError(file, line, token.column + i,
                       "unknown parameter '$" + shown(name) + "'" + hint(name, known) +
                           "; declare it first with 'param " +
                           (name.empty() ? "NAME" : shown(name)) + " VALUE'");
    }
    if (it->second.size() > room || out.size() > room - it->second.size()) {
      throw InputError(file, line, token.column + i,
                       command + ": line " + std::to_string(line) + " grows beyond the limit of " +
                           std::to_string(kMaxSubstitutedLine) +
                           " bytes (kMaxSubstitutedLine) when its parameters are substituted");
    }
    out += it->second;
    i = braced ? end + 1 : end;
  }
  return out;
}

}  // namespace

std::string shown(std::string_view text) { return printable_text(text, 48); }

std::string_view without_bom(std::string_view text) { return skip_utf8_bom(text); }

std::vector<Token> tokenize(std::string_view text, const std::string& file, std::size_t line) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      ++i;
      continue;
    }
    if (c == '#') break;
    Token token;
    token.column = i + 1;
    if (c == '"') {
      const std::size_t close = text.find('"', i + 1);
      if (close == std::string_view::npos) {
        throw InputError(file, line, i + 1, "unterminated quote");
      }
      token.text = std::string(text.substr(i + 1, close - i - 1));
      i = close + 1;
    } else {
      const std::size_t start = i;
      while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' &&
             text[i] != '\n' && text[i] != '#') {
        ++i;
      }
      token.text = std::string(text.substr(start, i - start));
    }
    out.push_back(std::move(token));
  }
  return out;
}

std::string kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kShape:
      return "shape";
    case ObjectKind::kCurve2:
      return "2-D curve";
    case ObjectKind::kCurve3:
      return "3-D path";
    case ObjectKind::kDeformation:
      return "deformation";
  }
  return "object";
}

std::string format_vec3(const Vec3& v) {
  return format_number(v.x()) + "," + format_number(v.y()) + "," + format_number(v.z());
}

const std::map<std::string, const CommandSpec*>& command_table() {
  static const std::vector<CommandSpec> specs = [] {
    std::vector<CommandSpec> all;
    add_shape_commands(all);
    add_skeletal_commands(all);
    add_curve_commands(all);
    add_output_commands(all);
    add_growth_commands(all);
    add_point_commands(all);
    add_draw_commands(all);
    return all;
  }();
  static const std::map<std::string, const CommandSpec*> table = [] {
    std::map<std::string, const CommandSpec*> t;
    for (const CommandSpec& spec : specs) {
      t[spec.name] = &spec;
      for (const std::string& alias : spec.aliases) t[alias] = &spec;
    }
    return t;
  }();
  return table;
}

Call::Call(ScriptSession::Impl& session, const CommandSpec& spec, std::vector<Token> tokens,
           std::string file, std::size_t line)
    : session_(session),
      spec_(spec),
      command_(tokens.front()),
      file_(std::move(file)),
      line_(line) {
  std::size_t line_size = 0;  // the substituted tokens' sizes so far
  for (std::size_t i = 1; i < tokens.size(); ++i) {
    Token token = tokens[i];
    const std::size_t room = kMaxSubstitutedLine - std::min(line_size, kMaxSubstitutedLine);
    token.text = substitute(token, session, spec.name, file_, line_, room);
    line_size += token.text.size();
    const std::size_t eq = token.text.find('=');
    if (eq != std::string::npos && eq > 0) {
      const std::string key = token.text.substr(0, eq);
      const bool any =
          std::find(spec.options.begin(), spec.options.end(), "*") != spec.options.end();
      if (!any && std::find(spec.options.begin(), spec.options.end(), key) == spec.options.end()) {
        fail(token, "unknown option '" + shown(key) + "'" + hint(key, spec.options) +
                        (spec.options.empty() ? "; it takes no options"
                                              : "; options: " + join(spec.options, ", ")));
      }
      if (has_option(key)) fail(token, "option '" + shown(key) + "' given twice");
      Token value{token.text.substr(eq + 1), token.column + eq + 1};
      options_.emplace_back(key, std::move(value));
    } else {
      positional_.push_back(std::move(token));
    }
  }
}

void Call::fail(const Token& token, const std::string& problem) const {
  // Commands quote their tokens with shown(); escaping the whole problem as well keeps a
  // message printable when a library message or a command echoes text unescaped.
  throw InputError(file_, line_, token.column, spec_.name + ": " + printable_text(problem));
}

void Call::fail(const std::string& problem) const { fail(command_, problem); }

const Token& Call::arg(std::size_t i) const {
  if (i >= positional_.size())
    fail("missing argument " + std::to_string(i + 1) + "; usage: " + spec_.synopsis);
  return positional_[i];
}

void Call::expect_count(std::size_t min, std::size_t max, const std::string& what) const {
  if (positional_.size() < min) {
    fail("expected " + what + ", got " + std::to_string(positional_.size()) +
         " argument(s); usage: " + spec_.synopsis);
  }
  if (positional_.size() > max) {
    fail(positional_[max], "unexpected argument '" + shown(positional_[max].text) + "': expected " +
                               what + "; usage: " + spec_.synopsis);
  }
}

std::string Call::new_name(std::size_t i) const {
  const Token& t = arg(i);
  if (t.text.size() > kMaxNameLength) {
    fail(t, "an object name is at most " + std::to_string(kMaxNameLength) + " characters, got " +
                std::to_string(t.text.size()) + " ('" + shown(t.text) + "')");
  }
  const bool ok = !t.text.empty() && std::isdigit(static_cast<unsigned char>(t.text[0])) == 0 &&
                  t.text[0] != '-' && t.text[0] != '.' &&
                  std::all_of(t.text.begin(), t.text.end(), is_name_char);
  if (!ok) {
    fail(t, "'" + shown(t.text) +
                "' is not a valid object name (letters, digits, '_', '-', '.'; not starting with a "
                "digit)");
  }
  return t.text;
}

double Call::parse_number(const Token& token, const std::string& what) const {
  const std::string& s = token.text;
  double v = 0;
  const NumberStatus status = ramiform::parse_number(s, v);
  if (status == NumberStatus::kNotFinite) {
    fail(token, what + " must be finite, got '" + shown(s) + "'");
  }
  if (status != NumberStatus::kOk) {
    fail(token, "expected a number for " + what + ", got '" + shown(s) + "'");
  }
  return v;
}

double Call::number(std::size_t i, const std::string& what) const {
  return parse_number(arg(i), what);
}

double Call::positive(std::size_t i, const std::string& what) const {
  const double v = number(i, what);
  if (!(v > 0)) fail(arg(i), what + " must be > 0, got " + arg(i).text);
  return v;
}

int Call::integer(std::size_t i, const std::string& what) const {
  const double v = number(i, what);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    fail(arg(i), what + " must be an integer, got " + arg(i).text);
  return static_cast<int>(v);
}

Vec3 Call::parse_vec3(const Token& token, const std::string& what) const {
  Vec3 v;
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = token.text.find(',', start);
    if ((k < 2) != (comma != std::string::npos)) {
      fail(token, "expected X,Y,Z (three numbers separated by commas) for " + what + ", got '" +
                      shown(token.text) + "'");
    }
    const std::size_t stop = k < 2 ? comma : token.text.size();
    const Token part{token.text.substr(start, stop - start), token.column + start};
    v[k] = parse_number(part, what);
    start = stop + 1;
  }
  return v;
}

const Object& Call::object_named(const Token& token, ObjectKind kind) const {
  const auto it = session_.objects.find(token.text);
  if (it == session_.objects.end()) {
    std::vector<std::string> known;
    for (const auto& [name, obj] : session_.objects) {
      if (obj.kind == kind) known.push_back(name);
    }
    fail(token, "unknown " + kind_name(kind) + " '" + shown(token.text) + "'" +
                    hint(token.text, known) + (known.empty() ? "; none is defined yet" : ""));
  }
  if (it->second.kind != kind) {
    fail(token, "'" + shown(token.text) + "' is a " + kind_name(it->second.kind) + ", expected a " +
                    kind_name(kind));
  }
  return it->second;
}

const Object& Call::object(std::size_t i, ObjectKind kind) const {
  return object_named(arg(i), kind);
}

std::string Call::input_path(const Token& token) const {
  fs::path p(token.text);
  if (p.is_relative()) p = fs::path(session_.input_dir) / p;
  // A file written earlier in this script is still staged, without a name where Linux allows:
  // it gets its staging name until this command ends (~Call).
  for (const Staged& s : session_.staged) {
    if (fs::path(s.final_path).lexically_normal() != p.lexically_normal()) continue;
    show_held_file(s.staged_path);
    session_.shown.push_back(s.staged_path);
    return s.staged_path;
  }
  std::error_code ec;
  if (!fs::exists(p, ec)) fail(token, "cannot read '" + shown(p.string()) + "': no such file");
  if (!fs::is_regular_file(p, ec))
    fail(token, "cannot read '" + shown(p.string()) + "': not a regular file");
  return p.string();
}

std::string Call::input_path(std::size_t i) const { return input_path(arg(i)); }

std::string Call::written_or_input_path(std::size_t i) const {
  return written_or_input_path(arg(i));
}

std::string Call::written_or_input_path(const Token& t) const {
  const fs::path rel(t.text);
  if (rel.is_relative()) {
    const fs::path written = (fs::path(session_.options.out_dir) / rel).lexically_normal();
    for (const Staged& s : session_.staged) {
      if (fs::path(s.final_path).lexically_normal() != written) continue;
      show_held_file(s.staged_path);
      session_.shown.push_back(s.staged_path);
      return s.staged_path;
    }
  }
  return input_path(t);
}

std::string Call::output_path(std::size_t i) { return output_path(arg(i), arg(i).text); }

std::string Call::output_path(const Token& t, const std::string& name) {
  fs::path rel(name);
  const fs::path out = fs::path(session_.options.out_dir);
  if (!session_.options.allow_any_path) {
    const fs::path norm = rel.lexically_normal();
    const bool escapes = rel.is_absolute() || norm.empty() || *norm.begin() == "..";
    if (escapes) {
      fail(t, "output '" + shown(name) +
                  "' is outside the output directory; use a path inside --out "
                  "or pass --allow-any-path");
    }
  }
  const fs::path final_path = rel.is_absolute() ? rel : out / rel;
  if (final_path.filename().empty()) fail(t, "output '" + shown(name) + "' names no file");
  std::error_code ec;
  const fs::path dir = final_path.parent_path().empty() ? fs::path(".") : final_path.parent_path();
  if (!fs::is_directory(dir, ec)) {
    fail(t, "cannot write '" + shown(final_path.string()) + "': directory '" + shown(dir.string()) +
                "' does not exist");
  }
  for (const Staged& s : session_.staged) {
    if (s.final_path == final_path.string()) return s.staged_path;  // written twice: last wins
  }
  const fs::path staged = dir / (".rf-staged-" + std::to_string(session_.staged.size()) + "-" +
                                 final_path.filename().string());
  session_.staged.push_back({final_path.string(), staged.string()});
  hold_file(staged.string());  // unnamed where Linux allows, else removed by a stop signal
  return staged.string();
}

Call::~Call() {
  for (const std::string& path : session_.shown) hide_held_file(path);
  session_.shown.clear();
}

const Token* Call::option_token(const std::string& key) const {
  for (const auto& [k, v] : options_) {
    if (k == key) return &v;
  }
  return nullptr;
}

bool Call::has_option(const std::string& key) const { return option_token(key) != nullptr; }

double Call::option_number(const std::string& key, double fallback) const {
  const Token* t = option_token(key);
  return t == nullptr ? fallback : parse_number(*t, key);
}

double Call::option_positive(const std::string& key, double fallback) const {
  const Token* t = option_token(key);
  if (t == nullptr) return fallback;
  const double v = parse_number(*t, key);
  if (!(v > 0)) fail(*t, key + " must be > 0, got " + t->text);
  return v;
}

int Call::option_integer(const std::string& key, int fallback, int min, int max) const {
  const Token* t = option_token(key);
  if (t == nullptr) return fallback;
  const double v = parse_number(*t, key);
  if (v != std::floor(v) || v < min || v > max) {
    fail(*t, key + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
                 "], got " + t->text);
  }
  return static_cast<int>(v);
}

Vec3 Call::option_vec3(const std::string& key, const Vec3& fallback) const {
  const Token* t = option_token(key);
  return t == nullptr ? fallback : parse_vec3(*t, key);
}

std::string Call::option_word(const std::string& key, const std::string& fallback,
                              const std::vector<std::string>& allowed) const {
  const Token* t = option_token(key);
  if (t == nullptr) return fallback;
  if (std::find(allowed.begin(), allowed.end(), t->text) == allowed.end()) {
    fail(*t, key + " must be one of " + join(allowed, ", ") + ", got '" + shown(t->text) + "'" +
                 hint(t->text, allowed));
  }
  return t->text;
}

void Call::define(const std::string& name, Object object) {
  if (object.summary.size() > kMaxSummary) {
    object.summary.resize(kMaxSummary - 3);
    object.summary += "...";
  }
  if (object.kind == ObjectKind::kShape || session_.objects.count(name) != 0) {
    auto& order = session_.shape_order;
    order.erase(std::remove(order.begin(), order.end(), name), order.end());
    if (object.kind == ObjectKind::kShape) order.push_back(name);
  }
  session_.objects[name] = std::move(object);
}

std::string summary_text(const Object& object) {
  if (object.more_transforms == 0) return object.summary;
  return object.summary + ", ... (" + std::to_string(object.more_transforms) + " more transform" +
         (object.more_transforms == 1 ? ")" : "s)");
}

namespace {

// The range of alpha that make_equipotential accepts (field/equipotential.h), checked here too
// so that the error points at the token.
constexpr double kMinAlpha = 2.0;
constexpr double kMaxAlpha = 16.0;

}  // namespace

const std::vector<std::string>& equipotential_keys() {
  static const std::vector<std::string> keys = {
      "alpha", "charge", "charge_spacing", "lambda", "lambda_scale", "open_ends", "fit_radii"};
  return keys;
}

std::optional<EquipotentialRequest> equipotential_request(const Call& c, bool equipotential,
                                                          const std::string& surface) {
  if (!equipotential) {
    for (const std::string& key : equipotential_keys()) {
      if (const Token* t = c.option_token(key)) {
        c.fail(*t, key + "= applies to surface=equipotential, not to surface=" + surface);
      }
    }
    return std::nullopt;
  }
  EquipotentialRequest r;
  EquipotentialOptions& o = r.options;
  o.alpha = c.option_number("alpha", o.alpha);
  if (!(o.alpha >= kMinAlpha && o.alpha <= kMaxAlpha)) {
    c.fail(*c.option_token("alpha"), "alpha must be in " + range_text(kMinAlpha, kMaxAlpha) +
                                         ", got " + c.option_token("alpha")->text);
  }
  o.charge = c.option_positive("charge", o.charge);
  o.charge_spacing = c.option_positive("charge_spacing", o.charge_spacing);
  o.lambda = c.option_positive("lambda", o.lambda);
  o.lambda_scale = c.option_positive("lambda_scale", o.lambda_scale);
  o.open_ends = c.option_word("open_ends", o.open_ends ? "yes" : "no", {"yes", "no"}) == "yes";
  r.fit_radii = c.option_word("fit_radii", "no", {"yes", "no"}) == "yes";
  // The potential is linear in the charges: the fit meets any lambda with scaled charges, so a
  // lambda_scale would change the numbers but not the surface.
  if (r.fit_radii && c.has_option("lambda_scale")) {
    c.fail(*c.option_token("lambda_scale"),
           "lambda_scale= does not change the surface with fit_radii=yes (the fitted charges "
           "scale with lambda); leave one of them out");
  }
  return r;
}

std::shared_ptr<const Equipotential> build_equipotential(const Call& c, const Skeleton& skeleton,
                                                         const EquipotentialRequest& request,
                                                         std::string& summary) {
  const EquipotentialOptions& o = request.options;
  auto eq = std::make_shared<Equipotential>(make_equipotential(skeleton, o));
  std::string fitted;
  if (request.fit_radii) {
    const ChargeFitResult fit =
        fit_charges(eq->charges, skeleton, eq->lambda, {}, o.theta, c.session().ctx);
    set_edge_charges(eq->charges, fit.edge_values);
    eq->field = make_equipotential_field(eq->charges, eq->lambda, o.theta);
    fitted = "; charges fitted to the radii, potential residual rms " +
             format_number(fit.residual_rms) + ", max " + format_number(fit.residual_max);
  }
  std::size_t open = 0;
  for (const std::uint8_t flag : eq->charges.open) open += flag != 0 ? 1 : 0;
  summary += ", equipotential surface (alpha " + format_number(eq->charges.alpha) + ", " +
             std::to_string(eq->charges.positions.size()) + " charges, lambda " +
             format_number(eq->lambda) +
             (open > 0 ? ", " + std::to_string(open) + " open end(s)" : "") + fitted + ")";
  return eq;
}

std::string equipotential_help() {
  const EquipotentialOptions o;
  return "surface=equipotential is the potential of point charges along the skeleton (Gruber & "
         "Wallner 2014), f = sum q_i / |p - c_i|^(alpha - 1), with the surface at f = lambda: "
         "`alpha`" +
         default_text(o.alpha, kMinAlpha, kMaxAlpha) +
         " (higher is more cylindrical, sharper blends); `charge`, one charge value for every "
         "edge (default per edge from its radii); `charge_spacing`, the distance between charges "
         "along an edge (default per edge " +
         format_number(o.spacing_factor) +
         " times its smaller node radius); `lambda`, the iso value (default estimated by the "
         "paper's eq. 2) times `lambda_scale`" +
         default_text(o.lambda_scale) +
         " (smaller is thicker: Figure 4); `open_ends`=yes|no (default no) makes every leaf an "
         "open, sharp-edged end (a skeleton file's \"end\": \"open\" opens one); "
         "`fit_radii`=yes|no (default no) fits one charge value per edge so that the surface "
         "passes through the radii";
}

}  // namespace script

std::string closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 2) + 1;
  for (const std::string& c : candidates) {
    // Levenshtein distance, two rows.
    std::vector<std::size_t> prev(c.size() + 1), cur(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        const std::size_t sub =
            prev[j - 1] + (std::tolower(static_cast<unsigned char>(word[i - 1])) ==
                                   std::tolower(static_cast<unsigned char>(c[j - 1]))
                               ? 0
                               : 1);
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
      }
      std::swap(prev, cur);
    }
    if (prev[c.size()] < best_d) {
      best_d = prev[c.size()];
      best = c;
    }
  }
  return best;
}

ScriptSession::ScriptSession(ScriptOptions options, Context* ctx)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->ctx = ctx;
  impl_->input_dir = impl_->options.input_dir.empty() ? "." : impl_->options.input_dir;
  std::error_code ec;
  if (!std::filesystem::is_directory(impl_->options.out_dir, ec)) {
    throw InvalidArgument("output directory '" + impl_->options.out_dir + "' does not exist");
  }
}

ScriptSession::~ScriptSession() { discard(); }

CommandResult ScriptSession::execute_line(std::string_view text, const std::string& file,
                                          std::size_t line) {
  // A UTF-8 byte order mark that an editor wrote at the start of a script (run_text's line 1,
  // or the shell's first line) is no part of the first command.
  if (line == 1) text = script::without_bom(text);
  std::vector<script::Token> tokens = script::tokenize(text, file, line);
  if (tokens.empty()) return {};
  const auto& table = script::command_table();
  const auto it = table.find(tokens.front().text);
  if (it == table.end()) {
    throw InputError(file, line, tokens.front().column,
                     "unknown command '" + script::shown(tokens.front().text) + "'" +
                         script::hint(tokens.front().text, command_names()) +
                         "; 'help' lists the commands");
  }
  script::Call call(*impl_, *it->second, std::move(tokens), file, line);
  try {
    CommandResult result = it->second->run(call);
    result.command = it->second->name;
    return result;
  } catch (const InputError& e) {
    if (e.file() == file) throw;
    call.fail(e.what());  // an input file's error, located at the command that read it
  } catch (const Cancelled&) {
    throw;
  } catch (const InvalidArgument& e) {
    call.fail(script::without_prefix(e.what(), it->second->name));
  } catch (const Failure& e) {
    call.fail(script::without_prefix(e.what(), it->second->name));
  }
}

std::vector<CommandResult> ScriptSession::run_text(std::string_view text, const std::string& file) {
  std::vector<CommandResult> results;
  std::size_t line = 1;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    check_cancel(impl_->ctx);
    CommandResult r = execute_line(text.substr(start, end - start), file, line);
    if (!r.command.empty()) results.push_back(std::move(r));
    start = end + 1;
    ++line;
  }
  for (const auto& [name, value] : impl_->options.params) {
    if (impl_->declared.count(name) == 0) {
      std::vector<std::string> known(impl_->declared.begin(), impl_->declared.end());
      throw InputError(file, 0,
                       "--set " + script::shown(name) + "=" + script::shown(value) +
                           ": the script declares no parameter '" + script::shown(name) + "'" +
                           script::hint(name, known) +
                           (known.empty() ? "" : "; it declares: " + script::join(known, ", ")));
    }
  }
  return results;
}

std::vector<CommandResult> ScriptSession::run_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec))
    throw InputError(path, 0, "cannot read the script");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (impl_->options.input_dir.empty()) {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    impl_->input_dir = dir.empty() ? "." : dir.string();
  }
  return run_text(buffer.str(), path);
}

std::vector<std::string> ScriptSession::commit() {
  std::vector<std::string> done;
  for (const script::Staged& s : impl_->staged) {
    publish_held_file(s.staged_path, s.final_path);
    done.push_back(s.final_path);
  }
  impl_->staged.clear();
  return done;
}

void ScriptSession::discard() noexcept {
  if (!impl_) return;
  for (const script::Staged& s : impl_->staged) drop_held_file(s.staged_path);
  impl_->staged.clear();
}

FieldPtr ScriptSession::shape(const std::string& name) const {
  const auto it = impl_->objects.find(name);
  if (it == impl_->objects.end()) {
    std::vector<std::string> names;
    for (const auto& [n, o] : impl_->objects) {
      if (o.kind == script::ObjectKind::kShape) names.push_back(n);
    }
    const std::string hint = closest_name(name, names);
    throw InvalidArgument("no shape named '" + name + "'" +
                          (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
  }
  if (it->second.kind != script::ObjectKind::kShape) {
    throw InvalidArgument("'" + name + "' is a " + script::kind_name(it->second.kind) +
                          ", not a shape");
  }
  return it->second.field;
}

std::vector<std::string> ScriptSession::shape_names() const { return impl_->shape_order; }

const std::vector<ScriptParam>& ScriptSession::params() const { return impl_->param_list; }

std::vector<std::string> ScriptSession::staged_outputs() const {
  std::vector<std::string> paths;
  for (const script::Staged& s : impl_->staged) paths.push_back(s.final_path);
  return paths;
}

std::vector<CommandInfo> ScriptSession::commands() {
  std::vector<CommandInfo> out;
  for (const auto& [name, spec] : script::command_table()) {
    if (spec->name == name) out.push_back({name, spec->synopsis, spec->description, spec->options});
  }
  return out;
}

std::vector<std::string> ScriptSession::command_names() {
  std::vector<std::string> names;
  for (const auto& [name, spec] : script::command_table()) {
    if (spec->name == name) names.push_back(name);
  }
  return names;
}

std::string ScriptSession::command_help(const std::string& name) {
  const auto& table = script::command_table();
  const auto it = table.find(name);
  if (it == table.end()) {
    throw InvalidArgument("unknown command '" + script::shown(name) + "'" +
                          script::hint(name, command_names()));
  }
  const script::CommandSpec& s = *it->second;
  std::string text = s.synopsis + "\n  " + s.description;
  if (!s.aliases.empty()) text += "\n  aliases: " + script::join(s.aliases, ", ");
  if (!s.example.empty()) text += "\n  example:\n    " + s.example;
  return text;
}

std::vector<CommandResult> run_script(const std::string& path, const ScriptOptions& options,
                                      Context* ctx) {
  ScriptSession session(options, ctx);
  std::vector<CommandResult> results;
  try {
    results = session.run_file(path);
    session.commit();
  } catch (...) {
    session.discard();
    throw;
  }
  return results;
}

}  // namespace ramiform
