// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Malformed files for every reader the command line has (issue 15): each run exits with code 2,
// prints one error line naming the file and the line or element, and leaves nothing behind (no
// output, no stats file, no staged or temporary file). The cases and ramiform's messages form
// the table of docs/reliability.md; the test writes the table to the build directory and fails
// when the documented one differs (RAMIFORM_UPDATE_DOCS=1 rewrites it in the source tree).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli/cli_run.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

// One malformed input and the command that reads it. In `command`, '@' stands for the case's
// directory followed by '/'.
struct Case {
  std::string reader;  // the format and reader, e.g. "skeleton PLY"
  std::string what;    // what is wrong with the file, for the table
  std::vector<std::pair<std::string, std::string>> files;  // name and bytes of every input
  std::string command;                                     // arguments of `ramiform`
  std::string bad_file;                                    // the file the message must name
  // What follows the file's path in the message: ":LINE:" (text), ": ELEMENT K:" (element of
  // a binary file or a whole skeleton), or ": " for a problem of the whole file (it is empty or
  // holds no data; InputError's line 0).
  std::string location;
};

// ---- Building the inputs ----

constexpr const char* kFork =
    R"({"nodes":[{"position":[0,0,0],"radius":0.5},{"position":[0,0,3],"radius":0.4},)"
    R"({"position":[-1.5,0,5],"radius":0.3},{"position":[1.5,0,5],"radius":0.3}],)"
    R"("edges":[[0,1],[1,2],[1,3]]})";

constexpr const char* kSkeletonVertex =
    "property float x\nproperty float y\nproperty float z\nproperty float radius\n";
constexpr const char* kSkeletonVertexDouble =
    "property double x\nproperty double y\nproperty double z\nproperty double radius\n";
constexpr const char* kEdge = "property int vertex1\nproperty int vertex2\n";
constexpr const char* kMeshVertex = "property float x\nproperty float y\nproperty float z\n";
constexpr const char* kMeshVertexDouble =
    "property double x\nproperty double y\nproperty double z\n";
constexpr const char* kFace = "property list uchar int vertex_indices\n";
constexpr const char* kTriangle = "0 0 0\n1 0 0\n0 1 0\n";

// A PLY file: magic, format line, the element declarations `elements`, end_header, `body`.
std::string ply(const std::string& format, const std::string& elements, const std::string& body) {
  return "ply\nformat " + format + " 1.0\n" + elements + "end_header\n" + body;
}

std::string element(const std::string& name, const std::string& count,
                    const std::string& properties) {
  return "element " + name + " " + count + "\n" + properties;
}

// Values as bytes in little- or big-endian order (the test machines are little-endian).
template <typename T>
std::string bytes_of(const std::vector<T>& values, bool big_endian = false) {
  std::string out;
  for (const T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

// Deterministic binary garbage: every byte value occurs, '\n' among them.
std::string garbage(std::size_t n) {
  std::string out(n, '\0');
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<char>((i * 37 + 11) % 256);
  return out;
}

std::string repeat(const std::string& s, std::size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (std::size_t i = 0; i < n; ++i) out += s;
  return out;
}

constexpr std::size_t k50MB = 50'000'000;

const std::string kBom = "\xEF\xBB\xBF";
// A script prefix that stages an output before the failing line, so that a run that fails
// must also remove the staged file.
const std::string kStaging = "sphere s 1\nsave_mesh s before.ply resolution=8\n";

// A TreeQSM row: radius, length, start xyz, axis xyz, parent (tab-separated).
std::string qsm_row(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i > 0 ? "\t" : "") + v[i];
  return out + "\n";
}
const std::string kQsmRoot = qsm_row({"0.2", "1", "0", "0", "0", "0", "0", "1", "0"});
const std::string kSimpleForestHeader = "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n";

// ---- The cases, one block per reader ----

std::vector<Case> skeleton_json_cases() {
  const std::string cmd = "convert @in.json @out.json --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"skeleton JSON", std::move(what),    {{"in.json", std::move(text)}}, cmd,
                "in.json",       std::move(location)};
  };
  const std::string two = R"({"nodes":[{"position":[0,0,0],"radius":0.5},)"
                          R"({"position":[0,0,1],"radius":0.5}],"edges":)";
  const std::string deep = repeat("[", 100'000) + repeat("]", 100'000);
  return {
      c("empty file", "", ": "),
      c("truncated inside a node",
        "{\"nodes\":[{\"position\":[0,0,0],\"radius\":0.5},\n{\"position\":[0,0", ":2:"),
      c("NaN literal", R"({"nodes":[{"position":[0,0,NaN],"radius":0.5}]})", ":1:"),
      c("number too large for a double (1e999)",
        R"({"nodes":[{"position":[0,0,0],"radius":1e999}]})", ":1:"),
      c("radius written as a string", R"({"nodes":[{"position":[0,0,0],"radius":"0.5"}]})",
        ": node 0:"),
      c("position with 2 numbers", R"({"nodes":[{"position":[0,0],"radius":0.5}]})", ": node 0:"),
      c("negative radius",
        R"({"nodes":[{"position":[0,0,0],"radius":0.5},{"position":[0,0,1],"radius":-1}]})",
        ": node 1:"),
      c("edge index 1.0", two + "[[0,1.0]]}", ": edge 0:"),
      c("negative edge index", two + "[[0,-1]]}", ": edge 0:"),
      c("edge index out of range", two + "[[0,1],[1,2]]}", ": edge 1:"),
      c("self-loop", two + "[[1,1]]}", ": edge 0:"),
      c("duplicate edge, reversed", two + "[[0,1],[1,0]]}", ": edge 1:"),
      c("edge of three indices", two + "[[0,1,1]]}", ": edge 0:"),
      c("curved edge: a control of two numbers",
        two + R"([{"nodes":[0,1],"controls":[[0,1]]}]})", ": edge 0: control point 0"),
      c("curved edge: a control that is not a number",
        two + R"([{"nodes":[0,1],"controls":[[0,"x",1]]}]})", ": edge 0: control point 0"),
      c("curved edge: two radii for one control",
        two + R"([{"nodes":[0,1],"controls":[[0,1,0]],"radii":[1,2]}]})", ": edge 0: 2 radii"),
      c("curved edge: 15 inner controls (degree 16)",
        two + R"([{"nodes":[0,1],"controls":[)" + [] {
          std::string c;
          for (int k = 0; k < 15; ++k) c += (k ? ",[" : "[") + std::to_string(k) + ",1,0]";
          return c;
        }() + "]}]}",
        ": edge 0: 15 control points"),
      c("curved edge: unknown key", two + R"([{"nodes":[0,1],"control":[[0,1,0]]}]})",
        ": edge 0: unknown key"),
      c("zero-length edge (two nodes at one position)",
        R"({"nodes":[{"position":[1,2,3],"radius":0.5},{"position":[1,2,3],"radius":0.5}],)"
        R"("edges":[[0,1]]})",
        ": edge 0:"),
      c("radius nested 100,000 arrays deep",
        R"({"nodes":[{"position":[0,0,0],"radius":)" + deep + "}]}", ": node 0:"),
      c("edge index nested 100,000 arrays deep", two + "[[" + deep + ",1]]}", ": edge 0:"),
      c("top level nested 100,000 arrays deep", deep, ": "),
      c("no \"nodes\" key", R"({"edges":[]})", ": "),
      c("empty \"nodes\" array", R"({"nodes":[]})", ": "),
      c("coordinates spanning more than a double",
        R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[-1e308,0,0],"radius":1},)"
        R"({"position":[1e308,0,0],"radius":1}]})",
        ": node 1:"),
      c("binary garbage", garbage(3000), ":1:"),
      c("UTF-16 text", std::string("\xFF\xFE{\0\"\0n\0", 8), ":1:"),
      c("a second document after the first",
        R"({"nodes":[{"position":[0,0,0],"radius":0.5}]})"
        "\n{\"nodes\":[]}",
        ":2:"),
      c("// comment", "// tree\n{\"nodes\":[]}", ":1:"),
      c("unterminated 50 MB line",
        R"({"nodes":[{"position":[0,0,0],"radius":0.5})" + std::string(k50MB, ' '), ":1:"),
  };
}

