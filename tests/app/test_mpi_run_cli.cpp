// `settle run` under mpirun (docs/parallel.md): the CI-sized free-settling sphere with the
// momentum exchange and the window following it, on 1, 2 and 4 processes (oversubscribed: CI has
// 2 cores), writes the same time series and VTK files as the plain run, byte for byte. Exact equality is the
// right check: a split run adds every sum in the one-process order (tests/coupling/
// test_split_simulation.cpp), so a difference is a lost message or a reordered sum. A malformed
// case under mpirun is reported once, and every process exits with the input-error status.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cli_support.hpp"

namespace test_mpi_run_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::run_settle;
using settle::test::scratch;
using settle::test::write_scratch_case;

// tests/app/test_free_settling_cli.cpp's sphere (Re ~ 16, 8 d wide window with 5 d ahead), at 6
// cells per diameter, with the momentum exchange, started at about its terminal speed so that the
// window shifts within the 0.03 s run (about 6 times: it falls 6.6 cells).
const char* kSphereCase = R"toml(
[fluid]
density = 1000.0
dynamic_viscosity = 4.0e-3
gravity = [0.0, 0.0, -9.81]
[particle]
shape = "sphere"
diameter = 1.0e-3
density = 2000.0
position = [4.0e-3, 4.0e-3, 6.0e-3]
velocity = [0.0, 0.0, -0.03]
[domain]
size = [8.0e-3, 8.0e-3, 16.0e-3]
walls = { x = "free-slip", y = "free-slip", z = "no-slip" }
follow_particle = true
[numerics]
cells_per_diameter = 6
coupling = "momentum_exchange"
[run]
end_time = 0.03
output_interval = 0
vtk_interval = 0.01
)toml";

// mpirun as CTest found it; leak detection off under the sanitizers (Open MPI's start-up
// allocations, as for tests/parallel/).
std::string launcher(int ranks) {
  return std::string("ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 ") + SETTLE_MPIEXEC +
         " --oversubscribe --allow-run-as-root -n " + std::to_string(ranks) + " ";
}

TEST(MpiRun, OneTwoAndFourProcessesWriteThePlainRunsTimeSeries) {
  const fs::path case_path = write_scratch_case("mpi_sphere", kSphereCase);
  const fs::path plain = scratch("mpi_plain");
  const auto reference = run_settle("run", case_path.string() + " -o " + plain.string() + " --threads 1 --quiet");
  ASSERT_EQ(reference.status, 0) << reference.err;
  const std::string series = read_text(plain / "timeseries.csv");
  ASSERT_GT(std::count(series.begin(), series.end(), '\n'), 200);  // every step of 0.03 s
  for (const int ranks : {1, 2, 4}) {
    SCOPED_TRACE(std::to_string(ranks) + " processes");
    const fs::path dir = scratch("mpi_n" + std::to_string(ranks));
    const char* binary = std::getenv("SETTLE_BINARY");
    ASSERT_NE(binary, nullptr);
    const std::string command = launcher(ranks) + binary + " run " + case_path.string() + " -o " + dir.string() +
                                " --threads 1 --quiet > " + scratch("mpi_out").string() + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << read_text(scratch("mpi_out"));
    EXPECT_EQ(read_text(dir / "timeseries.csv"), series);
    // The fields, gathered on rank 0, written as the one-process run writes them.
    int vtk_files = 0;
    for (const auto& entry : fs::directory_iterator(plain / "vtk")) {
      EXPECT_EQ(read_text(dir / "vtk" / entry.path().filename()), read_text(entry.path())) << entry.path().filename();
      ++vtk_files;
    }
    EXPECT_EQ(vtk_files, 10);  // fluid and surface at t = 0, 0.01, 0.02, 0.03 and their two .pvd
    EXPECT_TRUE(fs::exists(dir / "summary.json"));
    fs::remove_all(dir);
  }
  fs::remove_all(plain);
  fs::remove(case_path);
  fs::remove(scratch("mpi_out"));
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
