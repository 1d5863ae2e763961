// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// An independent decoder of the .glb files ramiform writes, for tests: the GLB header and
// chunks (glTF 2.0, "GLB File Format Specification"), the JSON, and accessors read through their
// buffer views. It checks the container's framing as it goes (gtest failures).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ramiform::test {

struct Glb {
  nlohmann::json json;
  std::string bin;  ///< the BIN chunk's bytes (empty without one)

  /// Accessor `index` as floats (componentType 5126), `count * components` values.
  [[nodiscard]] std::vector<float> floats(int index) const;
  /// Accessor `index` as uint32 (componentType 5125).
  [[nodiscard]] std::vector<std::uint32_t> uints(int index) const;
  /// The accessor of attribute `name` of mesh `mesh`'s first primitive, or -1.
  [[nodiscard]] int attribute(int mesh, const std::string& name) const;
};

/// Reads and decodes `path`; fails the test (and returns an empty Glb) when it is not a GLB.
[[nodiscard]] Glb read_glb(const std::string& path);

}  // namespace ramiform::test
