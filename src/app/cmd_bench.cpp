// `settle bench`: throughput of the fluid kernel on a periodic box, or of a case's coupled step
// (`--case`), reported against this machine's memory bandwidth measured in the same run
// (docs/architecture.md, "Contracts"; docs/lbm.md; docs/performance.md).
#include <omp.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/bench_rounds.hpp"
#include "app/commands.hpp"
#include "app/flag_values.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "io/case.hpp"
#include "io/preflight.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"
#include "parallel/lattice_steps.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  std::string lattice = "D3Q19";
  std::string collision = "trt";
  std::string subgrid = "none";
  double smagorinsky_constant = lbm::kDefaultSmagorinskyConstant;
  std::string precision = lbm::to_string(lbm::kDefaultPrecision);
  int size = 256;
  std::string case_file;               ///< --case: time this case's coupled step instead
  bool default_case = false;           ///< --default-case: the case `settle run` runs without a file
  std::vector<std::string> overrides;  ///< --set, with --case
  int steps = 40;
  int threads = 0;  // 0: OpenMP's default
  int rounds = 5;
  double probe_gib = 1.0;
};

bool coupled(const BenchOptions& o) { return o.default_case || !o.case_file.empty(); }
std::string case_name(const BenchOptions& o) { return o.default_case ? "default" : o.case_file; }

void check(const BenchOptions& o) {
  if (o.size < 8 || o.size > 2048) throw InputError(fmt::format("--size: must be in [8, 2048], got {}", o.size));
  if (o.steps < 2) throw InputError(fmt::format("--steps: must be >= 2, got {}", o.steps));
  if (o.rounds < 1 || o.rounds > 100) throw InputError(fmt::format("--rounds: must be in [1, 100], got {}", o.rounds));
  check_thread_count(o.threads, "--threads");
  if (!(o.probe_gib >= 0.0625 && o.probe_gib <= 64.0))
    throw InputError(fmt::format("--probe-gib: must be in [0.0625, 64], got {}", o.probe_gib));
  if (!o.overrides.empty() && !coupled(o))
    throw InputError("--set: applies to a case, give --case CASE.toml or --default-case");
}

// Under mpirun each rank holds one block of the box (lbm::choose_split, as a case's lattice).
lbm::SolverConfig kernel_config(const BenchOptions& o, parallel::Communicator& world) {
  lbm::SolverConfig c;
  c.lattice = lbm::parse_lattice(o.lattice, "--lattice");
  c.collision = lbm::parse_collision(o.collision, "--collision");
  c.subgrid = lbm::parse_subgrid_model(o.subgrid, "--subgrid");
  if (c.subgrid == lbm::SubgridModel::automatic)
    throw InputError("--subgrid: none or smagorinsky (auto chooses from a case's cell Reynolds number; give --case)");
  c.smagorinsky_constant = o.smagorinsky_constant;
  c.precision = lbm::parse_precision(o.precision, "--precision");
  c.nx = c.ny = c.nz = o.size;
  if (world.size() > 1) {
    c.split = lbm::choose_split({o.size, o.size, o.size}, world.size(), world.rank());
    const std::array<int, 3> block = c.split->extent(world.rank());
    c.nx = block[0], c.ny = block[1], c.nz = block[2];
  }
  c.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  c.tau = 0.6;
  c.body_force = Eigen::Vector3d(1e-7, 0.0, 0.0);
  return c;
}

// A smooth shear flow and a block of per-cell forces, so that the kernel works on realistic
// numbers (no denormals, no all-zero shortcuts) with the force array in use.
void prepare(lbm::Solver& solver) {
  const int n = solver.nx();
  const double k = 2.0 * M_PI / n;
  solver.initialise([&](int x, int y, int z) {
    lbm::CellState s;
    s.velocity = Eigen::Vector3d(0.02 * std::sin(k * y), 0.02 * std::sin(k * z), 0.02 * std::sin(k * x));
    return s;
  });
  const int lo = n / 4, hi = n / 4 + std::max(2, n / 8);
  for (int z = lo; z < hi; ++z)
    for (int y = lo; y < hi; ++y)
      for (int x = lo; x < hi; ++x) solver.add_force(x, y, z, Eigen::Vector3d(1e-6, -1e-6, 2e-6));
}

