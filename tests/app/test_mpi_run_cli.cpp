// `settle run` under mpirun (docs/parallel.md): the CI-sized free-settling sphere with the
// momentum exchange and the window following it, on 1, 2 and 4 processes (and with the immersed
// boundary on 2 and 4; oversubscribed: CI has 2 cores), writes the same time series as the plain
// run, byte for byte, and VTK pieces whose values are the plain run's. Exact equality is the right
// check: a split run adds every sum in the one-process order (tests/coupling/
// test_split_simulation.cpp), so a difference is a lost message or a reordered sum. A malformed
// case under mpirun is reported once, and every process exits with the input-error status. A run
// stopped under mpirun continues from its checkpoint parts under the same number of processes.
#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support/vtk_reader.hpp"

namespace test_mpi_run_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::run_settle;
using settle::test::scratch;
using settle::test::write_scratch_case;

// tests/app/test_free_settling_cli.cpp's sphere (Re ~ 16), at 6 cells per diameter, with the
// momentum exchange, in a window of 4 x 4 x 8 d (its physics is confined, but the check is bit-for-bit
// equality, for which any window serves; a 24 x 24 x 48 grid keeps the test short under the
// sanitizers), started at about its terminal speed so that the window shifts within the 0.015 s run
// (the sphere falls about 3 cells). The window holds it across z = 4 d, where 2 and 4 processes cut
// the grid (1 x 1 x 2 and 1 x 1 x 4 blocks), so that its cells and links lie in two blocks.
constexpr int kGridX = 24, kGridY = 24, kGridZ = 48;
const char* kSphereCase = R"toml(
[fluid]
density = 1000.0
dynamic_viscosity = 4.0e-3
gravity = [0.0, 0.0, -9.81]
[particle]
shape = "sphere"
diameter = 1.0e-3
density = 2000.0
position = [2.0e-3, 2.0e-3, 4.0e-3]
velocity = [0.0, 0.0, -0.03]
[domain]
size = [4.0e-3, 4.0e-3, 8.0e-3]
walls = { x = "free-slip", y = "free-slip", z = "no-slip" }
follow_particle = true
[numerics]
cells_per_diameter = 6
coupling = "momentum_exchange"
[run]
end_time = 0.015
output_interval = 0
vtk_interval = 0.005
)toml";

// mpirun as CTest found it; leak detection off under the sanitizers (Open MPI's start-up
// allocations, as for tests/parallel/); a session directory of this test process's own (see
// tests/app/CMakeLists.txt).
std::string launcher(int ranks, const std::string& options = "") {
  const std::string sessions = std::string(SETTLE_MPI_SESSIONS) + "/" + std::to_string(::getpid());
  return std::string("ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 ") + SETTLE_MPIEXEC +
         " --oversubscribe --allow-run-as-root --mca orte_tmpdir_base " + sessions + " " + options + "-n " +
         std::to_string(ranks) + " ";
}

// When a rank exits with an error status (143 after a signal), mpirun stops the others: SIGTERM,
// then SIGKILL odls_base_sigkill_timeout seconds later (1 by default), which on a loaded machine
// came before rank 0 had written its part and its message. 3 s (docs/checkpoints.md advises more
// for large grids); mpirun also waits that long before it returns.
const std::string kPatientMpirun = "--mca odls_base_sigkill_timeout 3 ";

