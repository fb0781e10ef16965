#include "io/vtk.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include <fmt/core.h>
#include <zlib.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "io/vtk_xml.hpp"

namespace settle::io {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Appended raw data: each array is a UInt64 byte count followed by its values.

enum class ValueType { float32, float64, int64 };

std::size_t value_size(ValueType type) { return type == ValueType::float32 ? 4 : 8; }

const char* vtk_type_name(ValueType type) {
  switch (type) {
    case ValueType::float32:
      return "Float32";
    case ValueType::float64:
      return "Float64";
    case ValueType::int64:
      return "Int64";
  }
  return "";
}

ValueType float_type(VtkPrecision precision) {
  return precision == VtkPrecision::float32 ? ValueType::float32 : ValueType::float64;
}

/// Converts values to the array's type and writes them through a buffer.
class ValueStream {
 public:
  ValueStream(std::ostream& out, ValueType type) : out_(out), type_(type), buffer_(kBufferBytes) {}

  void put(double value) {
    switch (type_) {
      case ValueType::float32:
        append(static_cast<float>(value));
        break;
      case ValueType::float64:
        append(value);
        break;
      case ValueType::int64:
        append(static_cast<std::int64_t>(value));
        break;
    }
  }
  void put_index(std::int64_t value) {
    if (type_ != ValueType::int64) throw std::logic_error("ValueStream: an index written to a floating-point array");
    append(value);
  }
  void put_vector(const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) put(v(a));
  }
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(used_));
    used_ = 0;
  }
  std::size_t values_written() const { return values_; }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  template <class T>
  void append(T value) {
    if (used_ + sizeof(T) > buffer_.size()) flush();
    std::memcpy(buffer_.data() + used_, &value, sizeof(T));
    used_ += sizeof(T);
    ++values_;
  }

  std::ostream& out_;
  ValueType type_;
  std::vector<char> buffer_;
  std::size_t used_ = 0;
  std::size_t values_ = 0;
};

/// One array of the appended block; `emit` writes exactly tuples x components values.
struct AppendedArray {
  std::string name;
  ValueType type = ValueType::float32;
  int components = 1;
  std::size_t tuples = 0;
  std::function<void(ValueStream&)> emit;

  std::uint64_t byte_count() const {
    return static_cast<std::uint64_t>(tuples) * static_cast<std::uint64_t>(components) * value_size(type);
  }
};

std::string triple(const Eigen::Vector3d& v) {
  return fmt::format("{} {} {}", vtk_number(v(0)), vtk_number(v(1)), vtk_number(v(2)));
}

std::string data_array_tag(const AppendedArray& array, std::uint64_t offset, bool field_data) {
  std::string tag =
      fmt::format(R"(<DataArray type="{}" Name="{}")", vtk_type_name(array.type), xml_escaped(array.name));
  if (array.components != 1) tag += fmt::format(R"( NumberOfComponents="{}")", array.components);
  if (field_data) tag += fmt::format(R"( NumberOfTuples="{}")", array.tuples);
  tag += fmt::format(R"( format="appended" offset="{}"/>)", offset);
  return tag;
}

/// Writes the array's values (in the machine's byte order) and checks their count.
void emit_values(std::ostream& out, const AppendedArray& array) {
  ValueStream values(out, array.type);
  array.emit(values);
  values.flush();
  const std::size_t expected = array.tuples * static_cast<std::size_t>(array.components);
  if (values.values_written() != expected)
    throw std::logic_error(
        fmt::format("VTK array {}: wrote {} values, declared {}", array.name, values.values_written(), expected));
}

std::string raw_bytes(const AppendedArray& array) {
  std::ostringstream out;
  emit_values(out, array);
  return std::move(out).str();
}

template <class T>
void append_bytes(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// VTK's default block size of compressed arrays (vtkDataCompressor).
constexpr std::size_t kCompressedBlockBytes = 32768;
/// zlib's fastest level: on float fields the higher levels shrink the files by a few per cent
/// more at several times the cost (docs/vtk.md).
constexpr int kZlibLevel = Z_BEST_SPEED;

/// The opening of a VTK XML file; `attributes` go on the VTKFile element.
std::string file_header(const char* type, std::string_view attributes = "") {
  return fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\"{}>\n",
      type, vtk_byte_order(), attributes);
}

