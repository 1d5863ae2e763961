// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal OBJ helpers shared by the skeleton and mesh readers.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform::io_detail {

/// The position of a `v` line: fields[0] is "v", then 3 to 7 numbers (x y z, optionally w and/or
/// a vertex colour, which are ignored). Throws InputError(source, line).
Vec3 parse_obj_vertex(const std::vector<std::string_view>& fields, const std::string& source,
                      std::size_t line);

/// Resolves one OBJ index (1-based, or negative: -1 is the last one defined) against the `count`
/// items defined so far to a 0-based index. `what` names the kind ("vertex", "normal").
/// Throws InputError(source, line) for 0, malformed or out-of-range indices.
std::uint32_t resolve_obj_index(std::string_view token, std::size_t count,
                                const std::string& source, std::size_t line, std::string_view what);

/// Splits an OBJ corner "v", "v/vt", "v//vn" or "v/vt/vn" into its parts (empty when absent).
/// Throws InputError(source, line) for more than three parts or an empty vertex part.
void split_obj_corner(std::string_view corner, std::string_view& v, std::string_view& vt,
                      std::string_view& vn, const std::string& source, std::size_t line);

}  // namespace ramiform::io_detail