/// Every array of the pieces that `pvti` lists equals, value for value (as stored: the same bits),
/// the one-process file `whole` at the piece's points. Returns the points compared.
std::size_t expect_pieces_match(const fs::path& pvti, const fs::path& whole) {
  namespace vtk = settle::test::vtk_reader;
  const vtk::ParsedVtk one = vtk::parse_vtk(whole);
  std::istringstream whole_extent(vtk::element_attributes(one.xml, "ImageData").at("WholeExtent"));
  std::array<int, 6> w{};
  for (int& v : w) whole_extent >> v;
  const std::string index = vtk::read_bytes(pvti);
  const std::string grid_extent = fmt::format("0 {} 0 {} 0 {}", kGridX - 1, kGridY - 1, kGridZ - 1);
  EXPECT_NE(vtk::element_attributes(index, "PImageData").at("WholeExtent").find(grid_extent), std::string::npos);
  static const std::regex piece_tag(R"re(<Piece Extent="([^"]*)" Source="([^"]*)"/>)re");
  std::size_t compared = 0;
  for (auto it = std::sregex_iterator(index.begin(), index.end(), piece_tag); it != std::sregex_iterator(); ++it) {
    std::istringstream extent((*it)[1].str());
    std::array<int, 6> e{};
    for (int& v : e) extent >> v;
    const vtk::ParsedVtk piece = vtk::parse_vtk(pvti.parent_path() / (*it)[2].str());
    for (const vtk::ParsedArray& array : piece.arrays) {
      if (array.section != "PointData") continue;
      const vtk::ParsedArray& reference = one.array(array.name);
      const std::size_t value_bytes = vtk::type_size(array.type) * static_cast<std::size_t>(array.components);
      std::size_t k = 0, differing = 0;
      for (int z = e[4]; z <= e[5]; ++z)
        for (int y = e[2]; y <= e[3]; ++y)
          for (int x = e[0]; x <= e[1]; ++x, ++k) {
            const std::size_t g = static_cast<std::size_t>(x) +
                                  static_cast<std::size_t>(w[1] + 1) *
                                      (static_cast<std::size_t>(y) + static_cast<std::size_t>(w[3] + 1) * z);
            if (array.bytes.compare(k * value_bytes, value_bytes, reference.bytes, g * value_bytes, value_bytes) != 0)
              ++differing;
          }
      EXPECT_EQ(differing, 0u) << array.name << " in " << (*it)[2].str();
      EXPECT_EQ(k * value_bytes, array.bytes.size()) << array.name;
      compared += k;
    }
  }
  return compared;
}

/// Runs `case_text` plainly and under mpirun with each of `process_counts`: the same time series
/// and surface files, byte for byte, and fluid pieces holding the one-process file's values.
void expect_mpi_runs_as_plain(const std::string& name, const std::string& case_text,
                              const std::vector<int>& process_counts) {
  const fs::path case_path = write_scratch_case(name, case_text);
  const fs::path plain = scratch(name + "_plain");
  const auto reference = run_settle("run", case_path.string() + " -o " + plain.string() + " --threads 1 --quiet");
  ASSERT_EQ(reference.status, 0) << reference.err;
  const std::string series = read_text(plain / "timeseries.csv");
  ASSERT_GT(std::count(series.begin(), series.end(), '\n'), 100);  // every step of 0.015 s
  for (const int ranks : process_counts) {
    SCOPED_TRACE(std::to_string(ranks) + " processes");
    const fs::path dir = scratch(name + "_n" + std::to_string(ranks));
    const char* binary = std::getenv("SETTLE_BINARY");
    ASSERT_NE(binary, nullptr);
    const std::string command = launcher(ranks) + binary + " run " + case_path.string() + " -o " + dir.string() +
                                " --threads 1 --quiet > " + scratch("mpi_out").string() + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << read_text(scratch("mpi_out"));
    EXPECT_EQ(read_text(dir / "timeseries.csv"), series);
    if (ranks == 1) {  // a run of one process writes the plain run's files
      for (const auto& entry : fs::directory_iterator(plain / "vtk"))
        EXPECT_EQ(read_text(dir / "vtk" / entry.path().filename()), read_text(entry.path())) << entry.path().filename();
      fs::remove_all(dir);
      continue;
    }
    // The surface as one process writes it; the fluid as a piece per rank whose values are the
    // one-process file's at the piece's points (four arrays, the grid's points with the shared
    // layers of the pieces counted twice).
    for (int k = 0; k < 4; ++k) {
      const std::string index = fmt::format("{:06d}", k);
      const std::string surface = "surface_" + index + ".vtp";
      EXPECT_EQ(read_text(dir / "vtk" / surface), read_text(plain / "vtk" / surface)) << surface;
      const std::size_t points =
          expect_pieces_match(dir / "vtk" / ("fluid_" + index + ".pvti"), plain / "vtk" / ("fluid_" + index + ".vti"));
      EXPECT_EQ(points, std::size_t{4} * kGridX * kGridY * (kGridZ + ranks - 1)) << index;
    }
    EXPECT_EQ(read_text(dir / "vtk" / "surface.pvd"), read_text(plain / "vtk" / "surface.pvd"));
    std::string fluid_pvd = read_text(plain / "vtk" / "fluid.pvd");
    for (std::size_t at = fluid_pvd.find(".vti\""); at != std::string::npos; at = fluid_pvd.find(".vti\"", at))
      fluid_pvd.replace(at, 5, ".pvti\"");
    EXPECT_EQ(read_text(dir / "vtk" / "fluid.pvd"), fluid_pvd);
    EXPECT_TRUE(fs::exists(dir / "summary.json"));
    fs::remove_all(dir);
  }
  fs::remove_all(plain);
  fs::remove(case_path);
  fs::remove(scratch("mpi_out"));
}