/// The array as VTK's compressed block (vtk.hpp): header, then the deflated blocks.
std::string zlib_block(const std::string& raw) {
  const std::size_t blocks = (raw.size() + kCompressedBlockBytes - 1) / kCompressedBlockBytes;
  std::vector<std::string> deflated(blocks);
  // Blocks deflate independently, one thread each: deflate, not the disk, is the slow part of a
  // compressed snapshot (docs/vtk.md).
  bool failed = false;
#pragma omp parallel for schedule(static) reduction(|| : failed)
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t first = b * kCompressedBlockBytes;
    const std::size_t size = std::min(kCompressedBlockBytes, raw.size() - first);
    uLongf length = compressBound(static_cast<uLong>(size));
    deflated[b].resize(length);
    failed = failed || compress2(reinterpret_cast<Bytef*>(deflated[b].data()), &length,
                                 reinterpret_cast<const Bytef*>(raw.data() + first), static_cast<uLong>(size),
                                 kZlibLevel) != Z_OK;
    deflated[b].resize(length);
  }
  if (failed) throw std::runtime_error("zlib: compress2 failed on a VTK array block");
  std::string out;
  append_bytes(out, static_cast<std::uint64_t>(blocks));
  append_bytes(out, static_cast<std::uint64_t>(kCompressedBlockBytes));
  append_bytes(out, static_cast<std::uint64_t>(raw.size() % kCompressedBlockBytes));
  for (const std::string& block : deflated) append_bytes(out, static_cast<std::uint64_t>(block.size()));
  for (const std::string& block : deflated) out += block;
  return out;
}

/// The XML of one file, with the DataArray tags of `arrays` placed by the caller through
/// tag(); then the appended data in the same order. Raw arrays are streamed at write(); compressed
/// ones are encoded here, since their offsets in the tags depend on their compressed sizes.
class VtkFileWriter {
 public:
  VtkFileWriter(std::vector<const AppendedArray*> arrays, VtkCompression compression)
      : arrays_(std::move(arrays)), compression_(compression) {
    if (compression_ == VtkCompression::zlib)
      for (const AppendedArray* array : arrays_) encoded_.push_back(zlib_block(raw_bytes(*array)));
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < arrays_.size(); ++i) {
      offsets_.push_back(offset);
      offset +=
          compression_ == VtkCompression::zlib ? encoded_[i].size() : sizeof(std::uint64_t) + arrays_[i]->byte_count();
    }
  }

  std::string tag(const AppendedArray& array, bool field_data = false) const {
    for (std::size_t i = 0; i < arrays_.size(); ++i)
      if (arrays_[i] == &array) return data_array_tag(array, offsets_[i], field_data);
    throw std::logic_error("VtkFileWriter: array not registered: " + array.name);
  }

  /// The VTKFile element's opening line for a dataset of this type.
  std::string header(const char* type) const {
    return file_header(type, compression_ == VtkCompression::zlib ? R"( compressor="vtkZLibDataCompressor")" : "");
  }

  /// Writes `xml` (everything up to the dataset's closing tag) and the appended block.
  void write(const fs::path& path, const std::string& xml) const {
    AtomicFile file(path);
    std::ostream& out = file.stream();
    out << xml << "  <AppendedData encoding=\"raw\">\n   _";
    if (compression_ == VtkCompression::zlib)
      for (const std::string& block : encoded_) out.write(block.data(), static_cast<std::streamsize>(block.size()));
    else
      for (const AppendedArray* array : arrays_) write_raw_block(out, *array);
    out << "\n  </AppendedData>\n</VTKFile>\n";
    file.commit();
  }

 private:
  static void write_raw_block(std::ostream& out, const AppendedArray& array) {
    const std::uint64_t bytes = array.byte_count();
    out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    emit_values(out, array);
  }

  std::vector<const AppendedArray*> arrays_;
  VtkCompression compression_;
  std::vector<std::string> encoded_;  // zlib only
  std::vector<std::uint64_t> offsets_;
};

std::optional<AppendedArray> time_array(const VtkOptions& options) {
  if (!options.time_si) return std::nullopt;
  const double t = *options.time_si;
  return AppendedArray{"TimeValue", ValueType::float64, 1, 1, [t](ValueStream& s) { s.put(t); }};
}

std::string field_data_xml(const VtkFileWriter& writer, const std::optional<AppendedArray>& time) {
  if (!time) return {};
  return fmt::format("    <FieldData>\n      {}\n    </FieldData>\n", writer.tag(*time, true));
}

