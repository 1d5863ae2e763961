// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "io/ply_format.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "io/text_scan.h"
#include "ramiform/core/errors.h"

namespace ramiform::io_detail {
namespace {

struct TypeName {
  std::string_view name;
  PlyType type;
};

constexpr TypeName kTypeNames[] = {
    {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUInt8},
    {"uint8", PlyType::kUInt8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
    {"ushort", PlyType::kUInt16},  {"uint16", PlyType::kUInt16},   {"int", PlyType::kInt32},
    {"int32", PlyType::kInt32},    {"uint", PlyType::kUInt32},     {"uint32", PlyType::kUInt32},
    {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
    {"float64", PlyType::kFloat64}};

std::optional<PlyType> type_from_name(std::string_view name) {
  for (const auto& t : kTypeNames) {
    if (t.name == name) return t.type;
  }
  return std::nullopt;
}

std::string_view type_name(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
      return "char";
    case PlyType::kUInt8:
      return "uchar";
    case PlyType::kInt16:
      return "short";
    case PlyType::kUInt16:
      return "ushort";
    case PlyType::kInt32:
      return "int";
    case PlyType::kUInt32:
      return "uint";
    case PlyType::kFloat32:
      return "float";
    case PlyType::kFloat64:
      return "double";
  }
  return "double";
}

std::size_t size_of(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 8;
}

bool is_float(PlyType type) { return type == PlyType::kFloat32 || type == PlyType::kFloat64; }

std::int64_t min_of(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
      return INT8_MIN;
    case PlyType::kInt16:
      return INT16_MIN;
    case PlyType::kInt32:
      return INT32_MIN;
    default:
      return 0;
  }
}

std::int64_t max_of(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
      return INT8_MAX;
    case PlyType::kUInt8:
      return UINT8_MAX;
    case PlyType::kInt16:
      return INT16_MAX;
    case PlyType::kUInt16:
      return UINT16_MAX;
    case PlyType::kInt32:
      return INT32_MAX;
    default:
      return UINT32_MAX;
  }
}

template <typename T>
T load(const unsigned char* p, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

double load_double(const unsigned char* p, PlyType type, bool swap) {
  switch (type) {
    case PlyType::kInt8:
      return load<std::int8_t>(p, false);
    case PlyType::kUInt8:
      return load<std::uint8_t>(p, false);
    case PlyType::kInt16:
      return load<std::int16_t>(p, swap);
    case PlyType::kUInt16:
      return load<std::uint16_t>(p, swap);
    case PlyType::kInt32:
      return load<std::int32_t>(p, swap);
    case PlyType::kUInt32:
      return load<std::uint32_t>(p, swap);
    case PlyType::kFloat32:
      return load<float>(p, swap);
    case PlyType::kFloat64:
      return load<double>(p, swap);
  }
  return 0.0;
}

std::int64_t load_int(const unsigned char* p, PlyType type, bool swap) {
  // Every integer type here (32 bits at most) converts to double and back exactly; float list
  // types are rejected before reading.
  return is_float(type) ? 0 : static_cast<std::int64_t>(load_double(p, type, swap));
}

std::string what_of(const PlyElement& e, std::size_t index, const PlyProperty& p) {
  return "'" + e.name + "' " + std::to_string(index) + ", property '" + p.name + "'";
}

// Where each requested scalar goes: column in the output row, or -1 when skipped.
struct Plan {
  std::vector<int> column;        // one per property
  int list = -1;                  // requested list property index
  std::size_t columns = 0;        // number of requested scalars
  PlyElementData* out = nullptr;  // nullptr when the element is skipped entirely
};

void check_list_type(const PlyElement& e, const PlyProperty& p, const std::string& source) {
  if (!p.is_list) {
    throw InputError(source, e.header_line,
                     "property '" + p.name + "' of element '" + e.name + "' must be a list");
  }
  if (is_float(p.type)) {
    throw InputError(source, e.header_line,
                     "list property '" + p.name + "' of element '" + e.name +
                         "' must have an integer item type, not " + std::string(type_name(p.type)));
  }
}

class AsciiBody {
 public:
  AsciiBody(std::string_view data, const PlyHeader& header, const std::string& source)
      : cursor_(data, header.body_offset, header.end_header_line + 1), source_(source) {}

  void read(const PlyElement& e, const Plan& plan) {
    if (e.properties.empty()) return;  // records without properties occupy no text
    for (std::size_t k = 0; k < e.count; ++k) {
      std::string_view line;
      do {
        if (!cursor_.next(line)) {
          throw InputError(source_, e.name, k,
                           "missing: the file ends after " + std::to_string(k) + " of " +
                               std::to_string(e.count) + " '" + e.name + "' elements");
        }
      } while (is_blank(line));
      const std::size_t ln = cursor_.line_number();
      split_fields(line, fields_);
      std::size_t f = 0;
      std::size_t row = 0;
      if (plan.out != nullptr) {
        if (plan.list >= 0) plan.out->list_offsets.push_back(plan.out->list_values.size());
        row = plan.out->scalars.size();
        plan.out->scalars.resize(row + plan.columns);
      }
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (!p.is_list) {
          need(f + 1, e, k, ln);
          if (plan.out != nullptr && plan.column[i] >= 0) {
            plan.out->scalars[row + static_cast<std::size_t>(plan.column[i])] =
                value(fields_[f], p.type, e, k, p, ln);
          }
          ++f;
          continue;
        }
        need(f + 1, e, k, ln);
        const std::int64_t n = integer(fields_[f], p.count_type, e, k, p, ln);
        if (n < 0) {
          throw InputError(source_, ln, what_of(e, k, p) + ": negative list length");
        }
        ++f;
        need(f + static_cast<std::size_t>(n), e, k, ln);
        if (plan.out != nullptr && static_cast<int>(i) == plan.list) {
          for (std::int64_t j = 0; j < n; ++j) {
            plan.out->list_values.push_back(integer(fields_[f + j], p.type, e, k, p, ln));
          }
        }
        f += static_cast<std::size_t>(n);
      }
      if (f != fields_.size()) {
        throw InputError(source_, ln,
                         "'" + e.name + "' " + std::to_string(k) + ": expected " +
                             std::to_string(f) + " fields, got " + std::to_string(fields_.size()));
      }
    }
    if (plan.out != nullptr && plan.list >= 0) {
      plan.out->list_offsets.push_back(plan.out->list_values.size());
    }
  }

  void finish() {
    std::string_view line;
    while (cursor_.next(line)) {
      if (!is_blank(line)) {
        throw InputError(source_, cursor_.line_number(), "extra data after the last element");
      }
    }
  }

 private:
  void need(std::size_t n, const PlyElement& e, std::size_t k, std::size_t ln) const {
    if (fields_.size() < n) {
      throw InputError(source_, ln,
                       "'" + e.name + "' " + std::to_string(k) + ": too few fields (" +
                           std::to_string(fields_.size()) + ")");
    }
  }

  double value(std::string_view token, PlyType type, const PlyElement& e, std::size_t k,
               const PlyProperty& p, std::size_t ln) const {
    if (is_float(type)) return to_double(token, source_, ln, what_of(e, k, p));
    return static_cast<double>(integer(token, type, e, k, p, ln));
  }

  std::int64_t integer(std::string_view token, PlyType type, const PlyElement& e, std::size_t k,
                       const PlyProperty& p, std::size_t ln) const {
    const std::int64_t v = to_int64(token, source_, ln, what_of(e, k, p));
    if (v < min_of(type) || v > max_of(type)) {
      throw InputError(source_, ln,
                       what_of(e, k, p) + ": " + quote(token) + " does not fit type " +
                           std::string(type_name(type)));
    }
    return v;
  }

  LineCursor cursor_;
  const std::string& source_;
  std::vector<std::string_view> fields_;
};

class BinaryBody {
 public:
  BinaryBody(std::string_view data, const PlyHeader& header, const std::string& source)
      : p_(reinterpret_cast<const unsigned char*>(data.data()) + header.body_offset),
        end_(reinterpret_cast<const unsigned char*>(data.data()) + data.size()),
        swap_((header.encoding == PlyEncoding::kBinaryLittleEndian) !=
              (std::endian::native == std::endian::little)),
        source_(source) {}

