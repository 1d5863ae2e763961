// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/curve_io.h"

#include <string_view>

#include "io/text_scan.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using namespace io_detail;

template <class V>
std::vector<V> parse_points(const std::string& path, int dim) {
  const std::string data = read_whole_file(path);
  // A UTF-8 byte order mark is not part of the first line (it would hide its first field).
  const std::string_view text = skip_bom(data);
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> f;
  std::vector<V> out;
  static constexpr const char* kNames[] = {"x", "y", "z"};
  while (cursor.next(line)) {
    const std::size_t ln = cursor.line_number();
    if (!split_fields(strip_comment(line), f, true)) {
      throw InputError(path, ln, "empty field between commas");
    }
    if (f.empty()) continue;
    if (static_cast<int>(f.size()) != dim) {
      throw InputError(path, ln,
                       "expected " + std::to_string(dim) + " numbers (" +
                           (dim == 2 ? std::string("x y") : std::string("x y z")) + "), got " +
                           std::to_string(f.size()) + " fields");
    }
    V v;
    for (int c = 0; c < dim; ++c)
      v[c] = to_double(f[static_cast<std::size_t>(c)], path, ln, kNames[c]);
    out.push_back(v);
  }
  if (out.empty()) throw InputError(path, 0, "no points");
  return out;
}

}  // namespace

std::vector<Vec2> read_points2(const std::string& path) { return parse_points<Vec2>(path, 2); }
std::vector<Vec3> read_points3(const std::string& path) { return parse_points<Vec3>(path, 3); }

}  // namespace ramiform