std::vector<Case> skeleton_ply_cases() {
  const std::string cmd = "convert @in.ply @out.json --stats @stats.json";
  const auto c = [&](std::string what, std::string bytes, std::string location) {
    return Case{"skeleton PLY", std::move(what),    {{"in.ply", std::move(bytes)}}, cmd,
                "in.ply",       std::move(location)};
  };
  const std::string vertex2 = element("vertex", "2", kSkeletonVertex);
  const std::string edges1 = element("edge", "1", kEdge);
  const std::string nodes2 = "0 0 0 1\n0 0 1 1\n";
  return {
      c("header claims 4,000,000,000 vertices (ASCII)",
        ply("ascii", element("vertex", "4000000000", kSkeletonVertex), "0 0 0 1\n"), ": vertex 1:"),
      c("header claims 4,000,000,000 vertices (binary)",
        ply("binary_little_endian", element("vertex", "4000000000", kSkeletonVertexDouble),
            bytes_of<double>({0, 0, 0, 1})),
        ": vertex 1:"),
      c("4,000,000,000 edges with a list property, 100 bytes of body",
        ply("binary_little_endian",
            element("vertex", "1", kSkeletonVertexDouble) +
                element(
                    "edge", "4000000000",
                    "property list uchar int junk\nproperty int vertex1\nproperty int vertex2\n"),
            bytes_of<double>({0, 0, 0, 1}) + std::string(100, '\0')),
        ": edge 11:"),
      c("element count beyond 64 bits",
        ply("ascii", element("vertex", "99999999999999999999", kSkeletonVertex), "0 0 0 1\n"),
        ":3:"),
      c("header ends without end_header",
        "ply\nformat ascii 1.0\nelement vertex 1\n" + std::string(kSkeletonVertex), ":7:"),
      c("no end_header before the body",
        "ply\nformat ascii 1.0\nelement vertex 1\n" + std::string(kSkeletonVertex) + "0 0 0 1\n",
        ":8:"),
      c("two format lines",
        "ply\nformat ascii 1.0\nformat binary_little_endian 1.0\n" +
            element("vertex", "1", kSkeletonVertex) + "end_header\n0 0 0 1\n",
        ":3:"),
      c("two vertex elements",
        ply("ascii",
            element("vertex", "1", kSkeletonVertex) + element("vertex", "1", kSkeletonVertex),
            "0 0 0 1\n0 0 1 1\n"),
        ":8:"),
      c("UTF-8 byte order mark before 'ply'",
        kBom + ply("ascii", element("vertex", "1", kSkeletonVertex), "0 0 0 1\n"), ":1:"),
      c("binary garbage after 'ply'", "ply\n" + garbage(3000), ":2:"),
      c("no radius property", ply("ascii", element("vertex", "1", kMeshVertex), "0 0 0\n"), ":3:"),
      c("nan coordinate (ASCII)", ply("ascii", vertex2 + edges1, "0 0 0 1\n0 0 nan 1\n0 1\n"),
        ":13:"),
      c("NaN coordinate (binary)",
        ply("binary_little_endian", element("vertex", "2", kSkeletonVertexDouble),
            bytes_of<double>({0, 0, 0, 1, 0, 0, std::numeric_limits<double>::quiet_NaN(), 1})),
        ": vertex 1:"),
      c("negative radius", ply("ascii", vertex2 + edges1, "0 0 0 1\n0 0 1 -1\n0 1\n"), ": node 1:"),
      c("self-loop", ply("ascii", vertex2 + edges1, nodes2 + "1 1\n"), ": edge 0:"),
      c("edge index 0.5 in a float column",
        ply("ascii",
            vertex2 + element("edge", "1", "property float vertex1\nproperty float vertex2\n"),
            nodes2 + "0 0.5\n"),
        ": edge 0:"),
      c("edge index out of range", ply("ascii", vertex2 + edges1, nodes2 + "0 7\n"), ": edge 0:"),
      c("edge index 300 in a uchar column",
        ply("ascii",
            vertex2 + element("edge", "1", "property uchar vertex1\nproperty uchar vertex2\n"),
            nodes2 + "0 300\n"),
        ":14:"),
      c("truncated big-endian body",
        ply("binary_big_endian", element("vertex", "3", kSkeletonVertexDouble),
            bytes_of<double>({0, 0, 0, 1, 0, 0}, true)),
        ": vertex 1:"),
      c("a record with 5 fields for 4 properties",
        ply("ascii", element("vertex", "1", kSkeletonVertex), "0 0 0 1 5\n"), ":9:"),
      c("text after the last element",
        ply("ascii", element("vertex", "1", kSkeletonVertex), "0 0 0 1\n1 2 3 4\n"), ":10:"),
      c("empty file", "", ": "),
  };
}