// ---------------------------------------------------------------------------------------------
// Fluid

AppendedArray vector_array(std::string name, VtkPrecision precision, std::size_t cells,
                           std::function<lbm::VectorField()> compute, double scale) {
  return {std::move(name), float_type(precision), 3, cells, [compute = std::move(compute), scale](ValueStream& s) {
            const lbm::VectorField field = compute();
            for (std::size_t n = 0; n < field.x.size(); ++n) {
              s.put(field.x[n] * scale);
              s.put(field.y[n] * scale);
              s.put(field.z[n] * scale);
            }
          }};
}

AppendedArray scalar_array(std::string name, VtkPrecision precision, std::size_t cells,
                           std::function<std::vector<double>()> compute, double scale) {
  return {std::move(name), float_type(precision), 1, cells, [compute = std::move(compute), scale](ValueStream& s) {
            for (const double value : compute()) s.put(value * scale);
          }};
}

void check_extra_fields(std::span<const ScalarPointField> extra, std::size_t cells) {
  std::set<std::string> names{"velocity", "pressure", "vorticity"};
  for (const ScalarPointField& field : extra) {
    if (field.name.empty()) throw std::invalid_argument("write_fluid_vti: an extra field has no name");
    if (!names.insert(field.name).second)
      throw std::invalid_argument("write_fluid_vti: field name used twice: " + field.name);
    if (field.values.size() != cells)
      throw std::invalid_argument(
          fmt::format("write_fluid_vti: field {} has {} values for {} cells", field.name, field.values.size(), cells));
  }
}

}  // namespace

// -----------------------------------------------------------------------------------------------

FieldScaling field_scaling(const coupling::UnitConverter& units, const Eigen::Vector3d& window_origin_si) {
  FieldScaling scaling;
  scaling.window_origin_si = window_origin_si;
  scaling.dx_si = units.dx_si();
  scaling.dt_si = units.dt_si();
  scaling.fluid_density_si = units.fluid_density_si();
  return scaling;
}

namespace {

std::string extent_text(const std::array<int, 3>& first, const std::array<int, 3>& count) {
  return fmt::format("{} {} {} {} {} {}", first[0], first[0] + count[0] - 1, first[1], first[1] + count[1] - 1,
                     first[2], first[2] + count[2] - 1);
}

// Points at the cell centres: cell (0, 0, 0) is centred half a cell inside the window's corner.
Eigen::Vector3d points_origin_si(const FieldScaling& scaling) {
  return scaling.window_origin_si + Eigen::Vector3d::Constant(0.5 * scaling.dx_si);
}

// The fluid's ImageData file from its point arrays (velocity, pressure, vorticity, extras), however
// they were obtained: the whole lattice, or one piece of it (points first .. first + cells - 1 of
// the whole lattice's `whole` points).
void write_fluid_image(const fs::path& path, const FluidPiece& piece, std::vector<AppendedArray> point_data,
                       const FieldScaling& scaling, const VtkOptions& options) {
  const std::optional<AppendedArray> time = time_array(options);
  std::vector<const AppendedArray*> order;
  if (time) order.push_back(&*time);
  for (const AppendedArray& array : point_data) order.push_back(&array);
  const VtkFileWriter writer(order, options.compression);

  const std::string whole = extent_text({0, 0, 0}, piece.whole);
  std::string xml = writer.header("ImageData");
  xml += fmt::format("  <ImageData WholeExtent=\"{}\" Origin=\"{}\" Spacing=\"{}\">\n", whole,
                     triple(points_origin_si(scaling)), triple(Eigen::Vector3d::Constant(scaling.dx_si)));
  xml += field_data_xml(writer, time);
  xml += fmt::format("    <Piece Extent=\"{}\">\n", extent_text(piece.first, piece.cells));
  xml += "      <PointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  for (const AppendedArray& array : point_data) xml += "        " + writer.tag(array) + "\n";
  xml += "      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n  </ImageData>\n";
  writer.write(path, xml);
}

void add_extra_fields(std::vector<AppendedArray>& point_data, std::span<const ScalarPointField> extra,
                      const VtkOptions& options, std::size_t cells) {
  for (const ScalarPointField& field : extra)
    point_data.push_back({field.name, float_type(options.precision), 1, cells, [&field](ValueStream& s) {
                            for (const double value : field.values) s.put(value);
                          }});
}

}  // namespace