double mlups(double cells, double steps, double seconds) { return cells * steps / seconds * 1e-6; }
double gbs(double mlups, double bytes_per_cell_update) { return mlups * 1e6 * bytes_per_cell_update * 1e-9; }

// Whole even/odd pairs, so that both AA kernels count equally.
int even_steps(int steps) { return steps + (steps % 2); }

// Under mpirun (docs/parallel.md, "Speed"): what each rank measured, per step of the timed rounds.
struct RankFigures {
  double block_cells = 0.0;
  double seconds_per_step = 0.0;
  double roofline_fraction = 0.0;
  parallel::Traffic in_rounds;  ///< the communicator's counts within the timed rounds

  /// Starts a round: the ranks first wait for each other (their bandwidth probes take different
  /// times), so that no rank's exchanges count another's probe as waiting.
  void start_round(parallel::Communicator& world) {
    world.gather_all({});
    round_start_ = world.traffic();
  }
  void end_round(const parallel::Communicator& world) {
    const parallel::Traffic& now = world.traffic();
    in_rounds.exchange_bytes_sent += now.exchange_bytes_sent - round_start_.exchange_bytes_sent;
    in_rounds.exchange_messages_sent += now.exchange_messages_sent - round_start_.exchange_messages_sent;
    in_rounds.exchange_seconds += now.exchange_seconds - round_start_.exchange_seconds;
    in_rounds.collective_bytes_sent += now.collective_bytes_sent - round_start_.collective_bytes_sent;
    in_rounds.collective_seconds += now.collective_seconds - round_start_.collective_seconds;
  }

 private:
  parallel::Traffic round_start_;
};

// One row per rank, in rank order, on rank 0 (empty elsewhere): its block, MLUPS, fraction of its
// bandwidth probes, and its messages: the ghost traffic and the time in the exchanges (waiting
// for the slowest neighbour included) and in the collectives.
nlohmann::json rank_rows(parallel::Communicator& world, const RankFigures& f, int timed_steps) {
  const double steps = timed_steps;
  const std::vector<double> mine{
      f.block_cells,
      f.seconds_per_step,
      f.roofline_fraction,
      static_cast<double>(f.in_rounds.exchange_bytes_sent) / steps,
      static_cast<double>(f.in_rounds.exchange_messages_sent) / steps,
      f.in_rounds.exchange_seconds / steps,
      f.in_rounds.collective_seconds / steps,
      static_cast<double>(f.in_rounds.collective_bytes_sent) / steps,
  };
  nlohmann::json rows = nlohmann::json::array();
  for (const std::vector<double>& r : world.gather_to_root(mine))
    rows.push_back({{"block_cells", r[0]},
                    {"mlups", r[0] / r[1] * 1e-6},
                    {"roofline_fraction", r[2]},
                    {"ghost_bytes_sent_per_step", r[3]},
                    {"messages_sent_per_step", r[4]},
                    {"exchange_seconds_per_step", r[5]},
                    {"exchange_share", r[5] / r[1]},
                    {"collective_seconds_per_step", r[6]},
                    {"collective_share", r[6] / r[1]},
                    {"collective_bytes_sent_per_step", r[7]}});
  return rows;
}

void add_ranks(nlohmann::json& j, parallel::Communicator& world, const lbm::Solver& block, const RankFigures& f,
               int timed_steps) {
  nlohmann::json rows = rank_rows(world, f, timed_steps);
  if (world.size() == 1) return;
  j["processes"] = world.size();
  j["split_blocks"] = block.config().split->blocks;
  j["ranks"] = std::move(rows);
}