std::vector<Case> skeleton_obj_cases() {
  const std::string cmd = "convert @in.obj @out.json --obj-radius 0.1 --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"skeleton OBJ", std::move(what),    {{"in.obj", std::move(text)}}, cmd,
                "in.obj",       std::move(location)};
  };
  const std::string two = "v 0 0 0\nv 0 0 1\n";
  return {
      c("self-loop 'l 1 1'", two + "l 1 1\n", ": edge 0:"),
      c("duplicate edge 'l 1 2', 'l 2 1'", two + "l 1 2\nl 2 1\n", ": edge 1:"),
      c("index out of range", two + "l 1 3\n", ":3:"),
      c("index of a vertex defined below", "v 0 0 0\nl 1 2\nv 0 0 1\n", ":2:"),
      c("index 0", two + "l 0 1\n", ":3:"),
      c("negative index out of range", two + "l -3 -1\n", ":3:"),
      c("'l' with one index", two + "l 1\n", ":3:"),
      c("index with trailing characters", two + "l 1 2x\n", ":3:"),
      c("corner with four parts", two + "l 1/1/1/1 2\n", ":3:"),
      c("'v' with 2 numbers", "v 0 0\n", ":1:"),
      c("inf coordinate", "v 0 0 inf\n", ":1:"),
      c("hexadecimal coordinate", "v 0x10 0 0\n", ":1:"),
      c("no 'v' lines", "# nothing\nf 1 2 3\n", ": "),
      c("one 50 MB 'v' line", "v 0 0 0" + repeat(" 0", k50MB / 2), ":1:"),
  };
}

std::vector<Case> treeqsm_cases() {
  const std::string cmd = "convert @tree.txt @out.json --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"TreeQSM .txt", std::move(what),    {{"tree.txt", std::move(text)}}, cmd,
                "tree.txt",     std::move(location)};
  };
  const auto child = [](std::vector<std::string> v) { return kQsmRoot + qsm_row(v); };
  return {
      c("8 columns", child({"0.1", "1", "0", "0", "1", "0", "0", "1"}), ":2:"),
      c("radius 0", child({"0", "1", "0", "0", "1", "0", "0", "1", "1"}), ":2:"),
      c("negative radius", child({"-0.1", "1", "0", "0", "1", "0", "0", "1", "1"}), ":2:"),
      c("negative length", child({"0.1", "-1", "0", "0", "1", "0", "0", "1", "1"}), ":2:"),
      c("zero axis", child({"0.1", "1", "0", "0", "1", "0", "0", "0", "1"}), ":2:"),
      c("parent 1.5", child({"0.1", "1", "0", "0", "1", "0", "0", "1", "1.5"}), ":2:"),
      c("nan start", child({"0.1", "1", "0", "nan", "1", "0", "0", "1", "1"}), ":2:"),
      c("length 1e999", child({"0.1", "1e999", "0", "0", "1", "0", "0", "1", "1"}), ":2:"),
      c("end beyond double range", child({"0.1", "1e308", "0", "0", "1e308", "0", "0", "1", "1"}),
        ":2:"),
      c("cylinder ending at 1e308 (a span beyond double range)",
        qsm_row({"0.2", "1e308", "0", "0", "0", "0", "0", "1", "0"}), ": node 1:"),
      c("empty file", "", ": "),
      c("header line only", "radius length start_x start_y start_z\n", ": "),
      c("binary garbage", garbage(3000), ":2:"),
      c("one 50 MB line", repeat("0.2 ", k50MB / 4), ":1:"),
  };
}

std::vector<Case> simpleforest_cases() {
  const std::string cmd = "convert @tree.csv @out.json --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"SimpleForest .csv", std::move(what),    {{"tree.csv", std::move(text)}}, cmd,
                "tree.csv",          std::move(location)};
  };
  const std::string h = kSimpleForestHeader;
  return {
      c("no radius column", "ID,parentID,startX,startY,startZ,endX,endY,endZ\n0,-1,0,0,0,0,0,1\n",
        ":1:"),
      c("8 fields under a 9-column header", h + "0,-1,0,0,0,0,0,1\n", ":2:"),
      c("empty field", h + "0,-1,0,,0,0,0,1,0.1\n", ":2:"),
      c("comma at the end of a row", h + "0,-1,0,0,0,0,0,1,0.1,\n", ":2:"),
      c("repeated ID", h + "0,-1,0,0,0,0,0,1,0.1\n0,0,0,0,1,0,0,2,0.1\n", ":3:"),
      c("ID 1.5", h + "1.5,-1,0,0,0,0,0,1,0.1\n", ":2:"),
      c("negative radius", h + "0,-1,0,0,0,0,0,1,-0.1\n", ":2:"),
      c("nan end point", h + "0,-1,0,0,0,0,0,nan,0.1\n", ":2:"),
      c("semicolons instead of commas",
        "ID;parentID;startX;startY;startZ;endX;endY;endZ;radius\n0;-1;0;0;0;0;0;1;0.1\n", ":1:"),
      c("header only", h, ": "),
      Case{"SimpleForest .csv",
           "SimpleForest columns in a .txt file, radius 'x'",
           {{"tree.txt", h + "0,-1,0,0,0,0,0,1,x\n"}},
           "convert @tree.txt @out.json --stats @stats.json",
           "tree.txt",
           ":2:"},
  };
}