TEST(MpiRun, OneTwoAndFourProcessesWriteThePlainRunsTimeSeries) {
  expect_mpi_runs_as_plain("mpi_sphere", kSphereCase, {1, 2, 4});
}

// The same sphere with the immersed boundary (the other coupling): its markers' stencils and its
// volume fractions straddle the blocks of 2 and 4 processes.
TEST(MpiRun, TheImmersedBoundaryOnTwoAndFourProcessesWritesThePlainRunsTimeSeries) {
  std::string text = kSphereCase;
  text.replace(text.find("coupling = \"momentum_exchange\""), 30, "coupling = \"immersed_boundary\"");
  expect_mpi_runs_as_plain("mpi_sphere_ibm", text, {2, 4});
}

/// Rows of a timeseries.csv whose time is past `t` (the first column).
int rows_after(const fs::path& csv, double t) {
  std::istringstream text(read_text(csv));
  std::string line;
  std::getline(text, line);  // header
  int rows = 0;
  while (std::getline(text, line))
    if (!text.eof() && std::stod(line.substr(0, line.find(','))) > t) ++rows;
  return rows;
}

// The process among mpirun's children on this machine (from /proc) that Open MPI made rank
// `rank` (OMPI_COMM_WORLD_RANK in its environment); 0 if none.
pid_t rank_process(pid_t mpirun, int rank) {
  const std::string wanted = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    // The fields after the command (which may hold spaces and ends at the last ')'): state, ppid.
    const std::string stat = read_text(entry.path() / "stat");
    std::istringstream rest(stat.substr(stat.rfind(')') + 1));
    std::string state;
    long ppid = 0;
    if (!(rest >> state >> ppid) || ppid != mpirun) continue;
    std::istringstream environment(read_text(entry.path() / "environ"));
    for (std::string variable; std::getline(environment, variable, '\0');)
      if (variable == wanted) return std::stoi(name);
  }
  return 0;
}

// Launches `command` (mpirun -n 2) through sh with its stderr in `out` and, once the first
// checkpoint (t = 0.002 s) is written and the run has gone past it, sends SIGTERM to rank 1 alone:
// the hardest case of a signal that reaches the ranks after different steps (rank 0, which
// reports, never sees it). mpirun itself passes a signal on to every rank, but it shares the two
// cores with its busy ranks and did so half a second late, after the small run had ended. Returns
// whether the signal landed mid-run and the launcher's wait status. A poll starved on a loaded
// machine can still see the run only after its end; the caller then tries again.
struct StopAttempt {
  bool stopped_mid_run = false;
  int wait_status = 0;
};