nlohmann::json run_kernel_bench(const BenchOptions& o) {
  parallel::Communicator& world = parallel::world();
  const bool lead = world.rank() == 0;
  const lbm::SolverConfig config = kernel_config(o, world);
  if (lead)
    fmt::print(stderr, "settle bench: {} {}{} {} on {}^3, {} rounds of {} steps and a bandwidth probe, {} threads{}\n",
               o.lattice, o.collision, o.subgrid == "none" ? "" : " + " + o.subgrid, o.precision, o.size, o.rounds,
               o.steps, omp_get_max_threads(),
               world.size() > 1 ? fmt::format(" on each of {} processes", world.size()) : "");
  auto solver = lbm::make_solver(config);
  prepare(*solver);
  const auto step = [&] { parallel::step(*solver, world); };
  for (int s = 0; s < 2; ++s) step();  // one step of each AA parity faults the pages in and warms the caches
  const int steps = even_steps(o.steps);
  const double whole_cells = std::pow(static_cast<double>(o.size), 3);
  const double cells = static_cast<double>(solver->cell_count());
  RankFigures figures;
  figures.block_cells = cells;
  const double bytes = static_cast<double>(solver->bytes_per_cell_update());
  // The two AA kernels are timed apart as well: the even step touches only each cell's own
  // slots, the odd step its neighbours' (lbm/aa_kernel.hpp), so their difference is the cost of
  // the neighbour access pattern.
  std::vector<double> round_seconds, round_mlups, parity_mlups[2];
  const BracketedRounds bracket = run_bracketed_rounds(
      o.rounds, o.probe_gib,
      [&](int) {
        std::array<double, 2> parity_seconds{};
        figures.start_round(world);
        const double start = omp_get_wtime();
        for (int s = 0; s < steps; ++s) {
          const auto parity = static_cast<std::size_t>(solver->step_count() & 1);
          const double step_start = omp_get_wtime();
          step();
          parity_seconds[parity] += omp_get_wtime() - step_start;
        }
        round_seconds.push_back(omp_get_wtime() - start);
        figures.end_round(world);
        round_mlups.push_back(mlups(cells, steps, round_seconds.back()));
        for (std::size_t p = 0; p < 2; ++p) parity_mlups[p].push_back(mlups(cells, steps / 2, parity_seconds[p]));
        return RoundResult{gbs(round_mlups.back(), bytes),
                           fmt::format("{:.1f} MLUPS (even steps {:.1f}, odd {:.1f})", round_mlups.back(),
                                       parity_mlups[0].back(), parity_mlups[1].back())};
      },
      lead);
  const double seconds = median(round_seconds);
  figures.seconds_per_step = seconds / steps;
  figures.roofline_fraction = median(bracket.steady_fraction.empty() ? bracket.fraction : bracket.steady_fraction);

  nlohmann::json j;
  j["lattice"] = lbm::to_string(config.lattice);
  j["collision"] = lbm::to_string(config.collision);
  j["subgrid_model"] = lbm::to_string(config.subgrid);
  j["precision"] = o.precision;
  j["size"] = o.size;
  j["cells"] = whole_cells;
  j["steps"] = steps;
  j["threads"] = omp_get_max_threads();
  j["seconds"] = seconds;
  j["mlups"] = mlups(whole_cells, steps, seconds);
  j["bytes_per_cell_update"] = solver->bytes_per_cell_update();
  j["achieved_gbs"] = gbs(j["mlups"].get<double>(), bytes);
  j["rounds"] = o.rounds;
  j["mlups_per_round"] = round_mlups;
  j["even_step_mlups"] = median(parity_mlups[0]);
  j["odd_step_mlups"] = median(parity_mlups[1]);
  add_roofline(j, bracket, o.probe_gib);  // the median of the bracketed fractions, not achieved / median bandwidth
  add_ranks(j, world, *solver, figures, steps * o.rounds);
  return j;
}

// The case as `settle run` would build it, checked by the same preflight (nothing is written).
coupling::SimulationSetup case_setup(const BenchOptions& o) {
  const fs::path path = o.case_file;
  const io::CaseValues values = io::load_case(path, o.overrides);
  const fs::path base = o.default_case ? fs::current_path() : fs::absolute(path).parent_path();
  coupling::SimulationSetup setup =
      io::simulation_setup(values, base, o.default_case ? "default" : path.stem().string());
  io::preflight(setup, io::PreflightOptions{});
  return setup;
}

