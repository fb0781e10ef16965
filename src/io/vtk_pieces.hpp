#pragma once
// The fluid of a run across processes as parallel VTK pieces (docs/vtk.md, "Across processes"):
// each rank writes its block as one piece, rank 0 the .pvti that ParaView opens as the whole
// lattice. No rank holds more than its block and a two-cell rim.
#include <filesystem>
#include <string>

#include "coupling/simulation.hpp"
#include "io/vtk.hpp"

namespace settle::io {

/// This rank's piece: its block's points and, where another block follows along an axis, that
/// block's first layer too (pieces of point data share one layer, so that ParaView draws the cells
/// between them), with the fields the one-process file holds at those points: velocity, pressure,
/// vorticity (from the velocities of a one-cell rim, received from the adjacent blocks, so the
/// central differences at block faces are those of one process) and the solid fraction. Every rank
/// calls it (the rims are exchanged). settle::InputError when a block is too thin for its rim to
/// come from its adjacent blocks only (fewer than 3 cells along a cut axis).
struct FluidPieceFields {
  FluidPiece piece;
  FluidFieldArrays fields;
  std::vector<double> solid_fraction;
};
FluidPieceFields fluid_piece(const coupling::Simulation& sim);

/// Writes this rank's piece as `<stem>/piece_RRRRR.vti` beside `pvti` and, on rank 0, `pvti` itself,
/// once every rank's piece is written (a failure on any rank fails on every rank). Every rank
/// calls it.
void write_fluid_pieces(const std::filesystem::path& pvti, const coupling::Simulation& sim, const FieldScaling& scaling,
                        const VtkOptions& options);

}  // namespace settle::io
