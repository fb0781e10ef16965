#pragma once
// Reading and writing STL files (ASCII and binary). The reader is meant to face arbitrary
// bytes: every count and offset is checked against the input size, numbers are parsed
// strictly, and every problem is a settle::InputError naming the file (and the line, for
// ASCII); it never reads out of bounds.
#include <filesystem>
#include <string>
#include <string_view>

#include "body/triangle_mesh.hpp"

namespace settle::body {

/// Format detection and vertex welding of one STL read.
struct StlReadInfo {
  bool binary = false;
  std::size_t facet_count = 0;
  std::size_t welded_vertex_count = 0;
};

/// Parses STL bytes. Format: a binary file has exactly 84 + 50 n bytes where n is the count in
/// bytes 80-83 (little-endian); an ASCII file starts with "solid". A file that starts with
/// "solid" but fails to parse as ASCII is read as binary when its size fits (some exporters
/// write "solid" into binary headers). Facet normals in the file are ignored: orientation comes
/// from the vertex order. Vertices with bit-identical coordinates are welded into one (STL
/// writers repeat shared vertices exactly; no tolerance is applied, so distinct points are never
/// merged). Refuses: empty input, truncated or over-long binary data, malformed ASCII, loops
/// that are not triangles, non-finite coordinates, zero facets.
TriangleMesh parse_stl(std::string_view bytes, const std::string& source, StlReadInfo* info = nullptr);

/// Reads an STL file (see parse_stl). Files above 2 GiB are refused.
TriangleMesh read_stl(const std::filesystem::path& path, StlReadInfo* info = nullptr);

void write_stl_ascii(const TriangleMesh& mesh, const std::filesystem::path& path, const std::string& name = "settle");
void write_stl_binary(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace settle::body
