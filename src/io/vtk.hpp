#pragma once
// VTK XML output for ParaView: the fluid on the grid as ImageData (.vti) and the particle's
// surface as PolyData (.vtp); ParaView data collections (.pvd) that list them in time are
// pvd.hpp, the surface's triangulation is body/surface_triangulation.hpp. Format: the XML file formats of the VTK documentation ("VTK File Formats",
// https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html; also in the VTK User's
// Guide, Kitware).
//
// Every file is self-contained XML with one block of binary "appended" data at the end, the
// values in the machine's byte order, which the header declares (byte_order="LittleEndian" on
// x86-64 and ARM). Raw (VtkCompression::none): each array is a UInt64 byte count followed by its
// values. Compressed (VtkCompression::zlib, compressor="vtkZLibDataCompressor", what ParaView
// writes itself): each array is cut into blocks of 32 KiB (VTK's default block size), each block
// deflated by zlib on its own, and preceded by the UInt64 header [blocks, block size, size of
// the last block if partial (0 if full), each block's compressed size].
//
// Units: SI throughout (m, s, m/s, Pa, 1/s). Frames: the inertial frame of the case (z up).
// Every file is written atomically and durably (common/atomic_file.hpp), so a reader or a run that
// stops never sees half a file. A file that cannot be written raises settle::InputError
// naming its path. The caller creates the output directory.
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "body/rigid_body.hpp"
#include "body/triangle_mesh.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/units.hpp"
#include "lbm/solver.hpp"

namespace settle::io {

/// Value type of the floating-point arrays in the file.
enum class VtkPrecision {
  float32,  ///< about 7 significant digits: plenty for looking at fields, half the size
  float64,
};

/// Encoding of the appended arrays (file comment).
enum class VtkCompression {
  none,  ///< raw bytes: fastest to write
  zlib,  ///< deflated blocks: smaller where the field is smooth or uniform; slower to write
};

struct VtkOptions {
  VtkPrecision precision = VtkPrecision::float32;
  /// Simulated time (s), written as the field-data array "TimeValue" that ParaView shows when the
  /// file is opened on its own (a .pvd carries the time anyway).
  std::optional<double> time_si;
  /// The writer's encoding when a caller asks for none; a run takes run.vtk_compression.
  VtkCompression compression = VtkCompression::none;
};

/// How the lattice fields map to SI, and where the grid sits. Lattice units: dx = dt = 1,
/// reference density 1 (lbm/config.hpp).
struct FieldScaling {
  /// SI position of the grid's lower corner: the corner of cell (0, 0, 0), which moves with the
  /// moving window (coupling::LatticeFrame::window_origin_si).
  Eigen::Vector3d window_origin_si = Eigen::Vector3d::Zero();
  double dx_si = 1.0;             ///< m
  double dt_si = 1.0;             ///< s
  double fluid_density_si = 1.0;  ///< kg/m^3, the reference density rho_0