std::map<std::string, double> timer_seconds(const coupling::SubstepTimers& timers) {
  std::map<std::string, double> seconds;
  for (const auto& [name, total] : timers.entries()) seconds[name] = total;
  return seconds;
}

void step_or_refuse(coupling::Simulation& sim, const BenchOptions& o) {
  if (!sim.can_step())
    throw InputError(
        fmt::format("--steps: the body reached the edge of the grid after {} steps of {}; bench fewer steps",
                    sim.steps(), case_name(o)));
  sim.step();
}

// The sub-steps in step order with their seconds per step and their share of the rounds' wall time;
// what the timers do not cover (the loop, the timers themselves) is `outside_substeps`.
nlohmann::json substep_shares(const coupling::SubstepTimers& timers, const std::map<std::string, double>& before,
                              double wall_seconds, int steps) {
  nlohmann::json list = nlohmann::json::array();
  double timed = 0.0;
  for (const auto& [name, total] : timers.entries()) {
    const auto earlier = before.find(name);
    const double seconds = total - (earlier == before.end() ? 0.0 : earlier->second);
    timed += seconds;
    list.push_back({{"name", name}, {"seconds_per_step", seconds / steps}, {"share", seconds / wall_seconds}});
  }
  list.push_back({{"name", "outside_substeps"},
                  {"seconds_per_step", (wall_seconds - timed) / steps},
                  {"share", (wall_seconds - timed) / wall_seconds}});
  return list;
}

nlohmann::json run_case_bench(const BenchOptions& o) {
  parallel::Communicator& world = parallel::world();
  const bool lead = world.rank() == 0;
  coupling::Simulation sim(case_setup(o), world);
  const auto& cells = sim.derived().cells;
  const double cell_count = static_cast<double>(sim.fluid().cell_count());  // this rank's block
  const double whole_cells = sim.lattice_cell_count();
  const double bytes = static_cast<double>(sim.fluid().bytes_per_cell_update());
  const int steps = even_steps(o.steps);
  if (lead)
    fmt::print(stderr,
               "settle bench --case {}: {}x{}x{} cells, {}, {} rounds of {} coupled steps and a bandwidth probe, {} "
               "threads{}\n",
               case_name(o), cells[0], cells[1], cells[2], coupling::to_string(sim.setup().coupling), o.rounds, steps,
               omp_get_max_threads(), world.size() > 1 ? fmt::format(" on each of {} processes", world.size()) : "");
  for (int s = 0; s < 2; ++s) step_or_refuse(sim, o);  // faults the pages in, starts the wake
  const std::map<std::string, double> before = timer_seconds(sim.timers());
  RankFigures figures;
  figures.block_cells = cell_count;
  std::vector<double> round_seconds, round_mlups;
  double wall_seconds = 0.0;
  const BracketedRounds bracket = run_bracketed_rounds(
      o.rounds, o.probe_gib,
      [&](int) {
        const double fluid_before = timer_seconds(sim.timers())["fluid"];
        figures.start_round(world);
        const double start = omp_get_wtime();
        for (int s = 0; s < steps; ++s) step_or_refuse(sim, o);
        round_seconds.push_back(omp_get_wtime() - start);
        figures.end_round(world);
        wall_seconds += round_seconds.back();
        round_mlups.push_back(mlups(whole_cells, steps, round_seconds.back()));
        const double fluid_mlups = mlups(cell_count, steps, timer_seconds(sim.timers())["fluid"] - fluid_before);
        return RoundResult{gbs(fluid_mlups, bytes),
                           fmt::format("{:.1f} MLUPS coupled, fluid sub-step {:.1f}", round_mlups.back(), fluid_mlups)};
      },
      lead);
  const int timed_steps = steps * o.rounds;
  const double fluid_seconds = timer_seconds(sim.timers())["fluid"] - before.at("fluid");
  figures.seconds_per_step = median(round_seconds) / steps;
  figures.roofline_fraction = median(bracket.steady_fraction.empty() ? bracket.fraction : bracket.steady_fraction);

  nlohmann::json j;
  j["case"] = case_name(o);
  j["overrides"] = o.overrides;
  j["cells"] = cells;
  j["cell_count"] = whole_cells;
  j["coupling"] = coupling::to_string(sim.setup().coupling);
  j["lattice"] = lbm::to_string(sim.setup().lattice);
  j["collision"] = lbm::to_string(sim.setup().collision);
  j["subgrid_model"] = lbm::to_string(sim.plan().subgrid_model);
  j["precision"] = lbm::to_string(sim.setup().precision);
  j["threads"] = omp_get_max_threads();
  j["steps"] = steps;
  j["rounds"] = o.rounds;
  j["seconds_per_step"] = median(round_seconds) / steps;
  j["mlups"] = mlups(whole_cells, steps, median(round_seconds));
  j["mlups_per_round"] = round_mlups;
  j["fluid_mlups"] = mlups(cell_count, timed_steps, fluid_seconds);
  j["non_fluid_share"] = 1.0 - fluid_seconds / wall_seconds;
  j["substeps"] = substep_shares(sim.timers(), before, wall_seconds, timed_steps);
  j["bytes_per_cell_update"] = sim.fluid().bytes_per_cell_update();
  j["fluid_achieved_gbs"] = gbs(j["fluid_mlups"].get<double>(), bytes);
  add_roofline(j, bracket, o.probe_gib);  // of the fluid sub-step
  add_ranks(j, world, sim.fluid(), figures, timed_steps);
  return j;
}

