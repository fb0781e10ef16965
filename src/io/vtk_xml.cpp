#include "io/vtk_xml.hpp"

#include <array>
#include <bit>
#include <string_view>
#include <utility>

#include <fmt/core.h>

namespace settle::io {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "VTK files declare either little- or big-endian byte order");

std::string xml_escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

std::string xml_unescaped(const std::string& text) {
  static const std::array<std::pair<std::string_view, char>, 5> entities{
      {{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}}};
  std::string plain;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    for (const auto& [entity, c] : entities) {
      if (text.compare(i, entity.size(), entity) == 0) {
        plain += c;
        i += entity.size();
        replaced = true;
        break;
      }
    }
    if (!replaced) plain += text[i++];
  }
  return plain;
}

std::string vtk_number(double value) { return fmt::format("{}", value); }

const char* vtk_byte_order() { return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian"; }

}  // namespace settle::io
