// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "gltf_format.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform::io {
namespace {

// glTF numeric constants (specification §5.1.3 accessor.componentType, §5.11 bufferView.target).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;

void append_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void append_f32(std::string& s, float f) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof bits);
  append_u32(s, bits);
}

}  // namespace

void write_glb(const TriMesh& mesh, std::ostream& out) {
  const std::size_t nv = mesh.positions.size();
  const std::size_t nt = mesh.triangles.size();
  if (nv > std::numeric_limits<std::uint32_t>::max() / 12 ||
      nt > std::numeric_limits<std::uint32_t>::max() / 12) {
    throw InvalidArgument("write_glb: mesh too large for one glTF buffer");
  }
  const bool normals = !mesh.normals.empty();
  std::string bin;
  bin.reserve(nv * (normals ? 24 : 12) + nt * 12);
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                 std::numeric_limits<float>::max()};
  float hi[3] = {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(),
                 std::numeric_limits<float>::lowest()};
  for (std::size_t i = 0; i < nv; ++i) {
    const Vec3& p = mesh.positions[i];
    if ((p.cwiseAbs().array() > static_cast<double>(std::numeric_limits<float>::max())).any()) {
      throw InvalidArgument("write_glb: vertex " + std::to_string(i) +
                            " lies outside the float range that glTF stores");
    }
    for (int k = 0; k < 3; ++k) {
      const auto f = static_cast<float>(p[k]);
      lo[k] = std::min(lo[k], f);
      hi[k] = std::max(hi[k], f);
      append_f32(bin, f);
    }
  }
  const std::size_t normal_offset = bin.size();
  if (normals) {
    for (const Vec3& n : mesh.normals) {
      for (int k = 0; k < 3; ++k) append_f32(bin, static_cast<float>(n[k]));
    }
  }
  const std::size_t index_offset = bin.size();
  for (const auto& t : mesh.triangles) {
    for (std::uint32_t i : t) append_u32(bin, i);
  }
  while (bin.size() % 4 != 0) bin.push_back('\0');

  using nlohmann::ordered_json;
  ordered_json j;
  j["asset"] = {{"version", "2.0"}, {"generator", "ramiform"}};
  j["scene"] = 0;
  j["scenes"] = ordered_json::array({{{"nodes", {0}}}});
  j["nodes"] = ordered_json::array({{{"mesh", 0}}});
  ordered_json attributes = {{"POSITION", 0}};
  if (normals) attributes["NORMAL"] = 2;
  j["meshes"] = ordered_json::array(
      {{{"primitives",
         ordered_json::array(
             {{{"attributes", attributes}, {"indices", 1}, {"mode", kTriangles}}})}}});
  ordered_json accessors = ordered_json::array();
  accessors.push_back({{"bufferView", 0},
                       {"componentType", kFloat},
                       {"count", nv},
                       {"type", "VEC3"},
                       {"min", {lo[0], lo[1], lo[2]}},
                       {"max", {hi[0], hi[1], hi[2]}}});
  accessors.push_back(
      {{"bufferView", 1}, {"componentType", kUnsignedInt}, {"count", nt * 3}, {"type", "SCALAR"}});
  ordered_json views = ordered_json::array();
  views.push_back(
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", nv * 12}, {"target", kArrayBuffer}});
  views.push_back({{"buffer", 0},
                   {"byteOffset", index_offset},
                   {"byteLength", nt * 12},
                   {"target", kElementArrayBuffer}});
  if (normals) {
    accessors.push_back(
        {{"bufferView", 2}, {"componentType", kFloat}, {"count", nv}, {"type", "VEC3"}});
    views.push_back({{"buffer", 0},
                     {"byteOffset", normal_offset},
                     {"byteLength", nv * 12},
                     {"target", kArrayBuffer}});
  }
  if (nv == 0) {
    // An empty mesh: accessors of count 0 are invalid, so write a scene without a mesh.
    j.erase("meshes");
    j["nodes"] = ordered_json::array({ordered_json::object()});
  } else {
    j["accessors"] = accessors;
    j["bufferViews"] = views;
    j["buffers"] = ordered_json::array({{{"byteLength", bin.size()}}});
  }
  std::string json = j.dump();
  while (json.size() % 4 != 0) json.push_back(' ');

  std::string glb;
  const bool has_bin = nv > 0;
  const std::size_t total = 12 + 8 + json.size() + (has_bin ? 8 + bin.size() : 0);
  append_u32(glb, 0x46546C67u);  // "glTF"
  append_u32(glb, 2);
  append_u32(glb, static_cast<std::uint32_t>(total));
  append_u32(glb, static_cast<std::uint32_t>(json.size()));
  append_u32(glb, 0x4E4F534Au);  // "JSON"
  glb += json;
  if (has_bin) {
    append_u32(glb, static_cast<std::uint32_t>(bin.size()));
    append_u32(glb, 0x004E4942u);  // "BIN\0"
    glb += bin;
  }
  out.write(glb.data(), static_cast<std::streamsize>(glb.size()));
}

}  // namespace ramiform::io
