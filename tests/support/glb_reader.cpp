// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "support/glb_reader.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

namespace ramiform::test {
namespace {

std::uint32_t u32_at(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) {
    v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
  }
  return v;
}

int components(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  ADD_FAILURE() << "unexpected accessor type " << type;
  return 0;
}

// The bytes of accessor `index` (tightly packed 4-byte components), checked against its view.
std::string accessor_bytes(const Glb& g, int index, int component_type) {
  const auto& a = g.json.at("accessors").at(static_cast<std::size_t>(index));
  EXPECT_EQ(a.at("componentType").get<int>(), component_type);
  const auto& v = g.json.at("bufferViews").at(a.at("bufferView").get<std::size_t>());
  const std::size_t n = a.at("count").get<std::size_t>() *
                        static_cast<std::size_t>(components(a.at("type").get<std::string>()));
  const std::size_t offset = v.at("byteOffset").get<std::size_t>();
  EXPECT_EQ(offset % 4, 0u);
  EXPECT_EQ(v.at("byteLength").get<std::size_t>(), n * 4);
  EXPECT_LE(offset + n * 4, g.bin.size());
  if (offset + n * 4 > g.bin.size()) return {};
  return g.bin.substr(offset, n * 4);
}

}  // namespace

std::vector<float> Glb::floats(int index) const {
  const std::string b = accessor_bytes(*this, index, 5126);
  std::vector<float> out(b.size() / 4);
  if (!out.empty()) std::memcpy(out.data(), b.data(), b.size());
  return out;
}

std::vector<std::uint32_t> Glb::uints(int index) const {
  const std::string b = accessor_bytes(*this, index, 5125);
  std::vector<std::uint32_t> out(b.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = u32_at(b, 4 * i);
  return out;
}

int Glb::attribute(int mesh, const std::string& name) const {
  const auto& attrs =
      json.at("meshes").at(static_cast<std::size_t>(mesh)).at("primitives").at(0).at("attributes");
  return attrs.contains(name) ? attrs.at(name).get<int>() : -1;
}

Glb read_glb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Glb g;
  if (s.size() < 20 || s.substr(0, 4) != "glTF") {
    ADD_FAILURE() << path << " is not a GLB file";
    return g;
  }
  EXPECT_EQ(u32_at(s, 4), 2u);
  EXPECT_EQ(u32_at(s, 8), s.size());
  const std::uint32_t json_len = u32_at(s, 12);
  EXPECT_EQ(s.substr(16, 4), "JSON");
  EXPECT_EQ(json_len % 4, 0u);
  g.json = nlohmann::json::parse(s.substr(20, json_len));
  const std::size_t bin_at = 20 + std::size_t{json_len};
  if (bin_at < s.size()) {
    EXPECT_EQ(s.substr(bin_at + 4, 4), std::string("BIN\0", 4));
    g.bin = s.substr(bin_at + 8, u32_at(s, bin_at));
    EXPECT_EQ(g.bin.size() % 4, 0u);
    EXPECT_EQ(g.json.at("buffers").at(0).at("byteLength").get<std::size_t>(), g.bin.size());
  }
  return g;
}

}  // namespace ramiform::test
