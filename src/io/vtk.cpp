#include "io/vtk.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>

#include "body/cube_sphere.hpp"
#include "body/mesh_shape.hpp"
#include "common/error.hpp"

namespace settle::io {
namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "VTK files declare either little- or big-endian byte order");
constexpr const char* kByteOrder = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

// ---------------------------------------------------------------------------------------------
// Atomic files: written to "<path>.tmp" and renamed over <path> on commit(). Rename within one
// directory is atomic on POSIX file systems; an uncommitted temporary is removed.

class AtomicFile {
 public:
  explicit AtomicFile(fs::path path) : path_(std::move(path)), temporary_(path_) {
    temporary_ += ".tmp";
    out_.open(temporary_, std::ios::binary | std::ios::trunc);
    if (!out_) throw InputError(fmt::format("{}: cannot write (cannot create {})", path_.string(), temporary_.string()));
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (committed_) return;
    out_.close();
    std::error_code ignored;
    fs::remove(temporary_, ignored);
  }

  std::ostream& stream() { return out_; }

  void commit() {
    out_.flush();
    const bool written = static_cast<bool>(out_);
    out_.close();
    if (!written || out_.fail()) throw InputError(fmt::format("{}: cannot write (write failed)", path_.string()));
    std::error_code error;
    fs::rename(temporary_, path_, error);
    if (error) throw InputError(fmt::format("{}: cannot write ({})", path_.string(), error.message()));
    committed_ = true;
  }

