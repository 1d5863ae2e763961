// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "gltf_format.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform::io {
namespace {

using nlohmann::ordered_json;

// glTF numeric constants (specification §5.1.3 accessor.componentType, §5.11 bufferView.target).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;

void append_u32(std::string& s, std::uint32_t v) {
  // Little-endian whatever the host's order, appended as one block (a glb of a million
  // triangles is some 20 million bytes).
  const char bytes[4] = {static_cast<char>(v & 0xffu), static_cast<char>((v >> 8) & 0xffu),
                         static_cast<char>((v >> 16) & 0xffu),
                         static_cast<char>((v >> 24) & 0xffu)};
  s.append(bytes, 4);
}

void append_f32(std::string& s, float f) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof bits);
  append_u32(s, bits);
}

// +Z up (the library) to +Y up (glTF): a rotation by -90 degrees about X.
Vec3 to_y_up(const Vec3& v) { return {v.x(), v.z(), -v.y()}; }

// The BIN chunk and the JSON arrays that describe it, filled one level at a time.
class GlbBuilder {
 public:
  // Appends a tightly packed view of `count` elements of `components` float32 or uint32
  // values each, made by `put(i, bin)`, and its accessor; returns the accessor's index.
  template <class Put>
  std::size_t add(std::size_t count, int components, int component_type, int target,
                  const char* type, Put&& put, bool min_max = false) {
    const std::size_t offset = bin_.size();
    bin_.reserve(offset + 4 * count * static_cast<std::size_t>(components));
    for (std::size_t i = 0; i < count; ++i) put(i, bin_);
    const std::size_t length = bin_.size() - offset;
    views_.push_back({{"buffer", 0},
                      {"byteOffset", offset},
                      {"byteLength", length},
                      {"target", target}});
    ordered_json a = {{"bufferView", views_.size() - 1},
                      {"componentType", component_type},
                      {"count", count},
                      {"type", type}};
    if (min_max) {
      // The accessor's bounds, from the float32 values just written (the validator compares).
      std::vector<float> lo(static_cast<std::size_t>(components),
                            std::numeric_limits<float>::max());
      std::vector<float> hi(static_cast<std::size_t>(components),
                            std::numeric_limits<float>::lowest());
      for (std::size_t i = 0; i < count * static_cast<std::size_t>(components); ++i) {
        float f = 0;
        std::memcpy(&f, bin_.data() + offset + 4 * i, sizeof f);
        const std::size_t k = i % static_cast<std::size_t>(components);
        lo[k] = std::min(lo[k], f);
        hi[k] = std::max(hi[k], f);
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    accessors_.push_back(std::move(a));
    return accessors_.size() - 1;
  }

  // Adds one mesh for `mesh`; returns its index, or -1 for a mesh without vertices (accessors
  // or triangles (accessors of count 0 are invalid).
  long long add_mesh(const TriMesh& mesh, bool normals, bool uvs) {
    const std::size_t nv = mesh.positions.size();
    const std::size_t nt = mesh.triangles.size();
    if (nv == 0 || nt == 0) return -1;
    if (nv > std::numeric_limits<std::uint32_t>::max() / 16 ||
        nt > std::numeric_limits<std::uint32_t>::max() / 12 ||
        bin_.size() > std::numeric_limits<std::uint32_t>::max() / 2) {
      throw InvalidArgument("write_glb: mesh too large for one glTF buffer");
    }
    for (std::size_t i = 0; i < nv; ++i) {
      if ((mesh.positions[i].cwiseAbs().array() >
           static_cast<double>(std::numeric_limits<float>::max()))
              .any()) {
        throw InvalidArgument("write_glb: vertex " + std::to_string(i) +
                              " lies outside the float range that glTF stores");
      }
    }
    const auto put3 = [](std::string& bin, const Vec3& v) {
      const Vec3 y = to_y_up(v);
      for (int k = 0; k < 3; ++k) append_f32(bin, static_cast<float>(y[k]));
    };
    ordered_json attributes;
    attributes["POSITION"] = add(
        nv, 3, kFloat, kArrayBuffer, "VEC3",
        [&](std::size_t i, std::string& bin) { put3(bin, mesh.positions[i]); }, true);
    if (normals && !mesh.normals.empty()) {
      attributes["NORMAL"] =
          add(nv, 3, kFloat, kArrayBuffer, "VEC3", [&](std::size_t i, std::string& bin) {
            put3(bin, mesh.normals[i].normalized());
          });
    }
    if (uvs && !mesh.uvs.empty()) {
      attributes["TEXCOORD_0"] =
          add(nv, 2, kFloat, kArrayBuffer, "VEC2", [&](std::size_t i, std::string& bin) {
            append_f32(bin, static_cast<float>(mesh.uvs[i].x()));
            append_f32(bin, static_cast<float>(1.0 - mesh.uvs[i].y()));
          });
      // TANGENT needs NORMAL (specification §3.7.2.1).
      if (normals && !mesh.normals.empty() && !mesh.tangents.empty()) {
        attributes["TANGENT"] =
            add(nv, 4, kFloat, kArrayBuffer, "VEC4", [&](std::size_t i, std::string& bin) {
              const Vec4& t = mesh.tangents[i];
              put3(bin, Vec3(t.x(), t.y(), t.z()).normalized());
              append_f32(bin, t.w() < 0 ? -1.0f : 1.0f);
            });
      }
    }
    const std::size_t indices = add(
        nt, 3, kUnsignedInt, kElementArrayBuffer, "SCALAR", [&](std::size_t i, std::string& bin) {
          for (const std::uint32_t v : mesh.triangles[i]) append_u32(bin, v);
        });
    accessors_[indices]["count"] = nt * 3;
    meshes_.push_back(
        {{"primitives", ordered_json::array({{{"attributes", attributes},
                                               {"indices", indices},
                                               {"material", 0},
                                               {"mode", kTriangles}}})}});
    return static_cast<long long>(meshes_.size() - 1);
  }

  ordered_json accessors_ = ordered_json::array();
  ordered_json views_ = ordered_json::array();
  ordered_json meshes_ = ordered_json::array();
  std::string bin_;
};

}  // namespace

void write_glb(std::span<const TriMesh> levels, bool normals, bool uvs, std::ostream& out) {
  if (levels.empty()) throw InvalidArgument("write_glb: no mesh to write");
  GlbBuilder b;
  ordered_json nodes = ordered_json::array();
  for (std::size_t k = 0; k < levels.size(); ++k) {
    ordered_json node;
    if (levels.size() > 1) node["name"] = "LOD" + std::to_string(k);
    const long long m = b.add_mesh(levels[k], normals, uvs);
    if (m >= 0) node["mesh"] = m;
    nodes.push_back(node.is_null() ? ordered_json::object() : node);
  }
  if (levels.size() > 1) {
    // MSFT_lod: the finest node lists the coarser ones, finest to coarsest; the screen coverage
    // below which each level gives way to the next halves from one level to the next.
    ordered_json ids = ordered_json::array();
    ordered_json coverage = ordered_json::array();
    double c = 0.5;
    for (std::size_t k = 1; k < levels.size(); ++k) ids.push_back(k);
    for (std::size_t k = 0; k < levels.size(); ++k, c *= 0.5) coverage.push_back(c);
    nodes[0]["extensions"] = {{"MSFT_lod", {{"ids", ids}}}};
    nodes[0]["extras"] = {{"MSFT_screencoverage", coverage}};
  }
  while (b.bin_.size() % 4 != 0) b.bin_.push_back('\0');

  ordered_json j;
  j["asset"] = {{"version", "2.0"}, {"generator", "ramiform"}};
  if (levels.size() > 1) {
    j["extensionsUsed"] = {"MSFT_lod"};
  }
  j["scene"] = 0;
  j["scenes"] = ordered_json::array({{{"nodes", {0}}}});
  j["nodes"] = nodes;
  const bool has_bin = !b.bin_.empty();
  if (!b.meshes_.empty()) {
    // One plain bark material (glTF's default would be white): brown, rough, not metallic.
    j["materials"] = ordered_json::array(
        {{{"name", "bark"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.36, 0.27, 0.19, 1.0}},
            {"metallicFactor", 0.0},
            {"roughnessFactor", 0.9}}}}});
    j["meshes"] = b.meshes_;
    j["accessors"] = b.accessors_;
    j["bufferViews"] = b.views_;
    j["buffers"] = ordered_json::array({{{"byteLength", b.bin_.size()}}});
  }
  std::string json = j.dump();
  while (json.size() % 4 != 0) json.push_back(' ');

  std::string glb;
  const std::size_t total = 12 + 8 + json.size() + (has_bin ? 8 + b.bin_.size() : 0);
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw InvalidArgument("write_glb: meshes too large for one .glb file (4 GiB)");
  }
  append_u32(glb, 0x46546C67u);  // "glTF"
  append_u32(glb, 2);
  append_u32(glb, static_cast<std::uint32_t>(total));
  append_u32(glb, static_cast<std::uint32_t>(json.size()));
  append_u32(glb, 0x4E4F534Au);  // "JSON"
  glb += json;
  out.write(glb.data(), static_cast<std::streamsize>(glb.size()));
  if (has_bin) {
    std::string head;
    append_u32(head, static_cast<std::uint32_t>(b.bin_.size()));
    append_u32(head, 0x004E4942u);  // "BIN\0"
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    out.write(b.bin_.data(), static_cast<std::streamsize>(b.bin_.size()));
  }
}

}  // namespace ramiform::io
