#include "io/vtk_pieces.hpp"

#include <array>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/core.h>

#include "common/error.hpp"
#include "coupling/lattice_view.hpp"
#include "lbm/decomposition.hpp"
#include "parallel/communicator.hpp"

namespace settle::io {
namespace {

using Cell = std::array<int, 3>;

/// A box of whole-lattice cells (unwrapped), x fastest.
struct Box {
  Cell first{};
  Cell cells{};
  std::size_t count() const {
    return static_cast<std::size_t>(cells[0]) * static_cast<std::size_t>(cells[1]) * static_cast<std::size_t>(cells[2]);
  }
  std::size_t index(const Cell& c) const {
    return static_cast<std::size_t>(c[0] - first[0]) +
           static_cast<std::size_t>(cells[0]) *
               (static_cast<std::size_t>(c[1] - first[1]) + static_cast<std::size_t>(cells[1]) * (c[2] - first[2]));
  }
  template <class Visit>
  void each(Visit&& visit) const {
    for (int z = 0; z < cells[2]; ++z)
      for (int y = 0; y < cells[1]; ++y)
        for (int x = 0; x < cells[0]; ++x) visit(Cell{first[0] + x, first[1] + y, first[2] + z});
  }
};

/// Rank r's piece: its block, plus the next block's first layer along each axis that has one.
Box piece_of(const lbm::BlockSplit& split, int r) {
  Box box{split.offset(r), split.extent(r)};
  for (std::size_t a = 0; a < 3; ++a)
    if (box.first[a] + box.cells[a] < split.global[a]) ++box.cells[a];
  return box;
}

/// The cells whose velocities the piece's vorticity needs: one more on each side, except beyond a
/// face that is not periodic (where the one-process vorticity is one-sided too).
Box rim_of(const Box& piece, const lbm::BlockSplit& split, const std::array<lbm::Boundary, 3>& boundaries) {
  Box box = piece;
  for (std::size_t a = 0; a < 3; ++a) {
    const bool periodic = boundaries[a] == lbm::Boundary::periodic;
    const int lo = periodic ? box.first[a] - 1 : std::max(0, box.first[a] - 1);
    const int hi =
        periodic ? box.first[a] + box.cells[a] + 1 : std::min(split.global[a], box.first[a] + box.cells[a] + 1);
    box.first[a] = lo;
    box.cells[a] = hi - lo;
  }
  return box;
}

constexpr std::size_t kValues = 4;  // velocity and pressure of a cell

void append_cell(const lbm::Solver& block, const coupling::LatticeView& view, const Cell& wrapped,
                 const lbm::VectorField& u, const std::vector<double>& p, std::vector<double>& out) {
  const Cell l = view.to_block(wrapped);
  const std::size_t n = static_cast<std::size_t>(l[0]) +
                        static_cast<std::size_t>(block.nx()) *
                            (static_cast<std::size_t>(l[1]) + static_cast<std::size_t>(block.ny()) * l[2]);
  out.insert(out.end(), {u.x[n], u.y[n], u.z[n], p[n]});
}

}  // namespace

FluidPieceFields fluid_piece(const coupling::Simulation& sim) {
  const lbm::Solver& block = sim.fluid();
  const lbm::BlockSplit& split = *block.config().split;
  const std::array<lbm::Boundary, 3>& boundaries = block.config().boundaries;
  const coupling::LatticeView view(block);
  parallel::Communicator& ranks = sim.communicator();
  const int me = ranks.rank();
  const lbm::VectorField u = block.velocity_field();
  const std::vector<double> p = block.pressure_field();

  // Each adjacent rank gets the cells of its rim that lie in this block, in its rim's order.
  const std::vector<int> neighbours = split.adjacent_ranks();
  std::vector<std::vector<double>> send(neighbours.size()), receive;
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    rim_of(piece_of(split, neighbours[k]), split, boundaries).each([&](const Cell& c) {
      const auto w = view.wrap(c);
      if (w && view.owner(*w) == me) append_cell(block, view, *w, u, p, send[k]);
    });
  ranks.exchange(neighbours, send, receive);

  const Box piece = piece_of(split, me), rim = rim_of(piece, split, boundaries);
  lbm::VectorField rim_u{std::vector<double>(rim.count()), std::vector<double>(rim.count()),
                         std::vector<double>(rim.count())};
  std::vector<double> rim_p(rim.count());
  std::vector<std::size_t> read(neighbours.size(), 0);
  std::vector<double> mine;
  rim.each([&](const Cell& c) {
    const Cell w = *view.wrap(c);
    const int owner = view.owner(w);
    const std::vector<double>* values = &mine;
    std::size_t at = 0;
    if (owner == me) {
      mine.clear();
      append_cell(block, view, w, u, p, mine);
    } else {
      std::size_t k = 0;
      while (k < neighbours.size() && neighbours[k] != owner) ++k;
      if (k == neighbours.size())
        throw InputError(fmt::format(
            "run.vtk_interval: the VTK pieces need blocks at least 3 cells thick along every cut axis; this "
            "lattice of {}x{}x{} cells over {} processes has thinner ones: use fewer processes",
            split.global[0], split.global[1], split.global[2], split.block_count()));
      values = &receive[k];
      at = read[k];
      read[k] += kValues;
      if (read[k] > values->size()) throw std::logic_error("fluid_piece: a rank sent fewer cells than its rim holds");
    }
    const std::size_t n = rim.index(c);
    rim_u.x[n] = (*values)[at], rim_u.y[n] = (*values)[at + 1], rim_u.z[n] = (*values)[at + 2];
    rim_p[n] = (*values)[at + 3];
  });
  // Central differences inside the rim, one-sided at its faces; its faces lie beyond the piece
  // except at a face of the lattice that is not periodic, where one process is one-sided too.
  const std::array<lbm::Boundary, 3> open{lbm::Boundary::no_slip, lbm::Boundary::no_slip, lbm::Boundary::no_slip};
  const lbm::VectorField rim_vorticity = lbm::vorticity_of(rim_u, rim.cells, open);

  FluidPieceFields out;
  out.piece = {split.global, piece.first, piece.cells};
  out.fields.cells = piece.cells;
  const std::size_t count = piece.count();
  for (auto* field : {&out.fields.velocity, &out.fields.vorticity}) {
    field->x.reserve(count), field->y.reserve(count), field->z.reserve(count);
  }
  out.fields.pressure.reserve(count);
  piece.each([&](const Cell& c) {
    const std::size_t n = rim.index(c);
    out.fields.velocity.x.push_back(rim_u.x[n]), out.fields.velocity.y.push_back(rim_u.y[n]);
    out.fields.velocity.z.push_back(rim_u.z[n]);
    out.fields.pressure.push_back(rim_p[n]);
    out.fields.vorticity.x.push_back(rim_vorticity.x[n]), out.fields.vorticity.y.push_back(rim_vorticity.y[n]);
    out.fields.vorticity.z.push_back(rim_vorticity.z[n]);
  });
  // The body's solid fraction at the piece's points (cells on periodic axes wrap, as in one process).
  out.solid_fraction.assign(count, 0.0);
  const coupling::SolidCells solids = sim.current_solid_cells();
  for (std::size_t s = 0; s < solids.cell.size(); ++s) {
    const auto w = view.wrap(solids.cell[s]);
    if (!w) continue;
    bool inside = true;
    for (std::size_t a = 0; a < 3; ++a)
      inside = inside && (*w)[a] >= piece.first[a] && (*w)[a] < piece.first[a] + piece.cells[a];
    if (inside) out.solid_fraction[piece.index(*w)] = solids.alpha[s];
  }
  return out;
}

void write_fluid_pieces(const std::filesystem::path& pvti, const coupling::Simulation& sim, const FieldScaling& scaling,
                        const VtkOptions& options) {
  parallel::Communicator& ranks = sim.communicator();
  const std::string stem = pvti.stem().string();
  const auto piece_name = [&](int r) { return fmt::format("{}/piece_{:05d}.vti", stem, r); };
  const FluidPieceFields mine = fluid_piece(sim);
  std::string failure;
  try {
    const std::filesystem::path file = pvti.parent_path() / piece_name(ranks.rank());
    std::filesystem::create_directories(file.parent_path());
    const std::vector<ScalarPointField> extra{{"solid_fraction", mine.solid_fraction}};
    write_fluid_piece_vti(file, mine.fields, mine.piece, scaling, options, extra);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  if (const auto failed =
          parallel::first_failure(ranks, failure.empty() ? std::nullopt : std::optional<std::string>(failure))) {
    if (!failure.empty()) throw InputError(fmt::format("VTK output: {}", failure));
    throw InputError(fmt::format("VTK output: rank {} could not write its piece of {}: {}", failed->rank, pvti.string(),
                                 failed->message));
  }
  if (ranks.rank() != 0) return;
  const lbm::BlockSplit& split = *sim.fluid().config().split;
  std::vector<PieceFile> pieces;
  for (int r = 0; r < split.block_count(); ++r) {
    const Box box = piece_of(split, r);
    pieces.push_back({{split.global, box.first, box.cells}, piece_name(r)});
  }
  write_fluid_pvti(pvti, split.global, pieces, scaling, options, {"solid_fraction"});
}

}  // namespace settle::io