  void read(const PlyElement& e, const Plan& plan) {
    bool has_list = false;
    std::size_t stride = 0;
    std::vector<std::size_t> offset(e.properties.size());
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      has_list = has_list || e.properties[i].is_list;
      offset[i] = stride;
      stride += size_of(e.properties[i].type);
    }
    if (!has_list) {
      read_fixed(e, plan, stride, offset);
    } else {
      read_variable(e, plan);
    }
  }

 private:
  [[noreturn]] void truncated(const PlyElement& e, std::size_t k) const {
    throw InputError(source_, e.name, k,
                     "the binary body ends inside this element (" + std::to_string(e.count) +
                         " declared; file truncated?)");
  }

  [[nodiscard]] std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }

  void read_fixed(const PlyElement& e, const Plan& plan, std::size_t stride,
                  const std::vector<std::size_t>& offset) {
    if (stride == 0) return;
    if (e.count > left() / stride) truncated(e, left() / stride);
    if (plan.out != nullptr) {
      std::vector<std::size_t> props;  // requested properties in column order
      for (std::size_t i = 0; i < plan.column.size(); ++i) {
        if (plan.column[i] >= 0) {
          if (props.size() <= static_cast<std::size_t>(plan.column[i])) {
            props.resize(static_cast<std::size_t>(plan.column[i]) + 1);
          }
          props[static_cast<std::size_t>(plan.column[i])] = i;
        }
      }
      const std::size_t cols = props.size();
      std::vector<double>& out = plan.out->scalars;
      out.resize(e.count * cols);
      for (std::size_t k = 0; k < e.count; ++k) {
        const unsigned char* rec = p_ + k * stride;
        for (std::size_t c = 0; c < cols; ++c) {
          const PlyProperty& prop = e.properties[props[c]];
          const double v = load_double(rec + offset[props[c]], prop.type, swap_);
          if (!std::isfinite(v)) {
            throw InputError(source_, e.name, k,
                             "property '" + prop.name + "' is not a finite number");
          }
          out[k * cols + c] = v;
        }
      }
    }
    p_ += e.count * stride;
  }

  void read_variable(const PlyElement& e, const Plan& plan) {
    PlyElementData* out = plan.out;
    for (std::size_t k = 0; k < e.count; ++k) {
      std::size_t row = 0;
      if (out != nullptr) {
        if (plan.list >= 0) out->list_offsets.push_back(out->list_values.size());
        row = out->scalars.size();
        out->scalars.resize(row + plan.columns);
      }
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& prop = e.properties[i];
        if (!prop.is_list) {
          const std::size_t size = size_of(prop.type);
          if (left() < size) truncated(e, k);
          if (out != nullptr && plan.column[i] >= 0) {
            const double v = load_double(p_, prop.type, swap_);
            if (!std::isfinite(v)) {
              throw InputError(source_, e.name, k,
                               "property '" + prop.name + "' is not a finite number");
            }
            out->scalars[row + static_cast<std::size_t>(plan.column[i])] = v;
          }
          p_ += size;
          continue;
        }
        const std::size_t count_size = size_of(prop.count_type);
        if (left() < count_size) truncated(e, k);
        const std::int64_t n = load_int(p_, prop.count_type, swap_);
        p_ += count_size;
        if (n < 0) {
          throw InputError(source_, e.name, k,
                           "list '" + prop.name + "' has negative length " + std::to_string(n));
        }
        const std::size_t item = size_of(prop.type);
        if (static_cast<std::size_t>(n) > left() / item) truncated(e, k);
        if (out != nullptr && static_cast<int>(i) == plan.list) {
          for (std::int64_t j = 0; j < n; ++j) {
            out->list_values.push_back(
                load_int(p_ + static_cast<std::size_t>(j) * item, prop.type, swap_));
          }
        }
        p_ += static_cast<std::size_t>(n) * item;
      }
    }
    if (out != nullptr && plan.list >= 0) out->list_offsets.push_back(out->list_values.size());
  }

  const unsigned char* p_;
  const unsigned char* end_;
  bool swap_;
  const std::string& source_;
};

}  // namespace