std::vector<Case> skeleton_via_commands_cases() {
  return {
      Case{"skeleton JSON",
           "negative radius, read by mesh",
           {{"tree.json", R"({"nodes":[{"position":[0,0,0],"radius":-1}]})"}},
           "mesh @tree.json -o @tree.ply --stats @stats.json",
           "tree.json",
           ": node 0:"},
      Case{"TreeQSM .txt",
           "radius 0, read by mesh",
           {{"tree.txt", kQsmRoot + qsm_row({"0", "1", "0", "0", "1", "0", "0", "1", "1"})}},
           "mesh @tree.txt -o @tree.ply --method mc --resolution 8 --stats @stats.json",
           "tree.txt",
           ":2:"},
      Case{"skeleton JSON",
           "edge out of range, read by eval",
           {{"tree.json", R"({"nodes":[{"position":[0,0,0],"radius":1}],"edges":[[0,1]]})"},
            {"points.xyz", "0 0 0\n"}},
           "eval @tree.json --points @points.xyz --stats @stats.json",
           "tree.json",
           ": edge 0:"},
      Case{"skeleton PLY",
           "self-loop, read by check --skeleton",
           {{"mesh.off", "OFF\n3 1 0\n" + std::string(kTriangle) + "3 0 1 2\n"},
            {"tree.ply",
             ply("ascii", element("vertex", "1", kSkeletonVertex) + element("edge", "1", kEdge),
                 "0 0 0 1\n0 0\n")}},
           "check @mesh.off --skeleton @tree.ply --stats @stats.json",
           "tree.ply",
           ": edge 0:"},
      Case{"skeleton JSON",
           "duplicate edge, read by the script command skeleton",
           {{"scene.rf", kStaging + "skeleton t tree.json\n"},
            {"tree.json", R"({"nodes":[{"position":[0,0,0],"radius":1},)"
                          R"({"position":[0,0,1],"radius":1}],"edges":[[0,1],[0,1]]})"}},
           "run @scene.rf --out @. --stats @stats.json",
           "tree.json",
           ": edge 1:"},
  };
}

std::vector<Case> mesh_ply_cases() {
  const std::string cmd = "check @mesh.ply --stats @stats.json";
  const auto c = [&](std::string what, std::string bytes, std::string location) {
    return Case{"mesh PLY", std::move(what), {{"mesh.ply", std::move(bytes)}},
                cmd,        "mesh.ply",      std::move(location)};
  };
  const std::string v3 = element("vertex", "3", kMeshVertex);
  const std::string f1 = element("face", "1", kFace);
  const std::string tri_floats = bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  return {
      c("face index out of range", ply("ascii", v3 + f1, kTriangle + std::string("3 0 1 3\n")),
        ": face 0:"),
      c("negative face index", ply("ascii", v3 + f1, kTriangle + std::string("3 0 1 -1\n")),
        ": face 0:"),
      c("face of 2 vertices", ply("ascii", v3 + f1, kTriangle + std::string("2 0 1\n")),
        ": face 0:"),
      c("float vertex indices",
        ply("ascii", v3 + element("face", "1", "property list uchar float vertex_indices\n"),
            kTriangle + std::string("3 0 1 2\n")),
        ":7:"),
      c("float list count type",
        ply("ascii", v3 + element("face", "1", "property list float int vertex_indices\n"),
            kTriangle + std::string("3 0 1 2\n")),
        ":8:"),
      c("face element without vertex_indices",
        ply("ascii", v3 + element("face", "1", "property int a\n"), kTriangle + std::string("1\n")),
        ":7:"),
      c("nx without ny and nz",
        ply("ascii", element("vertex", "3", std::string(kMeshVertex) + "property float nx\n"),
            "0 0 0 1\n1 0 0 1\n0 1 0 1\n"),
        ":3:"),
      c("header claims 4,000,000,000 faces",
        ply("binary_little_endian",
            element("vertex", "3", kMeshVertex) + element("face", "4000000000", kFace),
            tri_floats + "\x03" + bytes_of<std::int32_t>({0, 1, 2})),
        ": face 1:"),
      c("list of 255 indices, 3 present",
        ply("binary_little_endian", v3 + f1,
            tri_floats + "\xFF" + bytes_of<std::int32_t>({0, 1, 2})),
        ": face 0:"),
      c("list length 4294967295 (uint count)",
        ply("binary_little_endian",
            v3 + element("face", "1", "property list uint int vertex_indices\n"),
            tri_floats + bytes_of<std::uint32_t>({0xFFFFFFFFU}) +
                bytes_of<std::int32_t>({0, 1, 2})),
        ": face 0:"),
      c("infinite coordinate (binary)",
        ply("binary_little_endian", v3,
            bytes_of<float>({0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0})),
        ": vertex 2:"),
      c("two face elements",
        ply("ascii", v3 + f1 + f1, kTriangle + std::string("3 0 1 2\n3 0 1 9\n")), ":9:"),
      c("property x twice",
        ply("ascii",
            element("vertex", "3", "property float x\nproperty float x\nproperty float z\n"),
            kTriangle),
        ":5:"),
      c("property before any element",
        "ply\nformat ascii 1.0\nproperty float x\nelement vertex 0\nend_header\n", ":3:"),
      c("version 2.0", "ply\nformat ascii 2.0\nelement vertex 0\nend_header\n", ":2:"),
      c("unknown format 'binary'", "ply\nformat binary 1.0\nelement vertex 0\nend_header\n", ":2:"),
      c("no format line", "ply\nelement vertex 0\nend_header\n", ":3:"),
      c("unknown type float128",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", ":4:"),
      c("negative element count", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", ":3:"),
  };
}

std::vector<Case> mesh_obj_cases() {
  const std::string cmd = "check @mesh.obj --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"mesh OBJ", std::move(what), {{"mesh.obj", std::move(text)}},
                cmd,        "mesh.obj",      std::move(location)};
  };
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  return {
      c("'f' with 2 corners", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3:"),
      c("face index out of range", v3 + "f 1 2 4\n", ":4:"),
      c("texture index without 'vt'", v3 + "f 1/1 2/1 3/1\n", ":4:"),
      c("normal index without 'vn'", v3 + "f 1//1 2//1 3//1\n", ":4:"),
      c("'vn' with 2 numbers", "v 0 0 0\nvn 0 1\n", ":2:"),
      c("nan coordinate", "v 0 0 nan\n", ":1:"),
      c("no 'v' lines", "vt 0 0\n", ": "),
  };
}

std::vector<Case> mesh_off_cases() {
  const std::string cmd = "check @mesh.off --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"mesh OFF", std::move(what), {{"mesh.off", std::move(text)}},
                cmd,        "mesh.off",      std::move(location)};
  };
  const std::string tri = kTriangle;
  return {
      c("'COFF' header", "COFF\n3 1 0\n" + tri + "3 0 1 2\n", ":1:"),
      c("file ends after 2 of 3 vertices", "OFF\n3 1 0\n0 0 0\n1 0 0\n", ":4:"),
      c("counts claim 4,000,000,000 vertices", "OFF\n4000000000 1 0\n" + tri, ":5:"),
      c("counts claim 99,999,999,999,999 faces", "OFF\n3 99999999999999 0\n" + tri + "3 0 1 2\n",
        ":6:"),
      c("negative vertex count", "OFF\n-3 1 0\n", ":2:"),
      c("counts line with one number", "OFF\n3\n", ":2:"),
      c("vertex with 4 numbers", "OFF\n3 1 0\n0 0 0 1\n1 0 0\n0 1 0\n3 0 1 2\n", ":3:"),
      c("face index out of range", "OFF\n3 1 0\n" + tri + "3 0 1 3\n", ":6:"),
      c("face claims 99,999,999,999 corners", "OFF\n3 1 0\n" + tri + "99999999999 0 1 2\n", ":6:"),
      c("a face more than counted", "OFF\n3 1 0\n" + tri + "3 0 1 2\n3 0 1 2\n", ":7:"),
      c("binary garbage", garbage(3000), ":1:"),
      c("empty file", "", ": "),
  };
}

