// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "io/obj_format.h"

#include "io/text_scan.h"
#include "ramiform/core/errors.h"

namespace ramiform::io_detail {

Vec3 parse_obj_vertex(const std::vector<std::string_view>& fields, const std::string& source,
                      std::size_t line) {
  if (fields.size() < 4 || fields.size() > 8) {
    throw InputError(source, line,
                     "'v' needs 3 coordinates (optionally w and a colour), got " +
                         std::to_string(fields.size() - 1) + " values");
  }
  static constexpr std::string_view kNames[] = {"x", "y", "z", "w", "value", "value", "value"};
  Vec3 p;
  for (std::size_t i = 1; i < fields.size(); ++i) {
    const double v = to_double(fields[i], source, line, kNames[i - 1]);
    if (i <= 3) p[static_cast<Eigen::Index>(i - 1)] = v;
  }
  return p;
}

std::uint32_t resolve_obj_index(std::string_view token, std::size_t count,
                                const std::string& source, std::size_t line,
                                std::string_view what) {
  const std::int64_t i = to_int64(token, source, line, std::string(what) + " index");
  const auto n = static_cast<std::int64_t>(count);
  if (i == 0) {
    throw InputError(source, line,
                     std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
  }
  const std::int64_t resolved = i > 0 ? i - 1 : n + i;
  if (resolved < 0 || resolved >= n) {
    throw InputError(source, line,
                     std::string(what) + " index " + std::to_string(i) + " out of range (" +
                         std::to_string(count) + " defined so far)");
  }
  return static_cast<std::uint32_t>(resolved);
}

void split_obj_corner(std::string_view corner, std::string_view& v, std::string_view& vt,
                      std::string_view& vn, const std::string& source, std::size_t line) {
  vt = {};
  vn = {};
  const std::size_t a = corner.find('/');
  v = corner.substr(0, a);
  if (a != std::string_view::npos) {
    const std::string_view rest = corner.substr(a + 1);
    const std::size_t b = rest.find('/');
    vt = rest.substr(0, b);
    if (b != std::string_view::npos) {
      vn = rest.substr(b + 1);
      if (vn.find('/') != std::string_view::npos) {
        throw InputError(source, line, "malformed OBJ corner " + quote(corner));
      }
    }
  }
  if (v.empty()) throw InputError(source, line, "malformed OBJ corner " + quote(corner));
}

}  // namespace ramiform::io_detail