std::optional<std::size_t> PlyElement::find(std::string_view property) const {
  for (std::size_t i = 0; i < properties.size(); ++i) {
    if (properties[i].name == property) return i;
  }
  return std::nullopt;
}

std::optional<std::size_t> PlyHeader::find(std::string_view element) const {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].name == element) return i;
  }
  return std::nullopt;
}

PlyHeader parse_ply_header(std::string_view data, const std::string& source) {
  if (data.empty()) throw InputError(source, 0, "file is empty");
  LineCursor cursor(data);
  std::string_view line;
  cursor.next(line);
  {
    std::vector<std::string_view> magic;
    split_fields(line, magic);
    if (magic.size() != 1 || magic[0] != "ply") {
      throw InputError(source, 1, "not a PLY file: the first line must be 'ply'");
    }
  }
  PlyHeader header;
  std::size_t format_line = 0;  // line of the 'format' line, 0 before it
  std::vector<std::string_view> f;
  while (cursor.next(line)) {
    const std::size_t ln = cursor.line_number();
    split_fields(line, f);
    if (f.empty()) continue;
    const std::string_view key = f[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      if (f.size() != 1) throw InputError(source, ln, "unexpected text after 'end_header'");
      if (format_line == 0) throw InputError(source, ln, "the header has no 'format' line");
      header.body_offset = cursor.offset();
      header.end_header_line = ln;
      return header;
    }
    if (key == "format") {
      // A second format line would silently decide the encoding of the whole body.
      if (format_line != 0) {
        throw InputError(
            source, ln,
            "duplicate 'format' line (first on line " + std::to_string(format_line) + ")");
      }
      if (f.size() != 3) {
        throw InputError(source, ln,
                         "expected 'format <ascii|binary_little_endian|"
                         "binary_big_endian> 1.0'");
      }
      if (f[1] == "ascii") {
        header.encoding = PlyEncoding::kAscii;
      } else if (f[1] == "binary_little_endian") {
        header.encoding = PlyEncoding::kBinaryLittleEndian;
      } else if (f[1] == "binary_big_endian") {
        header.encoding = PlyEncoding::kBinaryBigEndian;
      } else {
        throw InputError(source, ln,
                         "unknown PLY format " + quote(f[1]) +
                             " (expected ascii, binary_little_endian or "
                             "binary_big_endian)");
      }
      if (f[2] != "1.0") {
        throw InputError(source, ln, "unsupported PLY version " + quote(f[2]) + " (expected 1.0)");
      }
      format_line = ln;
      continue;
    }
    if (key == "element") {
      if (f.size() != 3) throw InputError(source, ln, "expected 'element <name> <count>'");
      const std::int64_t count = to_int64(f[2], source, ln, "element count");
      if (count < 0) throw InputError(source, ln, "negative element count");
      // Readers use the first element of a name; a second one would be skipped unread.
      const std::string name = printable(f[1]);
      if (const auto first = header.find(name)) {
        throw InputError(source, ln,
                         "duplicate element '" + name + "' (first on line " +
                             std::to_string(header.elements[*first].header_line) + ")");
      }
      PlyElement e;
      // Names are kept as printable() text: they appear in messages, and the names readers
      // look for ("vertex", "x") are printable already.
      e.name = name;
      e.count = static_cast<std::size_t>(count);
      e.header_line = ln;
      header.elements.push_back(std::move(e));
      continue;
    }
    if (key == "property") {
      if (header.elements.empty()) {
        throw InputError(source, ln, "'property' before any 'element'");
      }
      PlyProperty p;
      if (f.size() >= 2 && f[1] == "list") {
        if (f.size() != 5) {
          throw InputError(source, ln, "expected 'property list <count type> <item type> <name>'");
        }
        const auto count_type = type_from_name(f[2]);
        const auto item_type = type_from_name(f[3]);
        if (!count_type) throw InputError(source, ln, "unknown PLY type " + quote(f[2]));
        if (!item_type) throw InputError(source, ln, "unknown PLY type " + quote(f[3]));
        if (is_float(*count_type)) {
          throw InputError(source, ln, "a list count must have an integer type");
        }
        p.is_list = true;
        p.count_type = *count_type;
        p.type = *item_type;
        p.name = printable(f[4]);
      } else {
        if (f.size() != 3) throw InputError(source, ln, "expected 'property <type> <name>'");
        const auto type = type_from_name(f[1]);
        if (!type) throw InputError(source, ln, "unknown PLY type " + quote(f[1]));
        p.type = *type;
        p.name = printable(f[2]);
      }
      PlyElement& e = header.elements.back();
      if (e.find(p.name)) {
        throw InputError(source, ln,
                         "duplicate property '" + p.name + "' in element '" + e.name + "'");
      }
      e.properties.push_back(std::move(p));
      continue;
    }
    throw InputError(source, ln, "unknown PLY header keyword " + quote(key));
  }
  throw InputError(source, cursor.line_number(), "the PLY header has no 'end_header' line");
}