nlohmann::json run_bench(const BenchOptions& o) {
  check(o);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  return coupled(o) ? run_case_bench(o) : run_kernel_bench(o);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Fluid-kernel throughput (MLUPS) on a periodic N^3 box with the per-cell force array in use, or with --case "
      "the coupled step of a case (MLUPS, each sub-step's share); and the fraction of this machine's memory "
      "bandwidth the fluid kernel reaches (measured in the same run by an in-place read-modify-write probe). "
      "Prints JSON.");
  CLI::Option* case_option =
      cmd->add_option("--case", options->case_file, "time this case's coupled step (no output is written)");
  CLI::Option* default_case_flag = cmd->add_flag("--default-case", options->default_case,
                                                 "time the coupled step of the case `settle run` runs without a file")
                                       ->excludes(case_option);
  cmd->add_option("--set", options->overrides,
                  "with --case or --default-case: override a case key, e.g. --set numerics.cells_per_diameter=24");
  // The periodic box's own options: a case sets its grid and model itself.
  const auto box_only = [&](CLI::Option* option) {
    option->capture_default_str()->excludes(case_option)->excludes(default_case_flag);
  };
  box_only(cmd->add_option("--lattice", options->lattice, "D3Q19 or D3Q27"));
  box_only(cmd->add_option("--collision", options->collision, "bgk, trt, recursive_regularized or cumulant (D3Q27)"));
  box_only(cmd->add_option("--subgrid", options->subgrid, "subgrid model: none or smagorinsky"));
  box_only(cmd->add_option("--smagorinsky-constant", options->smagorinsky_constant,
                           "C_S of --subgrid smagorinsky (the per-cell work does not depend on it)"));
  box_only(cmd->add_option("--precision", options->precision, "storage precision: double or float"));
  box_only(cmd->add_option("--size", options->size, "cells per edge N of the periodic box"));
  cmd->add_option("--steps", options->steps, "timed steps per round (rounded up to even)")->capture_default_str();
  cmd->add_option("--threads", options->threads, "OpenMP threads (0: OMP_NUM_THREADS or all cores)")
      ->capture_default_str();
  cmd->add_option("--rounds", options->rounds,
                  "rounds, each between two bandwidth probes; the median of the per-round fractions is reported")
      ->capture_default_str();
  cmd->add_option("--probe-gib", options->probe_gib, "size of the bandwidth probe's array in GiB")
      ->capture_default_str();
  cmd->callback([options] {
    const nlohmann::json result = run_bench(*options);
    if (parallel::world().rank() == 0) fmt::print("{}\n", result.dump(2));
  });
}

}  // namespace settle::app
