#pragma once
// A reader of the VTK XML files settle writes (appended data, raw or zlib-compressed, UInt64 block
// headers): enough to take a file apart and read its arrays back in tests (tests/io/test_vtk.cpp,
// tests/app/). The compressed layout is read from the VTK file-format documentation, independently
// of io/vtk.cpp's writer.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <zlib.h>
#include <Eigen/Core>

namespace settle::test::vtk_reader {

namespace fs = std::filesystem;

inline std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::map<std::string, std::string> attributes_of(const std::string& element_text) {
  static const std::regex attribute(R"re((\w+)="([^"]*)")re");
  std::map<std::string, std::string> attributes;
  for (auto it = std::sregex_iterator(element_text.begin(), element_text.end(), attribute);
       it != std::sregex_iterator(); ++it)
    attributes[(*it)[1].str()] = (*it)[2].str();
  return attributes;
}

/// The attributes of the first element named `element` in `xml`.
inline std::map<std::string, std::string> element_attributes(const std::string& xml, const std::string& element) {
  const std::regex pattern("<" + element + R"(\s([^>]*)>)");
  std::smatch match;
  if (!std::regex_search(xml, match, pattern)) return {};
  return attributes_of(match[1].str());
}

inline Eigen::Vector3d parse_triple(const std::string& text) {
  std::istringstream in(text);
  Eigen::Vector3d v;
  in >> v(0) >> v(1) >> v(2);
  return v;
}

struct ParsedArray {
  std::string name, type, section;  // section: the enclosing FieldData/PointData/Points/Polys
  int components = 1;
  std::uint64_t offset = 0;
  std::uint64_t byte_count = 0;    // the values' size in bytes (uncompressed)
  std::string bytes;               // the values, decompressed
  std::uint64_t blocks = 0;        // compressed files: the array's block count
  std::uint64_t stored_bytes = 0;  // what the array takes in the file, header included
};

/// A VTK XML file with raw appended data, taken apart.
struct ParsedVtk {
  std::string xml;       // everything before the appended block's '_'
  std::string appended;  // everything after it
  std::vector<ParsedArray> arrays;

  const ParsedArray& array(const std::string& name) const {
    for (const ParsedArray& a : arrays)
      if (a.name == name) return a;
    throw std::runtime_error("no array " + name);
  }
};

inline constexpr std::string_view kTrailer = "\n  </AppendedData>\n</VTKFile>\n";

inline std::uint64_t uint64_at(const std::string& data, std::uint64_t at, const std::string& what) {
  if (at + 8 > data.size()) throw std::runtime_error("header beyond the file: " + what);
  std::uint64_t value;
  std::memcpy(&value, data.data() + at, 8);
  return value;
}

/// Raw: a UInt64 byte count, then the values.
inline void read_raw_block(const std::string& appended, ParsedArray& array) {
  array.byte_count = uint64_at(appended, array.offset, array.name);
  if (array.offset + 8 + array.byte_count > appended.size())
    throw std::runtime_error("block beyond the file: " + array.name);
  array.bytes = appended.substr(array.offset + 8, array.byte_count);
  array.stored_bytes = 8 + array.byte_count;
}

/// vtkZLibDataCompressor: UInt64 [blocks, block size, last block's size if partial (0 if full),
/// each block's compressed size], then the blocks, each deflated on its own.
inline void read_compressed_block(const std::string& appended, ParsedArray& array) {
  const std::uint64_t blocks = uint64_at(appended, array.offset, array.name);
  const std::uint64_t block_size = uint64_at(appended, array.offset + 8, array.name);
  const std::uint64_t last_size = uint64_at(appended, array.offset + 16, array.name);
  std::uint64_t at = array.offset + 24 + 8 * blocks;
  array.blocks = blocks;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t stored = uint64_at(appended, array.offset + 24 + 8 * b, array.name);
    if (at + stored > appended.size()) throw std::runtime_error("block beyond the file: " + array.name);
    const uLongf expected = static_cast<uLongf>(b + 1 == blocks && last_size != 0 ? last_size : block_size);
    uLongf size = expected;
    std::string values(size, '\0');
    if (uncompress(reinterpret_cast<Bytef*>(values.data()), &size, reinterpret_cast<const Bytef*>(appended.data() + at),
                   static_cast<uLong>(stored)) != Z_OK ||
        size != expected)
      throw std::runtime_error("zlib cannot inflate a block of " + array.name + " to its declared size");
    array.bytes += values;
    at += stored;
  }
  array.byte_count = array.bytes.size();
  array.stored_bytes = at - array.offset;
}

inline ParsedVtk parse_vtk(const fs::path& path) {
  const std::string content = read_bytes(path);
  const std::string marker = "<AppendedData encoding=\"raw\">";
  const std::size_t at = content.find(marker);
  if (at == std::string::npos) throw std::runtime_error("no appended data");
  const std::size_t underscore = content.find('_', at + marker.size());
  ParsedVtk parsed{content.substr(0, underscore), content.substr(underscore + 1), {}};

  const bool compressed = element_attributes(parsed.xml, "VTKFile")["compressor"] == "vtkZLibDataCompressor";
  static const std::regex tag(R"re(<(FieldData|PointData|CellData|Points|Polys)[\s>]|<DataArray ([^>]*)/>)re");
  std::string section;
  for (auto it = std::sregex_iterator(parsed.xml.begin(), parsed.xml.end(), tag); it != std::sregex_iterator(); ++it) {
    if ((*it)[1].matched) {
      section = (*it)[1].str();
      continue;
    }
    auto attributes = attributes_of((*it)[2].str());
    ParsedArray array;
    array.name = attributes["Name"];
    array.type = attributes["type"];
    array.section = section;
    if (attributes.count("NumberOfComponents")) array.components = std::stoi(attributes["NumberOfComponents"]);
    EXPECT_EQ(attributes["format"], "appended") << array.name;
    array.offset = std::stoull(attributes["offset"]);
    if (compressed)
      read_compressed_block(parsed.appended, array);
    else
      read_raw_block(parsed.appended, array);
    parsed.arrays.push_back(std::move(array));
  }
  return parsed;
}

inline std::size_t type_size(const std::string& type) {
  if (type == "Float32") return 4;
  if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
  throw std::runtime_error("unexpected type " + type);
}

/// The values of an array as doubles (Float32, Float64) or integers (Int64) converted to double.
inline std::vector<double> values_of(const ParsedArray& array) {
  const std::size_t size = type_size(array.type);
  std::vector<double> values(array.bytes.size() / size);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const char* p = array.bytes.data() + i * size;
    if (array.type == "Float32") {
      float v;
      std::memcpy(&v, p, 4);
      values[i] = v;
    } else if (array.type == "Float64") {
      std::memcpy(&values[i], p, 8);
    } else {
      std::int64_t v;
      std::memcpy(&v, p, 8);
      values[i] = static_cast<double>(v);
    }
  }
  return values;
}

}  // namespace settle::test::vtk_reader