std::vector<Case> mesh_via_script_cases() {
  const std::string cmd = "run @scene.rf --out @. --stats @stats.json";
  return {
      Case{"mesh OFF",
           "face index out of range, read by the script command mesh_shape",
           {{"scene.rf", kStaging + "mesh_shape m mesh.off\n"},
            {"mesh.off", "OFF\n3 1 0\n" + std::string(kTriangle) + "3 0 1 5\n"}},
           cmd,
           "mesh.off",
           ":6:"},
      Case{"mesh OBJ",
           "face index out of range, read by the script command point_set_mesh",
           {{"scene.rf", kStaging + "point_set_mesh p mesh.obj\n"},
            {"mesh.obj", "v 0 0 0\nf 1 2 3\n"}},
           cmd,
           "mesh.obj",
           ":2:"},
      Case{"mesh PLY",
           "face of 2 vertices, read by the script command mesh_shape",
           {{"scene.rf", kStaging + "mesh_shape m mesh.ply\n"},
            {"mesh.ply",
             ply("ascii", element("vertex", "3", kMeshVertex) + element("face", "1", kFace),
                 kTriangle + std::string("2 0 1\n"))}},
           cmd,
           "mesh.ply",
           ": face 0:"},
  };
}

std::vector<Case> point_cases() {
  const std::string eval = "eval @tree.json --points @{} --stats @stats.json";
  const std::string grow = "grow --points @{} -o @tree.json --stats @stats.json";
  const auto c = [](std::string reader, std::string what, std::string name, std::string bytes,
                    const std::string& command, std::string location) {
    std::string cmd = command;
    cmd.replace(cmd.find("{}"), 2, name);
    Case k{std::move(reader),  std::move(what), {{name, std::move(bytes)}}, cmd, name,
           std::move(location)};
    if (command.rfind("eval", 0) == 0) k.files.emplace_back("tree.json", kFork);
    return k;
  };
  const std::string pt = "points text";
  const std::string pp = "points PLY";
  return {
      c(pt, "2 numbers on line 2", "p.xyz", "0 0 0\n1 1\n", eval, ":2:"),
      c(pt, "6 numbers after lines of 3", "p.xyz", "0 0 0\n1 1 1 0 0 1\n", eval, ":2:"),
      c(pt, "empty field between commas", "p.xyz", "0,,0\n", eval, ":1:"),
      c(pt, "column names without '#'", "p.xyz", "x y z\n0 0 0\n", eval, ":1:"),
      c(pt, "nan coordinate", "p.xyz", "0 0 nan\n", eval, ":1:"),
      c(pt, "coordinate 1e999", "p.xyz", "0 0 1e999\n", eval, ":1:"),
      c(pt, "semicolons", "p.xyz", "0;0;0\n", eval, ":1:"),
      c(pt, "lone carriage returns as line breaks", "p.xyz", "0 0 0\r1 1 1\r", eval, ":1:"),
      c(pt, "empty file", "p.xyz", "", eval, ": "),
      c(pt, "comments only", "p.xyz", "# x y z\n\n", eval, ": "),
      c(pt, "binary garbage", "p.xyz", garbage(3000), eval, ":1:"),
      c(pt, "word on line 3", "p.xyz", "0 0 0\n1 1 1\n2 2 two\n", grow, ":3:"),
      c(pt, "hexadecimal coordinate", "p.xyz", "0x1 0 0\n", grow, ":1:"),
      c(pt, "coordinates spanning more than a double", "p.xyz", "0 0 0\n0 0 1e308\n1 1 -1e308\n",
        grow, ":2:"),
      c(pt, "one 50 MB line", "p.xyz", repeat("0 ", k50MB / 2), grow, ":1:"),
      c(pt, "every point within the kill distance of the root", "p.xyz", "0 0 0\n1 1 1\n", grow,
        ": "),
      c(pt, "one point, at the root", "p.xyz", "0 0 0\n", grow, ": "),
      c(pt, "zero normal on line 2", "p.xyz", "0 0 0 0 0 1\n1 1 1 0 0 0\n", eval, ":2:"),
      c(pp, "header claims 4,000,000,000 vertices", "p.ply",
        ply("ascii", element("vertex", "4000000000", kMeshVertex), "0 0 0\n"), eval, ": vertex 1:"),
      c(pp, "no z property", "p.ply",
        ply("ascii", element("vertex", "1", "property float x\nproperty float y\n"), "0 0\n"), eval,
        ":3:"),
      c(pp, "vertex count 0", "p.ply", ply("ascii", element("vertex", "0", kMeshVertex), ""), eval,
        ":3:"),
      c(pp, "truncated binary body", "p.ply",
        ply("binary_little_endian", element("vertex", "2", kMeshVertexDouble),
            bytes_of<double>({0, 0, 0, 1, 1})),
        grow, ": vertex 1:"),
      c(pp, "NaN coordinate (binary)", "p.ply",
        ply("binary_little_endian", element("vertex", "2", kMeshVertexDouble),
            bytes_of<double>({0, 0, 0, 1, std::numeric_limits<double>::quiet_NaN(), 1})),
        grow, ": vertex 1:"),
  };
}

