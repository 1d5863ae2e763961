// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal PLY support shared by the skeleton, mesh and point readers and writers: one header
// parser, one body reader (ASCII, binary little- and big-endian) and one binary writer.

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace ramiform::io_detail {

enum class PlyType : std::uint8_t {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kFloat32,
  kFloat64
};
enum class PlyEncoding : std::uint8_t { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat64;  // scalar type, or the item type of a list
  bool is_list = false;
  PlyType count_type = PlyType::kUInt8;  // lists only
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t header_line = 0;  // line of its "element" line

  /// Index of the property called `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> find(std::string_view property) const;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;      // first byte after the end_header line
  std::size_t end_header_line = 0;  // line number of "end_header"

  /// Index of the first element called `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> find(std::string_view element) const;
};

/// Parses the header; throws InputError(source, line, ...) on a malformed header.
PlyHeader parse_ply_header(std::string_view data, const std::string& source);

/// The index of the scalar property `name` of `element`; throws InputError naming the element's
/// header line when it is missing or is a list.
std::size_t require_scalar(const PlyElement& element, std::string_view name,
                           const std::string& source);
/// Like require_scalar, but nullopt when the property is absent.
std::optional<std::size_t> optional_scalar(const PlyElement& element, std::string_view name,
                                           const std::string& source);

/// What to extract from one element of the body.
struct PlyRequest {
  std::size_t element = 0;           // index into PlyHeader::elements
  std::vector<std::size_t> scalars;  // scalar property indices, read as finite doubles
  std::optional<std::size_t> list;   // one list property of an integer type, read as int64
};

/// The request for the scalars `names` (each required, in that order) of the 'vertex' element;
/// throws InputError when the header has no 'vertex' element or it lacks one of them.
PlyRequest vertex_request(const PlyHeader& header, std::initializer_list<std::string_view> names,
                          const std::string& source);
/// Appends the vertex normal properties nx, ny, nz to a vertex_request when all three are
/// present and returns true; false when none is; throws InputError when only some are.
bool add_vertex_normals(const PlyHeader& header, PlyRequest& request, const std::string& source);

/// Adds the vertex element's texture coordinates to `request` when it has them, as one of the
/// pairs (u, v), (s, t) or (texture_u, texture_v), first found first; false when it has none.
/// Throws InputError when only one of a pair is there.
bool add_vertex_uvs(const PlyHeader& header, PlyRequest& request, const std::string& source);

/// What was extracted for one request.
struct PlyElementData {
  std::size_t count = 0;
  std::vector<double> scalars;            // count x request.scalars.size(), row-major
  std::vector<std::size_t> list_offsets;  // count + 1 entries when a list was requested
  std::vector<std::int64_t> list_values;  // all list items, back to back
};

/// Reads the body after `header`, skipping every property and element not requested. Throws
/// InputError naming the line (ASCII) or the element and its index (binary) on malformed, too
/// short or non-finite data. Returns one result per request, in request order.
std::vector<PlyElementData> read_ply_body(std::string_view data, const PlyHeader& header,
                                          const std::vector<PlyRequest>& requests,
                                          const std::string& source);

/// A column of a binary PLY element to write.
struct PlyColumn {
  std::string name;
  PlyType type = PlyType::kFloat64;
};

/// Incremental binary little-endian PLY writer: header first, then elements in header order.
class PlyWriter {
 public:
  explicit PlyWriter(std::ostream& out) : out_(out) {}
  /// Writes "ply", the format line and a comment; then declare elements.
  void begin(std::string_view comment);
  void element(std::string_view name, std::size_t count, const std::vector<PlyColumn>& columns);
  void list_element(std::string_view name, std::size_t count, PlyType count_type, PlyType item_type,
                    std::string_view property);
  void end_header();

  /// Appends one value of the given type (little-endian) to the body buffer.
  void put(PlyType type, double value);
  void put_index(PlyType type, std::uint64_t value);
  /// Writes the buffered body bytes when the buffer is large, or always when `force`.
  void flush(bool force = false);

 private:
  std::ostream& out_;
  std::string header_;
  std::string buffer_;
};

}  // namespace ramiform::io_detail
