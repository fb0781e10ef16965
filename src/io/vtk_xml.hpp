#pragma once
// The small pieces of VTK's XML that the data files (vtk.hpp) and the collections (pvd.hpp) share.
#include <string>

namespace settle::io {

/// `text` with the five XML special characters written as entities.
std::string xml_escaped(const std::string& text);
/// The inverse of xml_escaped.
std::string xml_unescaped(const std::string& text);
/// The shortest text that reads back as the same double.
std::string vtk_number(double value);
/// The byte_order attribute of this machine's files: "LittleEndian" or "BigEndian".
const char* vtk_byte_order();

}  // namespace settle::io