std::vector<Case> point_via_script_cases() {
  const std::string cmd = "run @scene.rf --out @. --stats @stats.json";
  return {
      Case{"points text",
           "2 numbers, read by the script command load_point_set",
           {{"scene.rf", kStaging + "load_point_set p.xyz\n"}, {"p.xyz", "1 2\n"}},
           cmd,
           "p.xyz",
           ":1:"},
      Case{"points text",
           "every point within the kill distance of the root, grown by the script command grow",
           {{"scene.rf", kStaging + "load_point_set p.xyz\ngrow t from points\n"},
            {"p.xyz", "0 0 0\n1 1 1\n"}},
           cmd,
           "scene.rf",
           ":4:"},
      Case{"points text",
           "2 numbers on line 2, read by the script command eval_points",
           {{"scene.rf", kStaging + "eval_points s p.xyz values.txt\n"}, {"p.xyz", "1 2 3\n4 5\n"}},
           cmd,
           "p.xyz",
           ":2:"},
  };
}

std::vector<Case> props_cases() {
  const std::string run = "run @scene.rf --out @. --stats @stats.json";
  const auto c = [&](std::string what, std::string dist, std::string text, std::string location) {
    return Case{".props",
                std::move(what),
                {{"scene.rf", kStaging + "point_set_gen s " + dist + " p.props\n"},
                 {"p.props", std::move(text)}},
                run,
                "p.props",
                std::move(location)};
  };
  const std::string sample =
      "sample @scene.rf s --dist uniform --props @p.props -o @points.txt --stats @stats.json";
  return {
      c("no '='", "poisson", "count 100\n", ":1:"),
      c("misspelt key", "poisson", "count = 100\nmin_dist = 0.1\n", ":2:"),
      c("key given twice", "poisson", "count = 100\ncount = 200\n", ":2:"),
      c("count nan", "uniform", "count = nan\n", ":1:"),
      c("negative count", "uniform", "count = -5\n", ":1:"),
      c("negative min_distance", "poisson", "min_distance = -1\n", ":1:"),
      c("no key before '='", "uniform", "= 10\n", ":1:"),
      c("key without a value", "uniform", "count =\n", ":1:"),
      c("key starting with a digit", "uniform", "9count = 1\n", ":1:"),
      c("UTF-8 byte order mark before a line without '='", "uniform", kBom + "count 100\n", ":1:"),
      c("terminal escape sequence in a key", "uniform", "cou\x1b[2Jnt = 5\n", ":1:"),
      c("control byte in a value", "uniform", "count = 5\x07\n", ":1:"),
      c("binary garbage", "uniform", garbage(3000), ":1:"),
      Case{".props",
           "count 4,000,000,000,000, beyond the memory budget",
           {{"scene.rf", kStaging + "point_set_gen s uniform p.props\n"},
            {"p.props", "# many\ncount = 4000000000000\n"}},
           "run @scene.rf --out @. --stats @stats.json --max-memory 1G",
           "p.props",
           ":2:"},
      Case{".props",
           "count 'x', read by sample --props",
           {{"scene.rf", "sphere s 1\n"}, {"p.props", "count = x\n"}},
           sample,
           "p.props",
           ":1:"},
      Case{".props",
           "misspelt key, read by sample --props",
           {{"scene.rf", "sphere s 1\n"}, {"p.props", "# uniform\ncont = 5\n"}},
           sample,
           "p.props",
           ":2:"},
  };
}

std::vector<Case> curve_cases() {
  const std::string cmd = "run @scene.rf --out @. --stats @stats.json";
  const auto c = [&](std::string reader, std::string what, std::string line, std::string name,
                     std::string text, std::string location) {
    return Case{std::move(reader),
                std::move(what),
                {{"scene.rf", kStaging + line + "\n"}, {name, std::move(text)}},
                cmd,
                name,
                std::move(location)};
  };
  const std::string c2 = "curve file (2-D)";
  const std::string c3 = "curve file (3-D path)";
  const std::string curve = "curve c polyline file=c.txt";
  const std::string path = "path p polyline file=p.txt";
  return {
      c(c2, "3 numbers on a line", curve, "c.txt", "0 0\n1 1 1\n", ":2:"),
      c(c2, "nan coordinate", curve, "c.txt", "0 0\n1 nan\n", ":2:"),
      c(c2, "empty field between commas", curve, "c.txt", "0,,0\n", ":1:"),
      c(c2, "empty file", curve, "c.txt", "", ": "),
      c(c2, "binary garbage", curve, "c.txt", garbage(3000), ":1:"),
      c(c3, "2 numbers on a line", path, "p.txt", "0 0 0\n1 1\n", ":2:"),
      c(c3, "coordinate 1e999", path, "p.txt", "0 0 0\n1 1 1e999\n", ":2:"),
      c(c3, "one 50 MB line", path, "p.txt", repeat("0 ", k50MB / 2), ":1:"),
  };
}