std::optional<std::size_t> optional_scalar(const PlyElement& element, std::string_view name,
                                           const std::string& source) {
  const auto index = element.find(name);
  if (index && element.properties[*index].is_list) {
    throw InputError(source, element.header_line,
                     "property '" + std::string(name) + "' of element '" + element.name +
                         "' must not be a list");
  }
  return index;
}

std::size_t require_scalar(const PlyElement& element, std::string_view name,
                           const std::string& source) {
  const auto index = optional_scalar(element, name, source);
  if (!index) {
    throw InputError(source, element.header_line,
                     "element '" + element.name + "' has no property '" + std::string(name) + "'");
  }
  return *index;
}

PlyRequest vertex_request(const PlyHeader& header, std::initializer_list<std::string_view> names,
                          const std::string& source) {
  const auto vertex = header.find("vertex");
  if (!vertex) throw InputError(source, header.end_header_line, "no 'vertex' element");
  PlyRequest request;
  request.element = *vertex;
  for (const std::string_view name : names) {
    request.scalars.push_back(require_scalar(header.elements[*vertex], name, source));
  }
  return request;
}

bool add_vertex_normals(const PlyHeader& header, PlyRequest& request, const std::string& source) {
  const PlyElement& v = header.elements[request.element];
  const auto nx = optional_scalar(v, "nx", source);
  const auto ny = optional_scalar(v, "ny", source);
  const auto nz = optional_scalar(v, "nz", source);
  if (!nx && !ny && !nz) return false;
  if (!(nx && ny && nz)) {
    throw InputError(source, v.header_line,
                     "element 'vertex' has only some of the normal properties nx, ny, nz");
  }
  request.scalars.insert(request.scalars.end(), {*nx, *ny, *nz});
  return true;
}