StopAttempt stop_after_first_checkpoint(const std::string& command, const fs::path& dir, const fs::path& out) {
  const pid_t launcher_pid = ::fork();
  if (launcher_pid < 0) return {};
  if (launcher_pid == 0) {
    if (!std::freopen(out.c_str(), "w", stderr) || !std::freopen("/dev/null", "w", stdout)) ::_exit(127);
    ::execl("/bin/sh", "sh", "-c", ("exec env " + command).c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  StopAttempt attempt;
  bool ended = false;
  for (int poll = 0; poll < 30000 && !attempt.stopped_mid_run && !ended; ++poll) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    attempt.stopped_mid_run = fs::exists(dir / "checkpoint.bin") && rows_after(dir / "timeseries.csv", 0.0021) > 2;
    ended = ::waitpid(launcher_pid, &attempt.wait_status, WNOHANG) == launcher_pid;
  }
  if (ended) return {false, attempt.wait_status};
  const pid_t rank_1 = rank_process(launcher_pid, 1);
  if (rank_1 > 0) ::kill(rank_1, SIGTERM);
  ::waitpid(launcher_pid, &attempt.wait_status, 0);
  // The signal may have come after the last step (the run wrote its summary and never heard of it);
  // a summary beside the interruption message is a defect the caller's checks report.
  const bool ended_first =
      fs::exists(dir / "summary.json") && read_text(out).find("run interrupted") == std::string::npos;
  attempt.stopped_mid_run = attempt.stopped_mid_run && !ended_first;
  return attempt;
}

// SIGTERM to rank 1 of two: the processes agree to stop after the same step, each writes its part
// of the checkpoint and rank 0 the manifest and the message, naming the signal it never received
// (docs/checkpoints.md, "Across processes"). Continued under the same number of processes the run
// ends as the plain run did, byte for byte (the restart is exact, as in one process); under another
// number it is refused before anything is written. The run is twice as long as the others and
// checkpoints early (t = 0.002 s), so that the signal, sent straight to the rank, lands mid-run.
TEST(MpiRun, AStoppedRunContinuesUnderTheSameNumberOfProcesses) {
  std::string text = kSphereCase;
  text.replace(text.find("end_time = 0.015"), 16, "end_time = 0.03");
  const fs::path case_path = write_scratch_case("mpi_restart_sphere", text);
  const fs::path plain = scratch("mpi_restart_plain");
  ASSERT_EQ(run_settle("run", case_path.string() + " -o " + plain.string() + " --threads 1 --quiet").status, 0);
  const char* binary = std::getenv("SETTLE_BINARY");
  ASSERT_NE(binary, nullptr);
  const fs::path dir = scratch("mpi_restart");
  const fs::path out = scratch("mpi_restart_out");
  const std::string command = launcher(2, kPatientMpirun) + binary + " run " + case_path.string() + " -o " +
                              dir.string() + " --threads 1 --quiet --set run.checkpoint_interval=0.002";
  StopAttempt attempt;
  for (int tries = 0; tries < 3 && !attempt.stopped_mid_run; ++tries) {
    fs::remove_all(dir);
    attempt = stop_after_first_checkpoint(command, dir, out);
  }
  const int raw = attempt.wait_status;
  ASSERT_TRUE(attempt.stopped_mid_run) << "three runs ended before they could be stopped after their first checkpoint\n"
                                       << read_text(out);
  // mpirun ends with its own status (1 with Open MPI) once a process returned 143; rank 0 alone says why.
  EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) != 0) << raw;
  const std::string said = read_text(out);
  const auto first = said.find("settle: run interrupted by SIGTERM");
  EXPECT_NE(first, std::string::npos) << said;
  EXPECT_EQ(said.find("settle: run interrupted", first + 1), std::string::npos) << "reported twice:\n" << said;
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  int step_folders = 0;
  for (const auto& step : fs::directory_iterator(dir / "checkpoint.bin.parts")) {
    EXPECT_TRUE(fs::exists(step.path() / "rank-00000.bin") && fs::exists(step.path() / "rank-00001.bin"));
    ++step_folders;
  }
  EXPECT_EQ(step_folders, 1);  // the parts of earlier checkpoints are gone

  const auto alone = run_settle("run", "--restart " + dir.string());
  EXPECT_EQ(alone.status, 2);
  EXPECT_NE(alone.err.find("written by 2 processes, this run has 1; continue it with mpirun -n 2"), std::string::npos)
      << alone.err;
  const std::string restart =
      launcher(2) + binary + " run --restart " + dir.string() + " --quiet > " + out.string() + " 2>&1";
  ASSERT_EQ(std::system(restart.c_str()), 0) << read_text(out);
  EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(plain / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  fs::remove_all(dir);
  fs::remove_all(plain);
  fs::remove(case_path);
  fs::remove(out);
}

// A restart under mpirun whose rank 1 cannot use its part: a byte flipped in it, then the part
// deleted. Rank 0 reports, and its message used to be only "rank 1 failed: reading its part of the
// checkpoint under ..."; it now carries rank 1's reason, as the one-process restart gives it.
TEST(MpiRun, ARanksFailedPartIsReportedWithItsReason) {
  std::string text = kSphereCase;
  text.replace(text.find("vtk_interval = 0.005"), 20, "checkpoint_interval = 0.015");
  const fs::path case_path = write_scratch_case("mpi_bad_part", text);
  const char* binary = std::getenv("SETTLE_BINARY");
  ASSERT_NE(binary, nullptr);
  const fs::path dir = scratch("mpi_bad_part");
  const fs::path out = scratch("mpi_bad_part_out");
  fs::remove_all(dir);
  const std::string run = launcher(2) + binary + " run " + case_path.string() + " -o " + dir.string() +
                          " --threads 1 --quiet > " + out.string() + " 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << read_text(out);
  fs::path part;
  for (const auto& step : fs::directory_iterator(dir / "checkpoint.bin.parts")) part = step.path() / "rank-00001.bin";
  ASSERT_TRUE(fs::exists(part));
  const std::string restart = launcher(2) + binary + " run --restart " + dir.string() +
                              " --set run.end_time=0.03 --quiet > " + out.string() + " 2>&1";
  {
    std::fstream file(part, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(fs::file_size(part) / 2));
    file.put('\x5a');
  }
  EXPECT_NE(std::system(restart.c_str()), 0);
  std::string said = read_text(out);
  EXPECT_NE(said.find("rank 1 failed: reading its part"), std::string::npos) << said;
  EXPECT_NE(said.find("rank-00001.bin: section 'fluid/populations' fails its CRC-32 check"), std::string::npos) << said;
  fs::remove(part);
  EXPECT_NE(std::system(restart.c_str()), 0);
  said = read_text(out);
  EXPECT_NE(said.find("rank 1 failed: reading its part"), std::string::npos) << said;
  EXPECT_NE(said.find("rank-00001.bin: cannot open the checkpoint: No such file or directory"), std::string::npos)
      << said;
  fs::remove_all(dir);
  fs::remove(case_path);
  fs::remove(out);
}