std::vector<Case> script_cases() {
  const std::string cmd = "run @scene.rf --out @. --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"scene script .rf", std::move(what),    {{"scene.rf", std::move(text)}}, cmd,
                "scene.rf",         std::move(location)};
  };
  std::string deep = "sphere a\n";
  // kMaxFieldDepth = 500: the union on line 501 would nest 501 deep (a chain of moves would
  // not: transforms of transforms compose into one).
  for (int i = 0; i < 500; ++i) deep += "union a a a\n";
  return {
      c("NUL byte in a command", kStaging + std::string("sphere\0 t\n", 10), ":3:"),
      c("terminal escape sequence", kStaging + "\x1b[2Jsphere t\n", ":3:"),
      c("unknown command", kStaging + "spere t\n", ":3:"),
      c("UTF-8 byte order mark, then an unknown command on line 3", kBom + kStaging + "spere t\n",
        ":3:"),
      c("UTF-8 letter in a command", kStaging + "sph\xC3\xA8re t\n", ":3:"),
      c("UTF-8 letter in an option", kStaging + "sphere t 1 c\xC3\xA9nter=0,0,0\n", ":3:"),
      c("unterminated quote", kStaging + "save_mesh s \"a.ply\n", ":3:"),
      c("undeclared parameter", kStaging + "sphere t $r\n", ":3:"),
      c("nan radius", kStaging + "sphere t nan\n", ":3:"),
      c("radius 1e999", kStaging + "sphere t 1e999\n", ":3:"),
      c("negative radius", kStaging + "sphere t -1\n", ":3:"),
      c("option given twice", kStaging + "save_mesh s a.ply resolution=8 resolution=9\n", ":3:"),
      c("misspelt option", kStaging + "sphere t 1 centre=0,0,0\n", ":3:"),
      c("output outside --out", kStaging + "save_mesh s ../x.ply\n", ":3:"),
      c("shapes nested 501 deep", deep, ":501:"),
      c("one 50 MB line", kStaging + "sphere t " + std::string(k50MB, '1'), ":3:"),
      Case{"RBF constraints (script rbf)",
           "3 numbers on a line",
           {{"scene.rf", kStaging + "rbf b c.txt\n"}, {"c.txt", "0 0 0 1\n1 1 1\n"}},
           cmd,
           "c.txt",
           ":2:"},
      Case{"RBF constraints (script rbf)",
           "nan value",
           {{"scene.rf", kStaging + "rbf b c.txt\n"}, {"c.txt", "0 0 0 nan\n"}},
           cmd,
           "c.txt",
           ":1:"},
      Case{"L-system file",
           "unfinished module, read by the script command lsystem",
           {{"scene.rf", kStaging + "lsystem t l.txt\n"}, {"l.txt", "axiom: F(\n"}},
           cmd,
           "l.txt",
           ":1:"},
      Case{"L-system file",
           "UTF-8 byte order mark, 'axiom' without ':', read by the script command lsystem",
           {{"scene.rf", kStaging + "lsystem t l.txt\n"}, {"l.txt", kBom + "axiom F\n"}},
           cmd,
           "l.txt",
           ":1:"},
      Case{"L-system file",
           "UTF-8 byte order mark before an unfinished module",
           {{"l.txt", kBom + "axiom: F(\n"}},
           "lsystem @l.txt -o @tree.json --stats @stats.json",
           "l.txt",
           ":1:"},
      Case{"L-system file",
           "UTF-8 letter as a module",
           {{"l.txt", "axiom: F\xC3\xA8\nF -> FF\n"}},
           "lsystem @l.txt -o @tree.json --stats @stats.json",
           "l.txt",
           ":1:"},
      Case{"L-system file",
           "unfinished module, read by lsystem",
           {{"l.txt", "axiom: F(\n"}},
           "lsystem @l.txt -o @tree.json --stats @stats.json",
           "l.txt",
           ":1:"},
      Case{"L-system file",
           "'axiom' without ':'",
           {{"l.txt", "axiom F\nF -> F[+F]F\n"}},
           "lsystem @l.txt -o @tree.json --stats @stats.json",
           "l.txt",
           ":1:"},
  };
}

std::vector<Case> swc_cases() {
  const std::string cmd = "convert @cell.swc @out.json --stats @stats.json";
  const auto c = [&](std::string what, std::string text, std::string location) {
    return Case{"SWC .swc", std::move(what), {{"cell.swc", std::move(text)}}, cmd, "cell.swc",
                std::move(location)};
  };
  const std::string soma = "# soma\n1 1 0 0 0 5 -1\n";
  return {
      c("6 fields", soma + "2 3 0 10 0 1\n", ":3:"),
      c("8 fields", soma + "2 3 0 10 0 1 1 7\n", ":3:"),
      c("coordinate 'x'", soma + "2 3 0 x 0 1 1\n", ":3:"),
      c("nan coordinate", soma + "2 3 0 nan 0 1 1\n", ":3:"),
      c("radius 0", soma + "2 3 0 10 0 0 1\n", ":3:"),
      c("negative radius", soma + "2 3 0 10 0 -1 1\n", ":3:"),
      c("index 2.5", soma + "2.5 3 0 10 0 1 1\n", ":3:"),
      c("negative index", soma + "-2 3 0 10 0 1 1\n", ":3:"),
      c("parent -2", soma + "2 3 0 10 0 1 -2\n", ":3:"),
      c("its own parent", soma + "2 3 0 10 0 1 2\n", ":3:"),
      c("unknown parent", soma + "2 3 0 10 0 1 9\n", ":3:"),
      c("duplicate index", soma + "1 3 0 10 0 1 -1\n", ":3:"),
      c("cycle of parents", soma + "2 3 0 10 0 1 3\n3 3 0 20 0 1 2\n", ":3:"),
      c("empty file", "", ": "),
      c("comments only", "# nothing\n# here\n", ": "),
      c("binary garbage", garbage(3000), ":1:"),
  };
}

std::vector<Case> all_cases() {
  std::vector<Case> all;
  for (auto block :
       {skeleton_json_cases(), skeleton_ply_cases(), skeleton_obj_cases(), treeqsm_cases(),
        simpleforest_cases(), skeleton_via_commands_cases(), mesh_ply_cases(), mesh_obj_cases(),
        mesh_off_cases(), mesh_via_script_cases(), point_cases(), point_via_script_cases(),
        props_cases(), curve_cases(), script_cases(), swc_cases()}) {
    for (Case& c : block) all.push_back(std::move(c));
  }
  // Rows grouped by reader, in the order given within a reader.
  std::stable_sort(all.begin(), all.end(),
                   [](const Case& a, const Case& b) { return a.reader < b.reader; });
  return all;
}

// ---- Running them and writing the table ----

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) {
    s.replace(p, from.size(), to);
  }
  return s;
}

bool is_printable_ascii(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) {
    const auto b = static_cast<unsigned char>(c);
    return b >= 0x20 && b < 0x7f;
  });
}

// A table cell: the text as a code span, '|' escaped for the table.
std::string code_cell(const std::string& text) {
  const std::string fence = text.find('`') == std::string::npos ? "`" : "`` ";
  const std::string close = fence == "`" ? "`" : " ``";
  return fence + replace_all(text, "|", "\\|") + close;
}

std::string text_cell(const std::string& text) { return replace_all(text, "|", "\\|"); }

const char* const kBegin = "<!-- malformed:begin -->";
const char* const kEnd = "<!-- malformed:end -->";