void write_fluid_vti(const fs::path& path, const lbm::Solver& fluid, const FieldScaling& scaling,
                     const VtkOptions& options, std::span<const ScalarPointField> extra) {
  const std::size_t cells = fluid.cell_count();
  check_extra_fields(extra, cells);
  std::vector<AppendedArray> point_data;
  point_data.push_back(vector_array(
      "velocity", options.precision, cells, [&fluid] { return fluid.velocity_field(); }, scaling.velocity_scale_si()));
  point_data.push_back(scalar_array(
      "pressure", options.precision, cells, [&fluid] { return fluid.pressure_field(); }, scaling.pressure_scale_si()));
  point_data.push_back(vector_array(
      "vorticity", options.precision, cells, [&fluid] { return fluid.vorticity_field(); }, scaling.rate_scale_si()));
  add_extra_fields(point_data, extra, options, cells);
  const std::array<int, 3> n{fluid.nx(), fluid.ny(), fluid.nz()};
  write_fluid_image(path, {n, {0, 0, 0}, n}, std::move(point_data), scaling, options);
}

void write_fluid_vti(const fs::path& path, const FluidFieldArrays& fields, const FieldScaling& scaling,
                     const VtkOptions& options, std::span<const ScalarPointField> extra) {
  write_fluid_piece_vti(path, fields, {fields.cells, {0, 0, 0}, fields.cells}, scaling, options, extra);
}

void write_fluid_piece_vti(const fs::path& path, const FluidFieldArrays& fields, const FluidPiece& piece,
                           const FieldScaling& scaling, const VtkOptions& options,
                           std::span<const ScalarPointField> extra) {
  if (fields.cells != piece.cells) throw std::invalid_argument("write_fluid_piece_vti: the fields are not the piece's");
  const std::size_t cells = static_cast<std::size_t>(fields.cells[0]) * static_cast<std::size_t>(fields.cells[1]) *
                            static_cast<std::size_t>(fields.cells[2]);
  if (fields.velocity.x.size() != cells || fields.pressure.size() != cells || fields.vorticity.x.size() != cells) {
    throw std::invalid_argument("write_fluid_vti: the fields do not hold one value per cell");
  }
  check_extra_fields(extra, cells);
  std::vector<AppendedArray> point_data;
  point_data.push_back(vector_array(
      "velocity", options.precision, cells, [&fields] { return fields.velocity; }, scaling.velocity_scale_si()));
  point_data.push_back(scalar_array(
      "pressure", options.precision, cells, [&fields] { return fields.pressure; }, scaling.pressure_scale_si()));
  point_data.push_back(vector_array(
      "vorticity", options.precision, cells, [&fields] { return fields.vorticity; }, scaling.rate_scale_si()));
  add_extra_fields(point_data, extra, options, cells);
  write_fluid_image(path, piece, std::move(point_data), scaling, options);
}

void write_fluid_pvti(const fs::path& path, const std::array<int, 3>& whole, const std::vector<PieceFile>& pieces,
                      const FieldScaling& scaling, const VtkOptions& options,
                      const std::vector<std::string>& extra_names) {
  const std::string type = vtk_type_name(float_type(options.precision));
  std::string xml = file_header("PImageData");
  xml += fmt::format("  <PImageData WholeExtent=\"{}\" GhostLevel=\"0\" Origin=\"{}\" Spacing=\"{}\">\n",
                     extent_text({0, 0, 0}, whole), triple(points_origin_si(scaling)),
                     triple(Eigen::Vector3d::Constant(scaling.dx_si)));
  xml += "    <PPointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  xml += fmt::format("      <PDataArray type=\"{}\" Name=\"velocity\" NumberOfComponents=\"3\"/>\n", type);
  xml += fmt::format("      <PDataArray type=\"{}\" Name=\"pressure\"/>\n", type);
  xml += fmt::format("      <PDataArray type=\"{}\" Name=\"vorticity\" NumberOfComponents=\"3\"/>\n", type);
  for (const std::string& name : extra_names)
    xml += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\"/>\n", type, xml_escaped(name));
  xml += "    </PPointData>\n";
  for (const PieceFile& piece : pieces)
    xml += fmt::format("    <Piece Extent=\"{}\" Source=\"{}\"/>\n", extent_text(piece.piece.first, piece.piece.cells),
                       xml_escaped(piece.source));
  xml += "  </PImageData>\n</VTKFile>\n";
  write_file_atomically(path, xml);
}