// `settle bench` under mpirun (docs/parallel.md, "Speed"): each rank benches its block and rank 0
// prints one JSON with a row per rank. The ghost traffic is counted by the communicator, so it is
// checked against its closed form: a 16^3 periodic box cut in two along z (1 x 1 x 2: the two
// blocks share two faces, one through the periodic wrap) sends, per step, the 5 populations of
// D3Q19 that cross a face for each of the 16 x 16 cells of each face, as doubles: 2 x 5 x 256 x 8
// = 20480 bytes, in one message to the one neighbour.
TEST(MpiRun, BenchReportsEachRanksBlockAndItsGhostTraffic) {
  const char* binary = std::getenv("SETTLE_BINARY");
  ASSERT_NE(binary, nullptr);
  const fs::path out = scratch("mpi_bench_out"), err = scratch("mpi_bench_err");
  const std::string command = launcher(2) + binary +
                              " bench --size 16 --steps 4 --rounds 1 --probe-gib 0.0625 --threads 1 > " + out.string() +
                              " 2> " + err.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(err);
  const nlohmann::json j = nlohmann::json::parse(read_text(out));  // one document: rank 0 alone prints
  EXPECT_EQ(j.at("processes"), 2);
  EXPECT_EQ(j.at("split_blocks"), nlohmann::json::array({1, 1, 2}));
  EXPECT_EQ(j.at("cells").get<double>(), 4096.0);
  ASSERT_EQ(j.at("ranks").size(), 2u);
  for (const auto& rank : j.at("ranks")) {
    EXPECT_EQ(rank.at("block_cells").get<double>(), 2048.0);
    EXPECT_EQ(rank.at("ghost_bytes_sent_per_step").get<double>(), 20480.0);
    EXPECT_EQ(rank.at("messages_sent_per_step").get<double>(), 1.0);
    EXPECT_GT(rank.at("mlups").get<double>(), 0.0);
    EXPECT_GE(rank.at("exchange_share").get<double>(), 0.0);
    EXPECT_LE(rank.at("exchange_share").get<double>(), 1.0);
  }
  fs::remove(out);
  fs::remove(err);
}

TEST(MpiRun, AMalformedCaseIsReportedOnceAndEveryProcessFails) {
  std::string text = kSphereCase;
  text.replace(text.find("cells_per_diameter = 6"), 22, "cells_per_diameter = -6");
  const fs::path case_path = write_scratch_case("mpi_bad", text);
  const char* binary = std::getenv("SETTLE_BINARY");
  ASSERT_NE(binary, nullptr);
  const fs::path out = scratch("mpi_bad_out");
  const std::string command = launcher(2) + binary + " run " + case_path.string() + " -o " +
                              scratch("mpi_bad_dir").string() + " > " + out.string() + " 2>&1";
  const int raw = std::system(command.c_str());
  EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 2) << raw;
  const std::string err = read_text(out);
  const auto first = err.find("cells_per_diameter = -6.0: must be in");
  ASSERT_NE(first, std::string::npos) << err;
  EXPECT_EQ(err.find("settle: error", err.find("settle: error") + 1), std::string::npos) << "reported twice:\n" << err;
  EXPECT_FALSE(fs::exists(scratch("mpi_bad_dir")));
  fs::remove(case_path);
  fs::remove(out);
}

}  // namespace test_mpi_run_cli
