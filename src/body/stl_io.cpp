#include "body/stl_io.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <unordered_map>

#include <fmt/core.h>
#include <fmt/os.h>

#include "common/error.hpp"

namespace settle::body {
namespace {

constexpr std::size_t kBinaryHeaderBytes = 80;
constexpr std::size_t kBinaryPreambleBytes = 84;
constexpr std::size_t kBinaryFacetBytes = 50;
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{2} << 30;

using Triangle = std::array<Eigen::Vector3d, 3>;

// Welds bit-identical vertices. -0.0 and +0.0 are the same point, so zeros are normalised
// before hashing.
class VertexWelder {
 public:
  int index_of(const Eigen::Vector3d& p) {
    Key key{};
    for (int i = 0; i < 3; ++i) key[i] = std::bit_cast<std::uint64_t>(p(i) + 0.0);
    const auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p + Eigen::Vector3d::Zero());
    return it->second;
  }
  void add(const Triangle& tri) { mesh_.triangles.push_back({index_of(tri[0]), index_of(tri[1]), index_of(tri[2])}); }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  using Key = std::array<std::uint64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9E3779B97F4A7C15ull;
      for (std::uint64_t v : k) h = (h ^ v) * 0x100000001B3ull + (h >> 29);
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Key, int, KeyHash> index_;
  TriangleMesh mesh_;
};

// ---------------------------------------------------------------- ASCII
class AsciiTokenizer {
 public:
  AsciiTokenizer(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  bool at_end() {
    skip_space();
    return pos_ >= text_.size();
  }
  std::string_view next(const char* expected) {
    skip_space();
    if (pos_ >= text_.size()) fail(fmt::format("expected {}, got the end of the file", expected));
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  void expect(std::string_view keyword) {
    const std::string_view token = next(fmt::format("'{}'", keyword).c_str());
    if (!same_keyword(token, keyword)) fail(fmt::format("expected '{}', got '{}'", keyword, printable(token)));
  }
  double number() {
    const std::string_view token = next("a number");
    double value = 0.0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size()) {
      fail(fmt::format("'{}' is not a number", printable(token)));
    }
    if (!std::isfinite(value)) fail(fmt::format("coordinate '{}' is not finite", printable(token)));
    return value;
  }
  void skip_rest_of_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: ASCII STL: {}", source_, line_, what));
  }
  static bool same_keyword(std::string_view token, std::string_view keyword) {
    return token.size() == keyword.size() &&
           std::equal(token.begin(), token.end(), keyword.begin(),
                      [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  static std::string printable(std::string_view token) {
    std::string out;
    for (char c : token.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
    if (token.size() > 40) out += "...";
    return out;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

Triangle parse_ascii_facet(AsciiTokenizer& tokens) {
  tokens.expect("normal");
  for (int i = 0; i < 3; ++i) tokens.number();  // the file's normal is not trusted
  tokens.expect("outer");
  tokens.expect("loop");
  Triangle tri;
  for (auto& vertex : tri) {
    tokens.expect("vertex");
    for (int i = 0; i < 3; ++i) vertex(i) = tokens.number();
  }
  const std::string_view closing = tokens.next("'endloop'");
  if (AsciiTokenizer::same_keyword(closing, "vertex")) tokens.fail("a facet loop has more than 3 vertices");
  if (!AsciiTokenizer::same_keyword(closing, "endloop")) tokens.fail(fmt::format("expected 'endloop'"));
  tokens.expect("endfacet");
  return tri;
}

TriangleMesh parse_ascii(std::string_view text, const std::string& source, StlReadInfo& info) {
  AsciiTokenizer tokens(text, source);
  VertexWelder welder;
  tokens.expect("solid");
  tokens.skip_rest_of_line();  // the solid's name
  for (;;) {
    const std::string_view keyword = tokens.next("'facet' or 'endsolid'");
    if (AsciiTokenizer::same_keyword(keyword, "facet")) {
      welder.add(parse_ascii_facet(tokens));
      ++info.facet_count;
    } else if (AsciiTokenizer::same_keyword(keyword, "endsolid")) {
      tokens.skip_rest_of_line();
      if (tokens.at_end()) break;
      tokens.expect("solid");  // several solids in one file form one body
      tokens.skip_rest_of_line();
    } else {
      tokens.fail("expected 'facet' or 'endsolid'");
    }
  }
  return welder.take();
}

// ---------------------------------------------------------------- binary
std::uint32_t read_u32_le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

float read_f32_le(const unsigned char* p) { return std::bit_cast<float>(read_u32_le(p)); }

std::uint64_t binary_facet_count(std::string_view bytes) {
  return read_u32_le(reinterpret_cast<const unsigned char*>(bytes.data()) + kBinaryHeaderBytes);
}

bool has_binary_size(std::string_view bytes) {
  return bytes.size() >= kBinaryPreambleBytes &&
         kBinaryPreambleBytes + kBinaryFacetBytes * binary_facet_count(bytes) == bytes.size();
}

TriangleMesh parse_binary(std::string_view bytes, const std::string& source, StlReadInfo& info) {
  if (bytes.size() < kBinaryPreambleBytes) {
    throw InputError(fmt::format("{}: binary STL: {} bytes is shorter than the 84-byte header", source, bytes.size()));
  }
  const std::uint64_t count = binary_facet_count(bytes);
  const std::uint64_t needed = kBinaryPreambleBytes + kBinaryFacetBytes * count;
  if (needed != bytes.size()) {
    throw InputError(
        fmt::format("{}: binary STL: the header announces {} triangles ({} bytes) but the file has {} bytes", source,
                    count, needed, bytes.size()));
  }
  VertexWelder welder;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  for (std::uint64_t f = 0; f < count; ++f) {
    const unsigned char* facet = data + kBinaryPreambleBytes + kBinaryFacetBytes * f;
    Triangle tri;
    for (int v = 0; v < 3; ++v) {
      for (int i = 0; i < 3; ++i) {
        const float value = read_f32_le(facet + 12 + 12 * v + 4 * i);  // after the 12-byte normal
        if (!std::isfinite(value)) {
          throw InputError(fmt::format("{}: binary STL: triangle {} has a non-finite coordinate", source, f + 1));
        }
        tri[v](i) = static_cast<double>(value);
      }
    }
    welder.add(tri);
  }
  info.binary = true;
  info.facet_count = count;
  return welder.take();
}

bool starts_with_solid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\n' || bytes[i] == '\r')) ++i;
  return bytes.size() - i >= 5 && AsciiTokenizer::same_keyword(bytes.substr(i, 5), "solid");
}

}  // namespace

TriangleMesh parse_stl(std::string_view bytes, const std::string& source, StlReadInfo* info_out) {
  if (bytes.empty()) throw InputError(source + ": the STL file is empty");
  StlReadInfo info;
  TriangleMesh mesh;
  if (starts_with_solid(bytes)) {
    try {
      mesh = parse_ascii(bytes, source, info);
    } catch (const InputError&) {
      if (!has_binary_size(bytes)) throw;
      info = StlReadInfo{};
      mesh = parse_binary(bytes, source, info);
    }
  } else if (bytes.size() >= kBinaryPreambleBytes) {
    mesh = parse_binary(bytes, source, info);
  } else {
    throw InputError(
        fmt::format("{}: not an STL file: it does not start with 'solid' and its {} bytes are fewer "
                    "than a binary STL header",
                    source, bytes.size()));
  }
  if (mesh.triangles.empty()) throw InputError(source + ": the STL file contains no triangles");
  info.welded_vertex_count = mesh.vertices.size();
  if (info_out) *info_out = info;
  return mesh;
}

TriangleMesh read_stl(const std::filesystem::path& path, StlReadInfo* info) {
  const std::string source = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(source + ": no such file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(source + ": cannot read the file size: " + ec.message());
  if (size > kMaxFileBytes) throw InputError(fmt::format("{}: {} bytes is larger than the 2 GiB limit", source, size));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(source + ": cannot open the file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) throw InputError(source + ": could not read the whole file");
  return parse_stl(bytes, source, info);
}

void write_stl_ascii(const TriangleMesh& mesh, const std::filesystem::path& path, const std::string& name) {
  auto out = fmt::output_file(path.string());
  out.print("solid {}\n", name);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = triangle_vector_area(mesh, static_cast<int>(t)).normalized();
    out.print("  facet normal {:.17g} {:.17g} {:.17g}\n    outer loop\n", n.x(), n.y(), n.z());
    for (int v : mesh.triangles[t]) {
      const Eigen::Vector3d& p = mesh.vertices[v];
      out.print("      vertex {:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
    }
    out.print("    endloop\n  endfacet\n");
  }
  out.print("endsolid {}\n", name);
}

void write_stl_binary(const TriangleMesh& mesh, const std::filesystem::path& path) {
  std::string bytes(kBinaryPreambleBytes + kBinaryFacetBytes * mesh.triangles.size(), '\0');
  const char header[] = "binary STL written by settle";
  std::memcpy(bytes.data(), header, sizeof(header) - 1);
  auto put_u32 = [&](std::size_t offset, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>((v >> (8 * i)) & 0xFFu);
  };
  auto put_f32 = [&](std::size_t offset, double v) {
    put_u32(offset, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
  };
  put_u32(kBinaryHeaderBytes, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::size_t base = kBinaryPreambleBytes + kBinaryFacetBytes * t;
    const Eigen::Vector3d n = triangle_vector_area(mesh, static_cast<int>(t)).normalized();
    for (int i = 0; i < 3; ++i) put_f32(base + 4 * i, n(i));
    for (int v = 0; v < 3; ++v) {
      for (int i = 0; i < 3; ++i) put_f32(base + 12 + 12 * v + 4 * i, mesh.vertices[mesh.triangles[t][v]](i));
    }
  }
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw InputError(path.string() + ": cannot write the file");
}

}  // namespace settle::body