TEST(MalformedFiles, EveryReaderRefusesThemCleanly) {
  const std::vector<Case> cases = all_cases();
  ASSERT_GE(cases.size(), 70U);
  const fs::path base = temp_dir("malformed");
  std::ostringstream table;
  table << "| # | reader | command (`ramiform ...`) | what is wrong | message | exit |\n"
        << "|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    SCOPED_TRACE(c.reader + ": " + c.what);
    char name[32];
    std::snprintf(name, sizeof name, "case%03zu", i + 1);
    const fs::path dir = base / name;
    fs::create_directory(dir);
    const std::string prefix = dir.string() + "/";
    std::vector<std::string> inputs;
    for (const auto& [file, bytes] : c.files) {
      std::ofstream(dir / file, std::ios::binary) << bytes;
      inputs.push_back(file);
    }
    std::sort(inputs.begin(), inputs.end());

    const CliRun r = run_cli(replace_all(c.command, "@", prefix), 60);
    EXPECT_EQ(r.code, 2) << r.out.substr(0, 2000);
    EXPECT_EQ(r.out.rfind("ramiform: error: ", 0), 0U) << r.out.substr(0, 2000);
    EXPECT_TRUE(!r.out.empty() && r.out.find('\n') == r.out.size() - 1) << "one line expected:\n"
                                                                        << r.out.substr(0, 2000);
    const std::string message = r.out.empty() ? r.out : r.out.substr(0, r.out.size() - 1);
    EXPECT_TRUE(is_printable_ascii(message)) << message.substr(0, 2000);
    const std::string where = prefix + c.bad_file + c.location;
    EXPECT_NE(message.find(where), std::string::npos) << "expected '" << where << "' in\n"
                                                      << message.substr(0, 2000);
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, inputs) << "the run left files behind";

    const std::string shown = replace_all(message, prefix, "");
    table << "| " << i + 1 << " | " << text_cell(c.reader) << " | "
          << code_cell(replace_all(replace_all(c.command, "@.", "."), "@", "")) << " | "
          << text_cell(c.what) << " | " << code_cell(shown.substr(0, 600)) << " | " << r.code
          << " |\n";
  }
  fs::remove_all(base);

  const std::string generated = table.str();
  std::ofstream(fs::path(RAMIFORM_BUILD_DIR) / "reliability_table.md") << generated;

  const fs::path doc = fs::path(RAMIFORM_SOURCE_DIR) / "docs" / "reliability.md";
  const std::string text = read_file(doc.string());
  const std::size_t begin = text.find(kBegin);
  const std::size_t end = text.find(kEnd);
  ASSERT_TRUE(begin != std::string::npos && end != std::string::npos && begin < end)
      << doc << " needs the markers " << kBegin << " and " << kEnd;
  const std::size_t body = begin + std::strlen(kBegin);
  const std::string documented = text.substr(body, end - body);
  const std::string wanted = "\n" + generated;
  if (documented == wanted) return;
  const char* update = std::getenv("RAMIFORM_UPDATE_DOCS");
  if (update != nullptr && std::string(update) == "1") {
    std::ofstream(doc, std::ios::binary) << text.substr(0, body) + wanted + text.substr(end);
    return;
  }
  ADD_FAILURE() << "the table in " << doc << " differs from the generated one ("
                << RAMIFORM_BUILD_DIR << "/reliability_table.md); regenerate it with\n"
                << "  RAMIFORM_UPDATE_DOCS=1 ctest -R Malformed";
}

// Controls, kept out of the table: files that only look malformed are read in full. A UTF-8 byte
// order mark used to hide the first line of OBJ and TreeQSM files (a vertex or the root
// cylinder was dropped without a word) and to spoil the first key of a props file; CRLF line
// ends are allowed everywhere.
TEST(MalformedFiles, LookalikesAreReadInFull) {
  const fs::path dir = temp_dir("malformed-lookalikes");
  const auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return (dir / name).string();
  };
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  struct Control {
    std::string args;
    std::string expected;  // in the output
  };
  const std::vector<Control> controls = {
      {"check " + write("bom.obj", kBom + quad), "vertices    4\ntriangles   2\n"},
      {"check " + write("crlf.obj", replace_all(quad, "\n", "\r\n")), "vertices    4\n"},
      {"check " + write("bom.off", kBom + "OFF\n3 1 0\n" + kTriangle + "3 0 1 2\n"),
       "vertices    3\n"},
      {"convert " +
           write("bom.txt",
                 kBom + kQsmRoot + qsm_row({"0.1", "1", "0", "0", "1", "0", "0", "1", "1"})) +
           " " + (dir / "a.json").string(),
       "cylinders 2:"},
      {"convert " + write("bom.csv", kBom + kSimpleForestHeader + "0,-1,0,0,0,0,0,1,0.1\n") + " " +
           (dir / "b.json").string(),
       "cylinders 1:"},
      {"eval " + write("fork.json", kFork) + " --points " +
           write("bom.xyz", kBom + "0 0 1\r\n0 0 2\r\n"),
       "\n"},
  };
  for (const Control& c : controls) {
    const CliRun r = run_cli(c.args, 60);
    EXPECT_EQ(r.code, 0) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expected), std::string::npos) << c.args << "\n" << r.out;
  }
  // A script and an L-system file with a byte order mark: their first line is a command.
  const CliRun script = run_cli("run " + write("bom.rf", kBom + "sphere s 1\r\ninfo s\r\n") +
                                " --out " + dir.string());
  EXPECT_EQ(script.code, 0) << script.out;
  EXPECT_NE(script.out.find("s: sphere"), std::string::npos) << script.out;
  const CliRun lsystem = run_cli("lsystem " + write("bom.lsys", kBom + "axiom: F\r\nF -> FF\r\n") +
                                 " --iterations 2 -o " + (dir / "l.json").string());
  EXPECT_EQ(lsystem.code, 0) << lsystem.out;
  EXPECT_NE(lsystem.out.find("4 edges"), std::string::npos) << lsystem.out;
  const CliRun two =
      run_cli("eval " + (dir / "fork.json").string() + " --points " + (dir / "bom.xyz").string());
  EXPECT_EQ(std::count(two.out.begin(), two.out.end(), '\n'), 2) << two.out;
  // A props file with a byte order mark and CRLF line ends: its count is read (5 points).
  const std::string sampled = (dir / "sampled.txt").string();
  const CliRun props = run_cli(
      "sample " + write("s.rf", "sphere s 1\n") + " s --dist uniform --props " +
      write("bom.props", kBom + "count = 5\r\nmax_attempts = 100000\r\n") + " -o " + sampled);
  EXPECT_EQ(props.code, 0) << props.out;
  const std::string points = read_file(sampled);
  EXPECT_EQ(std::count(points.begin(), points.end(), '\n'), 5) << points;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ramiform::test