std::vector<double> solid_fraction_field(const lbm::Solver& fluid, const coupling::SolidCells& cells) {
  return solid_fraction_field({fluid.nx(), fluid.ny(), fluid.nz()}, fluid.config().boundaries, cells);
}

std::vector<double> solid_fraction_field(const std::array<int, 3>& n, const std::array<lbm::Boundary, 3>& boundaries,
                                         const coupling::SolidCells& cells) {
  std::vector<double> alpha(
      static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]), 0.0);
  for (std::size_t c = 0; c < cells.cell.size(); ++c) {
    std::array<int, 3> ijk = cells.cell[c];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      if (boundaries[a] == lbm::Boundary::periodic) ijk[a] = ((ijk[a] % n[a]) + n[a]) % n[a];
      inside = inside && ijk[a] >= 0 && ijk[a] < n[a];
    }
    if (inside) {
      alpha[static_cast<std::size_t>(ijk[0]) +
            static_cast<std::size_t>(n[0]) *
                (static_cast<std::size_t>(ijk[1]) + static_cast<std::size_t>(n[1]) * ijk[2])] = cells.alpha[c];
    }
  }
  return alpha;
}

BodySnapshot body_snapshot(const body::RigidBody& body) {
  BodySnapshot snapshot;
  snapshot.position_si = body.state().position_si;
  snapshot.body_to_inertial = body.body_to_inertial();
  snapshot.velocity_si = body.state().velocity_si;
  snapshot.angular_velocity_n_si = body.angular_velocity_n_si();
  return snapshot;
}

void write_surface_vtp(const fs::path& path, const body::TriangleMesh& surface_b, const BodySnapshot& body,
                       const VtkOptions& options) {
  const std::size_t point_count = surface_b.vertices.size();
  const std::size_t triangle_count = surface_b.triangles.size();
  for (const auto& triangle : surface_b.triangles)
    for (const int v : triangle)
      if (v < 0 || static_cast<std::size_t>(v) >= point_count)
        throw std::invalid_argument(fmt::format("write_surface_vtp: vertex index {} out of range", v));

  // Offsets of the surface points from the centroid, inertial frame.
  std::vector<Eigen::Vector3d> arm_n(point_count);
  for (std::size_t i = 0; i < point_count; ++i) arm_n[i] = body.body_to_inertial * surface_b.vertices[i];

  const AppendedArray points{"Points", ValueType::float64, 3, point_count, [&](ValueStream& s) {
                               for (const Eigen::Vector3d& arm : arm_n) s.put_vector(body.position_si + arm);
                             }};
  const AppendedArray velocity{"velocity", float_type(options.precision), 3, point_count, [&](ValueStream& s) {
                                 for (const Eigen::Vector3d& arm : arm_n)
                                   s.put_vector(body.velocity_si + body.angular_velocity_n_si.cross(arm));
                               }};
  const AppendedArray connectivity{"connectivity", ValueType::int64, 1, 3 * triangle_count, [&](ValueStream& s) {
                                     for (const auto& triangle : surface_b.triangles)
                                       for (const int v : triangle) s.put_index(v);
                                   }};
  const AppendedArray offsets{"offsets", ValueType::int64, 1, triangle_count, [&](ValueStream& s) {
                                for (std::size_t t = 1; t <= triangle_count; ++t)
                                  s.put_index(static_cast<std::int64_t>(3 * t));
                              }};
  const std::optional<AppendedArray> time = time_array(options);
  std::vector<const AppendedArray*> order;
  if (time) order.push_back(&*time);
  for (const AppendedArray* array : {&velocity, &points, &connectivity, &offsets}) order.push_back(array);
  const VtkFileWriter writer(order, options.compression);

  std::string xml = writer.header("PolyData");
  xml += "  <PolyData>\n";
  xml += field_data_xml(writer, time);
  xml += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"{}\">\n",
      point_count, triangle_count);
  xml += "      <PointData Vectors=\"velocity\">\n        " + writer.tag(velocity) + "\n      </PointData>\n";
  xml += "      <CellData>\n      </CellData>\n";
  xml += "      <Points>\n        " + writer.tag(points) + "\n      </Points>\n";
  xml +=
      "      <Polys>\n        " + writer.tag(connectivity) + "\n        " + writer.tag(offsets) + "\n      </Polys>\n";
  xml += "    </Piece>\n  </PolyData>\n";
  writer.write(path, xml);
}

}  // namespace settle::io