 private:
  fs::path path_;
  fs::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

// ---------------------------------------------------------------------------------------------
// Appended raw data: each array is a UInt64 byte count followed by its values.

enum class ValueType { float32, float64, int64 };

std::size_t value_size(ValueType type) { return type == ValueType::float32 ? 4 : 8; }

const char* vtk_type_name(ValueType type) {
  switch (type) {
    case ValueType::float32: return "Float32";
    case ValueType::float64: return "Float64";
    case ValueType::int64: return "Int64";
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
      case ValueType::float32: append(static_cast<float>(value)); break;
      case ValueType::float64: append(value); break;
      case ValueType::int64: append(static_cast<std::int64_t>(value)); break;
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

/// Offsets of the arrays in the appended block, counted from the byte after its '_'.
std::vector<std::uint64_t> appended_offsets(const std::vector<const AppendedArray*>& arrays) {
  std::vector<std::uint64_t> offsets;
  std::uint64_t offset = 0;
  for (const AppendedArray* array : arrays) {
    offsets.push_back(offset);
    offset += sizeof(std::uint64_t) + array->byte_count();
  }
  return offsets;
}

std::string xml_escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      case '\'': escaped += "&apos;"; break;
      default: escaped += c;
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

// The shortest text that reads back as the same double.
std::string number(double value) { return fmt::format("{}", value); }

std::string triple(const Eigen::Vector3d& v) { return fmt::format("{} {} {}", number(v(0)), number(v(1)), number(v(2))); }

std::string data_array_tag(const AppendedArray& array, std::uint64_t offset, bool field_data) {
  std::string tag = fmt::format(R"(<DataArray type="{}" Name="{}")", vtk_type_name(array.type), xml_escaped(array.name));
  if (array.components != 1) tag += fmt::format(R"( NumberOfComponents="{}")", array.components);
  if (field_data) tag += fmt::format(R"( NumberOfTuples="{}")", array.tuples);
  tag += fmt::format(R"( format="appended" offset="{}"/>)", offset);
  return tag;
}

/// The XML of one file, with the DataArray tags of `arrays` placed by the caller through
/// tag(); then the appended data in the same order.
class VtkFileWriter {
 public:
  explicit VtkFileWriter(std::vector<const AppendedArray*> arrays)
      : arrays_(std::move(arrays)), offsets_(appended_offsets(arrays_)) {}

  std::string tag(const AppendedArray& array, bool field_data = false) const {
    for (std::size_t i = 0; i < arrays_.size(); ++i)
      if (arrays_[i] == &array) return data_array_tag(array, offsets_[i], field_data);
    throw std::logic_error("VtkFileWriter: array not registered: " + array.name);
  }

  /// Writes `xml` (everything up to the dataset's closing tag) and the appended block.
  void write(const fs::path& path, const std::string& xml) const {
    AtomicFile file(path);
    std::ostream& out = file.stream();
    out << xml << "  <AppendedData encoding=\"raw\">\n   _";
    for (const AppendedArray* array : arrays_) write_block(out, *array);
    out << "\n  </AppendedData>\n</VTKFile>\n";
    file.commit();
  }

 private:
  static void write_block(std::ostream& out, const AppendedArray& array) {
    const std::uint64_t bytes = array.byte_count();
    out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    ValueStream values(out, array.type);
    array.emit(values);
    values.flush();
    const std::size_t expected = array.tuples * static_cast<std::size_t>(array.components);
    if (values.values_written() != expected)
      throw std::logic_error(fmt::format("VTK array {}: wrote {} values, declared {}", array.name,
                                         values.values_written(), expected));
  }

  std::vector<const AppendedArray*> arrays_;
  std::vector<std::uint64_t> offsets_;
};

std::string file_header(const char* type) {
  return fmt::format("<?xml version=\"1.0\"?>\n<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\">\n",
                     type, kByteOrder);
}

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
      throw std::invalid_argument(fmt::format("write_fluid_vti: field {} has {} values for {} cells", field.name,
                                              field.values.size(), cells));
  }
}

// ---------------------------------------------------------------------------------------------
// Surface triangulation

/// The point where the ray from the centroid along `direction` leaves the body, by bisection
/// on the exact inside test (assumes the body is star-shaped about the centroid).
Eigen::Vector3d ray_exit(const body::Shape& shape, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  const double radius = shape.bounding_radius();
  double inside = 0.0;
  // A little beyond the bounding radius is outside by its definition.
  double outside = radius * (1.0 + 1e-6);
  if (shape.contains(outside * d)) throw std::logic_error("surface_triangulation: bounding radius is too small");
  // 1e-13 of the radius: far below anything a grid resolves, and some 500 ulp above the
  // round-off of the inside tests of bodies of size ~1.
  while (outside - inside > 1e-13 * radius) {
    const double middle = 0.5 * (inside + outside);
    (shape.contains(middle * d) ? inside : outside) = middle;
  }
  return 0.5 * (inside + outside) * d;
}

// Cube-sphere grid sizes: 1.6 h / max_edge cells per axis to start with (cube_sphere.cpp), which
// refinement raises by at most about pi/2 (the equiangular grid's largest stretch).
constexpr double kMaxTriangles = 1.0e7;

void check_triangle_budget(const Eigen::Vector3d& half_extents, double max_edge) {
  const Eigen::Vector3d cells = 1.6 * 1.6 * half_extents / max_edge + Eigen::Vector3d::Constant(2.0);
  const double triangles = 4.0 * (cells(0) * cells(1) + cells(1) * cells(2) + cells(2) * cells(0));
  if (triangles > kMaxTriangles)
    throw std::invalid_argument(fmt::format(
        "surface_triangulation: max_edge {} would need about {:.3g} triangles (limit {:.0g})", max_edge, triangles,
        kMaxTriangles));
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

void write_fluid_vti(const fs::path& path, const lbm::Solver& fluid, const FieldScaling& scaling,
                     const VtkOptions& options, std::span<const ScalarPointField> extra) {
  const std::size_t cells = fluid.cell_count();
  check_extra_fields(extra, cells);

  std::vector<AppendedArray> point_data;
  point_data.push_back(vector_array("velocity", options.precision, cells, [&fluid] { return fluid.velocity_field(); },
                                    scaling.velocity_scale_si()));
  point_data.push_back(scalar_array("pressure", options.precision, cells, [&fluid] { return fluid.pressure_field(); },
                                    scaling.pressure_scale_si()));
  point_data.push_back(vector_array("vorticity", options.precision, cells, [&fluid] { return fluid.vorticity_field(); },
                                    scaling.rate_scale_si()));
  for (const ScalarPointField& field : extra)
    point_data.push_back({field.name, float_type(options.precision), 1, cells, [&field](ValueStream& s) {
                            for (const double value : field.values) s.put(value);
                          }});

  const std::optional<AppendedArray> time = time_array(options);
  std::vector<const AppendedArray*> order;
  if (time) order.push_back(&*time);
  for (const AppendedArray& array : point_data) order.push_back(&array);
  const VtkFileWriter writer(order);

  const std::string extent = fmt::format("0 {} 0 {} 0 {}", fluid.nx() - 1, fluid.ny() - 1, fluid.nz() - 1);
  // Points at the cell centres: cell (0, 0, 0) is centred half a cell inside the window's corner.
  const Eigen::Vector3d origin_si = scaling.window_origin_si + Eigen::Vector3d::Constant(0.5 * scaling.dx_si);
  std::string xml = file_header("ImageData");
  xml += fmt::format("  <ImageData WholeExtent=\"{}\" Origin=\"{}\" Spacing=\"{}\">\n", extent, triple(origin_si),
                     triple(Eigen::Vector3d::Constant(scaling.dx_si)));
  xml += field_data_xml(writer, time);
  xml += fmt::format("    <Piece Extent=\"{}\">\n", extent);
  xml += "      <PointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  for (const AppendedArray& array : point_data) xml += "        " + writer.tag(array) + "\n";
  xml += "      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n  </ImageData>\n";
  writer.write(path, xml);
}

std::vector<double> solid_fraction_field(const lbm::Solver& fluid, const coupling::SolidCells& cells) {
  std::vector<double> alpha(fluid.cell_count(), 0.0);
  const std::array<int, 3> n{fluid.nx(), fluid.ny(), fluid.nz()};
  const auto& boundaries = fluid.config().boundaries;
  for (std::size_t c = 0; c < cells.cell.size(); ++c) {
    std::array<int, 3> ijk = cells.cell[c];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      if (boundaries[a] == lbm::Boundary::periodic) ijk[a] = ((ijk[a] % n[a]) + n[a]) % n[a];
      inside = inside && ijk[a] >= 0 && ijk[a] < n[a];
    }
    if (inside) alpha[fluid.linear_index(ijk[0], ijk[1], ijk[2])] = cells.alpha[c];
  }
  return alpha;
}

body::TriangleMesh surface_triangulation(const body::Shape& shape, double max_edge) {
  if (const auto* mesh = dynamic_cast<const body::MeshShape*>(&shape)) return mesh->body_mesh();
  if (!std::isfinite(max_edge) || max_edge <= 0.0)
    throw std::invalid_argument(fmt::format("surface_triangulation: max_edge must be finite and > 0, got {}", max_edge));
  const body::Aabb box = shape.bounding_box();
  const Eigen::Vector3d half_extents = box.lower.cwiseAbs().cwiseMax(box.upper.cwiseAbs());
  check_triangle_budget(half_extents, max_edge);
  if (!shape.contains(Eigen::Vector3d::Zero()))
    throw std::logic_error("surface_triangulation: the centroid of a " + shape.kind() + " lies outside it");
  return body::cube_sphere_mesh_with_max_edge(half_extents, max_edge, [&](const Eigen::Vector3d& u) {
    return ray_exit(shape, half_extents.cwiseProduct(u));
  });
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
  const VtkFileWriter writer(order);

  std::string xml = file_header("PolyData");
  xml += "  <PolyData>\n";
  xml += field_data_xml(writer, time);
  xml += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"{}\">\n",
      point_count, triangle_count);
  xml += "      <PointData Vectors=\"velocity\">\n        " + writer.tag(velocity) + "\n      </PointData>\n";
  xml += "      <CellData>\n      </CellData>\n";
  xml += "      <Points>\n        " + writer.tag(points) + "\n      </Points>\n";
  xml += "      <Polys>\n        " + writer.tag(connectivity) + "\n        " + writer.tag(offsets) + "\n      </Polys>\n";
  xml += "    </Piece>\n  </PolyData>\n";
  writer.write(path, xml);
}