  double velocity_scale_si() const { return dx_si / dt_si; }  ///< m/s per lattice velocity
  /// Pa per lattice pressure (lattice pressure is in units of rho_0 dx^2 / dt^2).
  double pressure_scale_si() const { return fluid_density_si * dx_si * dx_si / (dt_si * dt_si); }
  double rate_scale_si() const { return 1.0 / dt_si; }  ///< 1/s per lattice vorticity
};

/// The scaling of a run: its converter and the window's current origin.
FieldScaling field_scaling(const coupling::UnitConverter& units, const Eigen::Vector3d& window_origin_si);

/// An extra scalar written with the fluid: one SI value per cell, linear index x + nx (y + ny z).
struct ScalarPointField {
  std::string name;
  std::vector<double> values;
};

/// Writes the fluid as ImageData with one point per cell centre: Origin = window origin + dx/2,
/// Spacing = dx, WholeExtent 0..nx-1 etc. Point data (at the cell centres, so that ParaView's
/// contours and stream tracers apply directly):
///   "velocity"  (3 components, m/s; Guo's half-force correction included, lbm::Solver)
///   "pressure"  (Pa) p = c_s^2 (rho - rho_0) scaled to SI: the hydrodynamic pressure relative to
///               the reference. The lattice fluid carries no gravity, so there is no hydrostatic
///               part (coupling/simulation.hpp).
///   "vorticity" (3 components, 1/s) curl u by second-order central differences
///               (lbm::Solver::vorticity_field, one-sided at non-periodic faces)
/// followed by `extra` fields in the order given (each must hold cell_count() values and have a
/// name distinct from the others; std::invalid_argument otherwise). The fields are computed one
/// after another while the file is written, so the extra memory is that of the vorticity.
void write_fluid_vti(const std::filesystem::path& path, const lbm::Solver& fluid, const FieldScaling& scaling,
                     const VtkOptions& options = {}, std::span<const ScalarPointField> extra = {});

/// The fluid's fields as arrays (lattice units, linear index x + nx (y + ny z)): what the blocks of a
/// split run gather for one file.
struct FluidFieldArrays {
  std::array<int, 3> cells{};
  lbm::VectorField velocity;
  std::vector<double> pressure;
  lbm::VectorField vorticity;
};

/// The same file from arrays (write_fluid_vti above computes them from the solver).
void write_fluid_vti(const std::filesystem::path& path, const FluidFieldArrays& fields, const FieldScaling& scaling,
                     const VtkOptions& options = {}, std::span<const ScalarPointField> extra = {});

/// A piece of the whole lattice's points: `cells` points from `first` (whole-lattice point
/// indices) of the `whole` lattice's.
struct FluidPiece {
  std::array<int, 3> whole{};
  std::array<int, 3> first{};
  std::array<int, 3> cells{};
};

/// One piece of a parallel file (docs/vtk.md, "Across processes"): the fields of `piece` (fields.cells
/// equal to piece.cells) as an ImageData file whose WholeExtent is the whole lattice's and whose
/// Piece Extent is the piece's, the same arrays as write_fluid_vti.
void write_fluid_piece_vti(const std::filesystem::path& path, const FluidFieldArrays& fields, const FluidPiece& piece,
                           const FieldScaling& scaling, const VtkOptions& options = {},
                           std::span<const ScalarPointField> extra = {});

/// The parallel ImageData file (.pvti) that ParaView opens as the whole lattice: the arrays'
/// names and types and each piece's extent and file (`source`, relative to the .pvti's folder).
struct PieceFile {
  FluidPiece piece;
  std::string source;
};
void write_fluid_pvti(const std::filesystem::path& path, const std::array<int, 3>& whole,
                      const std::vector<PieceFile>& pieces, const FieldScaling& scaling, const VtkOptions& options,
                      const std::vector<std::string>& extra_names);

/// Solid volume fraction per cell (linear index of `fluid`), 0 outside the body, from the body's
/// solid cells (coupling::solid_cells). Cells on periodic axes wrap into the grid; cells outside
/// a non-periodic axis (none, for a body the coupling can step) are dropped.
std::vector<double> solid_fraction_field(const lbm::Solver& fluid, const coupling::SolidCells& cells);
/// The same on a lattice of extent n with these faces.
std::vector<double> solid_fraction_field(const std::array<int, 3>& n, const std::array<lbm::Boundary, 3>& boundaries,
                                         const coupling::SolidCells& cells);

/// Where the body is and how it moves (SI, inertial frame).
struct BodySnapshot {
  Eigen::Vector3d position_si = Eigen::Vector3d::Zero();            ///< centroid, m
  Eigen::Matrix3d body_to_inertial = Eigen::Matrix3d::Identity();   ///< C_b^n: body-frame vector to inertial
  Eigen::Vector3d velocity_si = Eigen::Vector3d::Zero();            ///< of the centroid, m/s
  Eigen::Vector3d angular_velocity_n_si = Eigen::Vector3d::Zero();  ///< inertial frame, rad/s
};

/// The snapshot of a rigid body's current state.
BodySnapshot body_snapshot(const body::RigidBody& body);

/// Writes the body-frame surface at the snapshot's pose as PolyData: points x = X_c + C_b^n p
/// (always Float64: a small particle far from the origin needs more than float32's 7 digits),
/// triangles as polygons (counterclockwise seen from outside), point data "velocity" (3
/// components, m/s), the rigid-body velocity v + omega x (x - X_c) of each surface point. No
/// normals are written: ParaView shades each triangle flat, which shows a cuboid's edges sharp;
/// its "Generate Surface Normals" filter gives smooth shading where wanted.
void write_surface_vtp(const std::filesystem::path& path, const body::TriangleMesh& surface_b, const BodySnapshot& body,
                       const VtkOptions& options = {});

}  // namespace settle::io