bool add_vertex_uvs(const PlyHeader& header, PlyRequest& request, const std::string& source) {
  const PlyElement& v = header.elements[request.element];
  static constexpr std::string_view kPairs[][2] = {
      {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
  for (const auto& pair : kPairs) {
    const auto u = optional_scalar(v, pair[0], source);
    const auto w = optional_scalar(v, pair[1], source);
    if (!u && !w) continue;
    if (!(u && w)) {
      throw InputError(source, v.header_line,
                       "element 'vertex' has '" + std::string(u ? pair[0] : pair[1]) +
                           "' without '" + std::string(u ? pair[1] : pair[0]) + "'");
    }
    request.scalars.insert(request.scalars.end(), {*u, *w});
    return true;
  }
  return false;
}

std::vector<PlyElementData> read_ply_body(std::string_view data, const PlyHeader& header,
                                          const std::vector<PlyRequest>& requests,
                                          const std::string& source) {
  std::vector<PlyElementData> results(requests.size());
  std::vector<Plan> plans(header.elements.size());
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    plans[e].column.assign(header.elements[e].properties.size(), -1);
  }
  for (std::size_t r = 0; r < requests.size(); ++r) {
    const PlyRequest& req = requests[r];
    const PlyElement& e = header.elements.at(req.element);
    Plan& plan = plans[req.element];
    plan.out = &results[r];
    results[r].count = e.count;
    plan.columns = req.scalars.size();
    for (std::size_t c = 0; c < req.scalars.size(); ++c) {
      plan.column.at(req.scalars[c]) = static_cast<int>(c);
    }
    if (req.list) {
      check_list_type(e, e.properties.at(*req.list), source);
      plan.list = static_cast<int>(*req.list);
    }
  }
  if (header.encoding == PlyEncoding::kAscii) {
    AsciiBody body(data, header, source);
    for (std::size_t e = 0; e < header.elements.size(); ++e)
      body.read(header.elements[e], plans[e]);
    body.finish();
  } else {
    // Trailing bytes after the last element (often a newline) are ignored.
    BinaryBody body(data, header, source);
    for (std::size_t e = 0; e < header.elements.size(); ++e)
      body.read(header.elements[e], plans[e]);
  }
  return results;
}

void PlyWriter::begin(std::string_view comment) {
  header_ = "ply\nformat binary_little_endian 1.0\n";
  if (!comment.empty()) header_ += "comment " + std::string(comment) + "\n";
}

void PlyWriter::element(std::string_view name, std::size_t count,
                        const std::vector<PlyColumn>& columns) {
  header_ += "element " + std::string(name) + " " + std::to_string(count) + "\n";
  for (const auto& c : columns) {
    header_ += "property " + std::string(type_name(c.type)) + " " + c.name + "\n";
  }
}

void PlyWriter::list_element(std::string_view name, std::size_t count, PlyType count_type,
                             PlyType item_type, std::string_view property) {
  header_ += "element " + std::string(name) + " " + std::to_string(count) + "\n";
  header_ += "property list " + std::string(type_name(count_type)) + " " +
             std::string(type_name(item_type)) + " " + std::string(property) + "\n";
}

void PlyWriter::end_header() {
  header_ += "end_header\n";
  out_.write(header_.data(), static_cast<std::streamsize>(header_.size()));
  buffer_.reserve(1 << 20);
}

namespace {

template <typename T>
void store(std::string& buffer, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  buffer.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

}  // namespace

void PlyWriter::put(PlyType type, double value) {
  switch (type) {
    case PlyType::kFloat32:
      store(buffer_, static_cast<float>(value));
      break;
    case PlyType::kFloat64:
      store(buffer_, value);
      break;
    default:
      put_index(type, static_cast<std::uint64_t>(value));
      return;
  }
  if (buffer_.size() >= (1U << 20)) flush();
}

void PlyWriter::put_index(PlyType type, std::uint64_t value) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      store(buffer_, static_cast<std::uint8_t>(value));
      break;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      store(buffer_, static_cast<std::uint16_t>(value));
      break;
    case PlyType::kInt32:
    case PlyType::kUInt32:
      store(buffer_, static_cast<std::uint32_t>(value));
      break;
    case PlyType::kFloat32:
      store(buffer_, static_cast<float>(value));
      break;
    case PlyType::kFloat64:
      store(buffer_, static_cast<double>(value));
      break;
  }
  if (buffer_.size() >= (1U << 20)) flush();
}

void PlyWriter::flush(bool force) {
  if (buffer_.empty() || (!force && buffer_.size() < (1U << 20))) return;
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
}

}  // namespace ramiform::io_detail