// -----------------------------------------------------------------------------------------------
// PvdCollection

PvdCollection::PvdCollection(fs::path pvd_path) : path_(std::move(pvd_path)) {}

PvdCollection PvdCollection::resume(fs::path pvd_path, double keep_until_time_si) {
  PvdCollection collection(std::move(pvd_path));
  const fs::path& path = collection.path_;
  if (!fs::exists(path)) return collection;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  const std::string content = text.str();
  if (content.find("<VTKFile type=\"Collection\"") == std::string::npos)
    throw InputError(fmt::format("{}: not a ParaView data collection (.pvd)", path.string()));

  // Entries as rewrite() writes them: one DataSet element per line, timestep first, file last.
  static const std::regex dataset(R"re(<DataSet timestep="([^"]*)"[^>]*\sfile="([^"]*)"\s*/>)re");
  std::size_t dropped = 0;
  for (auto it = std::sregex_iterator(content.begin(), content.end(), dataset); it != std::sregex_iterator(); ++it) {
    const std::string time_text = (*it)[1].str();
    char* end = nullptr;
    const double time_si = std::strtod(time_text.c_str(), &end);
    if (time_text.empty() || *end != '\0' || !std::isfinite(time_si))
      throw InputError(fmt::format("{}: bad timestep \"{}\"", path.string(), time_text));
    if (time_si > keep_until_time_si) {
      ++dropped;
      continue;
    }
    if (!collection.entries_.empty() && time_si <= collection.entries_.back().time_si)
      throw InputError(fmt::format("{}: timesteps do not increase at {}", path.string(), time_text));
    collection.entries_.push_back({time_si, xml_unescaped((*it)[2].str())});
  }
  if (dropped > 0) collection.rewrite();
  return collection;
}

void PvdCollection::add(double time_si, const fs::path& file) {
  if (!std::isfinite(time_si)) throw std::invalid_argument(fmt::format("PvdCollection::add: time {} is not finite", time_si));
  if (!entries_.empty() && time_si <= entries_.back().time_si)
    throw std::invalid_argument(fmt::format("PvdCollection::add: time {} does not follow the last entry's {}", time_si,
                                            entries_.back().time_si));
  const fs::path directory = fs::absolute(path_).lexically_normal().parent_path();
  const fs::path absolute_file = fs::absolute(file).lexically_normal();
  fs::path relative = absolute_file.lexically_relative(directory);
  if (relative.empty()) relative = absolute_file;  // no relative route (e.g. another drive root)
  entries_.push_back({time_si, relative.generic_string()});
  try {
    rewrite();
  } catch (...) {
    entries_.pop_back();  // the collection stays as the file on disk
    throw;
  }
}

void PvdCollection::rewrite() const {
  AtomicFile file(path_);
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"" << kByteOrder
      << "\">\n  <Collection>\n";
  for (const Entry& entry : entries_)
    out << fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", number(entry.time_si),
                       xml_escaped(entry.file));
  out << "  </Collection>\n</VTKFile>\n";
  file.commit();
}

}  // namespace settle::io
