// Case tests of checkpoints in `settle run` and of `settle run --restart DIR` (docs/checkpoints.md):
// the real binary (SETTLE_BINARY) on the default case, coarsened to 6 cells per diameter (36 x 36 x
// 72 cells, 89 steps of 0.34 ms to t = 0.03 s, about a second on one thread).
//  - A run killed with SIGKILL after a checkpoint and continued with --restart writes the same
//    timeseries.csv, byte for byte, and the same summary.json (wall-time fields aside) as the run
//    that went straight through. Exact equality is the claim: with one thread and the same build the
//    restart is bit for bit (coupling/checkpoint_state.hpp) and the CSV holds every double at
//    round-trip precision, so any difference is a fault.
//  - Three runs killed with SIGKILL at random moments (a printed seed), one before the first
//    checkpoint: each continued with --restart, or refused and run afresh when no checkpoint was
//    written yet, ends with the uninterrupted run's timeseries.csv and summary.
//  - SIGTERM and SIGINT stop the run with a checkpoint (also when run.checkpoint_interval is 0), exit
//    status 128 + signal and no summary.json; the restart completes identically.
//  - A finished run continued with --restart and --set run.end_time=T writes what one run to T
//    writes (timeseries.csv and case.resolved.toml byte for byte, summary.json but the wall clock).
//  - --restart continues only the run its checkpoint belongs to (docs/errors.md, "Promises"): a
//    checkpoint copied from another run, a time series edited before the checkpoint and a mesh
//    copy replaced by another mesh of the same mass and volume are refused; a checkpoint written
//    before the fingerprint was recorded is continued with a warning.
//  - --restart refuses a directory without a checkpoint, a truncated checkpoint, a case file beside
//    it, --set of any other key and an end time not after the checkpoint: exit status 2, a message
//    naming the file or flag, the directory untouched.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"
#include "common/checkpoint_file.hpp"

namespace test_restart_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::scratch;
using Result = settle::test::CliResult;

// A checkpoint every 0.005 s (about 15 steps): the runs of these tests can be continued from any
// of them, and a checkpoint never changes what a run writes.
const std::vector<std::string> kCase{"--set",     "numerics.cells_per_diameter=6",
                                     "--set",     "run.end_time=0.03",
                                     "--set",     "run.output_interval=0.0025",
                                     "--set",     "run.checkpoint_interval=0.005",
                                     "--threads", "1"};

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const auto& w : words) text += " " + w;
  return text;
}

Result run_settle(const std::string& arguments) { return settle::test::run_settle("run", arguments); }

/// `settle run` started in the background (fork and exec), its stderr in a file.
class Background {
 public:
  explicit Background(const std::vector<std::string>& arguments, const fs::path& stderr_file) {
    const char* binary = std::getenv("SETTLE_BINARY");
    if (binary == nullptr) throw std::runtime_error("SETTLE_BINARY is not set");
    std::vector<std::string> words{binary, "run"};
    words.insert(words.end(), arguments.begin(), arguments.end());
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      if (!std::freopen(stderr_file.c_str(), "w", stderr) || !std::freopen("/dev/null", "w", stdout)) ::_exit(127);
      std::vector<char*> argv;
      for (auto& w : words) argv.push_back(w.data());
      argv.push_back(nullptr);
      ::execv(binary, argv.data());
      ::_exit(127);
    }
  }
  ~Background() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  void signal(int number) const {
    if (!reaped_) ::kill(pid_, number);
  }
  /// The raw wait status.
  int wait() {
    if (!reaped_) ::waitpid(pid_, &status_, 0);
    reaped_ = true;
    return status_;
  }
  bool running() {
    if (!reaped_ && ::waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
    return !reaped_;
  }

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
};

/// Times of the complete rows of a timeseries.csv (its first column).
std::vector<double> row_times(const fs::path& csv) {
  std::vector<double> times;
  std::istringstream text(read_text(csv));
  std::string line;
  std::getline(text, line);  // header
  while (std::getline(text, line))
    if (!text.eof()) times.push_back(std::stod(line.substr(0, line.find(','))));
  return times;
}

/// Polls (every 2 ms, at most 300 s) until `ready` holds or the process ended; true if it holds.
/// The bound only stops a hung run: the instrumented build on a loaded 2-core machine took more
/// than 30 s to reach the first checkpoint; a run that ends returns at once.
template <class Condition>
bool wait_until(Background& process, Condition ready) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  while (std::chrono::steady_clock::now() < deadline) {
    if (ready()) return true;
    if (!process.running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return false;
}

/// summary.json without what depends on the wall clock (wall time, MLUPS, the sub-step timers).
nlohmann::json physics_of_summary(const fs::path& dir) {
  nlohmann::json j = nlohmann::json::parse(read_text(dir / "summary.json"));
  for (const char* key : {"wall_seconds", "mlups", "timing"}) {
    EXPECT_TRUE(j.contains(key)) << key;
    j.erase(key);
  }
  return j;
}

/// The restart's "continuing from ... at t = X s" line: the checkpoint's time.
double restart_time(const std::string& err) {
  const auto at = err.find("continuing from");
  if (at == std::string::npos) return -1.0;
  const auto t = err.find("at t = ", at);
  return t == std::string::npos ? -1.0 : std::stod(err.substr(t + 7));
}

/// Every file under `dir` with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) files[fs::relative(entry.path(), dir).string()] = read_text(entry.path());
  return files;
}

class RestartCli : public ::testing::Test {
 protected:
  /// The uninterrupted reference run, once for all tests.
  static void SetUpTestSuite() {
    straight_ = new fs::path(scratch("restart_straight"));
    const Result r = run_settle("-o " + straight_->string() + joined(kCase));
    ASSERT_EQ(r.status, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*straight_);
    delete straight_;
  }
  static fs::path* straight_;

  /// Continues `dir` with --restart and checks the result against the uninterrupted run `reference`
  /// (by default the fixture's); returns the time the restart continued from.
  static double restart_and_compare(const fs::path& dir, const fs::path* reference = nullptr) {
    const fs::path& straight = reference ? *reference : *straight_;
    const std::string resolved_case = read_text(dir / "case.resolved.toml");
    const Result r = run_settle("--restart " + dir.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(straight / "timeseries.csv"));
    EXPECT_EQ(physics_of_summary(dir), physics_of_summary(straight));
    EXPECT_EQ(read_text(dir / "case.resolved.toml"), resolved_case);  // rewritten from the checkpoint
    return restart_time(r.err);
  }
};
fs::path* RestartCli::straight_ = nullptr;

// Killed with SIGKILL (nothing of settle runs: only the checkpoint on the disk counts) after the
// checkpoint at t = 0.02 s and after rows later than it reached the CSV, so that the restart must cut
// them off and write them again.
TEST_F(RestartCli, KilledRunContinuesToTheUninterruptedResult) {
  const fs::path dir = scratch("restart_killed");
  std::vector<std::string> arguments{"-o", dir.string()};
  arguments.insert(arguments.end(), kCase.begin(), kCase.end());
  arguments.insert(arguments.end(), {"--set", "run.checkpoint_interval=0.02"});  // after kCase's: it wins
  Background run(arguments, scratch("restart_killed.err"));
  const bool ready = wait_until(run, [&] {
    if (!fs::exists(dir / "checkpoint.bin")) return false;
    const std::vector<double> times = row_times(dir / "timeseries.csv");
    return !times.empty() && times.back() > 0.0201;  // the row after the checkpoint's (0.0225)
  });
  run.signal(SIGKILL);
  const int status = run.wait();
  ASSERT_TRUE(ready) << "the run ended, or took 300 s, before its first checkpoint";
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  const std::vector<double> times_at_kill = row_times(dir / "timeseries.csv");

  const double checkpoint_t = restart_and_compare(dir);
  ASSERT_GT(checkpoint_t, 0.0);
  // The killed run had rows past its checkpoint: the restart cut them and wrote them again.
  EXPECT_GT(times_at_kill.back(), checkpoint_t);
  fs::remove_all(dir);
  fs::remove(scratch("restart_killed.err"));
}

// ---- random kills -------------------------------------------------------------------------------

/// The seed of the random kills: SETTLE_KILL_SEED when set (to repeat a failure), else a fresh one.
std::uint32_t kill_seed() {
  if (const char* given = std::getenv("SETTLE_KILL_SEED")) return static_cast<std::uint32_t>(std::stoul(given));
  return std::random_device{}();
}

// Three runs killed with SIGKILL at moments drawn from a seeded generator (the seed is printed;
// SETTLE_KILL_SEED=N draws the same moments again, though where a moment falls among the steps also
// depends on the machine's pace). A moment is a count of rows of timeseries.csv to wait for, then
// 0-20 ms more (a step takes a few ms: the kill lands anywhere in one, checkpoint writes included).
// The first run is killed before its first checkpoint (0, 1 or 2 rows: t = 0.005 s is the third
// row, and the checkpoint follows it), the others after it (4 to 12 of the 13 rows). Then each is
// continued as docs/checkpoints.md and docs/errors.md (section 6, promise 1) promise, according to
// what the kill left:
//  - a checkpoint: --restart continues to the uninterrupted run's timeseries.csv, byte for byte,
//    and its summary (wall-clock fields aside);
//  - none (killed before the first): --restart is refused with status 2, naming the missing
//    directory or DIR/checkpoint.bin, and changes nothing; a fresh run into DIR (--overwrite) then
//    replaces what the killed run wrote and gives the uninterrupted result;
//  - the run ended before the kill (status 0): its result is the uninterrupted one.
TEST_F(RestartCli, RandomKillsContinueToTheUninterruptedResult) {
  const std::uint32_t seed = kill_seed();
  std::printf("RandomKills: seed %u (repeat with SETTLE_KILL_SEED=%u)\n", seed, seed);
  std::fflush(stdout);  // before the fork: a child would flush the copy of the buffer it inherits
  RecordProperty("kill_seed", std::to_string(seed));
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> extra_ms(0, 20);
  const fs::path err = scratch("restart_random.err");
  std::vector<std::string> arguments{"-o", ""};
  arguments.insert(arguments.end(), kCase.begin(), kCase.end());
  for (int iteration = 0; iteration < 3; ++iteration) {
    const int rows = iteration == 0 ? std::uniform_int_distribution<int>(0, 2)(random)
                                    : std::uniform_int_distribution<int>(4, 12)(random);
    const int delay_ms = extra_ms(random);
    SCOPED_TRACE(fmt::format("seed {}, kill {}: after {} rows and {} ms", seed, iteration, rows, delay_ms));
    const fs::path dir = scratch("restart_random_" + std::to_string(iteration));
    fs::remove_all(dir);
    arguments[1] = dir.string();
    Background run(arguments, err);
    wait_until(run, [&] { return rows == 0 || row_times(dir / "timeseries.csv").size() >= std::size_t(rows); });
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    run.signal(SIGKILL);
    const int status = run.wait();
    const bool checkpointed = fs::exists(dir / "checkpoint.bin");
    std::printf("RandomKills: kill %d after %d rows and %d ms: %s\n", iteration, rows, delay_ms,
                WIFEXITED(status) ? "finished first"
                : checkpointed    ? "restarted"
                                  : "no checkpoint yet");
    std::fflush(stdout);
    if (WIFEXITED(status)) {  // finished before the kill
      ASSERT_EQ(WEXITSTATUS(status), 0) << read_text(err);
      EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(*straight_ / "timeseries.csv"));
      EXPECT_EQ(physics_of_summary(dir), physics_of_summary(*straight_));
    } else if (checkpointed) {
      ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
      EXPECT_GT(restart_and_compare(dir), 0.0);
    } else {
      ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
      const bool dir_existed = fs::exists(dir);
      const auto before = dir_existed ? snapshot(dir) : std::map<std::string, std::string>{};
      const Result refused = run_settle("--restart " + dir.string());
      EXPECT_EQ(refused.status, 2) << refused.err;
      EXPECT_NE(refused.err.find(dir_existed ? (dir / "checkpoint.bin").string() + ": no checkpoint to restart from"
                                             : "--restart " + dir.string() + ": no such run directory"),
                std::string::npos)
          << refused.err;
      EXPECT_EQ(fs::exists(dir), dir_existed);
      if (dir_existed) {
        EXPECT_TRUE(snapshot(dir) == before);
      }
      const Result fresh = run_settle(joined(arguments) + " --overwrite");
      ASSERT_EQ(fresh.status, 0) << fresh.err;
      EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(*straight_ / "timeseries.csv"));
      EXPECT_EQ(physics_of_summary(dir), physics_of_summary(*straight_));
    }
    fs::remove_all(dir);
  }
  fs::remove(err);
}

// SIGTERM with run.checkpoint_interval = 0 (the default): the signal alone makes the checkpoint. A
// fixed sphere in a periodic box (32^3 cells, 461 steps to t = 0.3 s, about a second), whose summary
// (mean force, drag coefficient, averaged_samples) is the average of the run loop's samples over the
// second half: stopped in that half, the restart must carry the samples before the stop over.
TEST_F(RestartCli, TerminatedRunExits143WithACheckpointAndNoSummary) {
  const std::string case_file = std::string(SETTLE_SOURCE_DIR) + "/cases/periodic_sphere_array.toml";
  const std::vector<std::string> fixed_case{case_file, "--set", "run.end_time=0.3", "--threads", "1"};
  const fs::path reference = scratch("restart_term_straight");
  ASSERT_EQ(run_settle("-o " + reference.string() + joined(fixed_case)).status, 0);

  const fs::path dir = scratch("restart_term");
  const fs::path err = scratch("restart_term.err");
  std::vector<std::string> arguments{"-o", dir.string()};
  arguments.insert(arguments.end(), fixed_case.begin(), fixed_case.end());
  Background run(arguments, err);
  // Rows after t = 0 are written inside the run loop, after the handlers were installed.
  const bool ready = wait_until(run, [&] {
    const std::vector<double> times = row_times(dir / "timeseries.csv");
    return !times.empty() && times.back() > 0.16;
  });
  run.signal(SIGTERM);
  const int status = run.wait();
  ASSERT_TRUE(ready);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_TRUE(fs::exists(dir / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  const std::string message = read_text(err);
  EXPECT_NE(message.find("SIGTERM"), std::string::npos) << message;
  EXPECT_NE(message.find("settle run --restart " + dir.string()), std::string::npos) << message;

  EXPECT_GT(restart_and_compare(dir, &reference), 0.15);  // stopped in the averaged half
  fs::remove_all(dir);
  fs::remove_all(reference);
  fs::remove(err);
}

TEST_F(RestartCli, InterruptedRunExits130WithACheckpoint) {
  const fs::path dir = scratch("restart_int");
  std::vector<std::string> arguments{"-o", dir.string()};
  arguments.insert(arguments.end(), kCase.begin(), kCase.end());
  arguments.insert(arguments.end(), {"--set", "run.checkpoint_interval=0"});  // the signal alone writes it
  Background run(arguments, scratch("restart_int.err"));
  const bool ready = wait_until(run, [&] {
    const std::vector<double> times = row_times(dir / "timeseries.csv");
    return !times.empty() && times.back() > 0.0;
  });
  run.signal(SIGINT);
  const int status = run.wait();
  ASSERT_TRUE(ready);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(fs::exists(dir / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  fs::remove_all(dir);
  fs::remove(scratch("restart_int.err"));
}

// SIGHUP (an ssh connection or terminal that went away) stops the run as SIGTERM does: a
// checkpoint, a message, status 129, and a restart that continues to the uninterrupted result. It
// used to end the run at once, without either.
TEST_F(RestartCli, HangupStopsTheRunWithACheckpoint) {
  const fs::path dir = scratch("restart_hup");
  const fs::path err = scratch("restart_hup.err");
  std::vector<std::string> arguments{"-o", dir.string()};
  arguments.insert(arguments.end(), kCase.begin(), kCase.end());
  Background run(arguments, err);
  const bool ready = wait_until(run, [&] {
    const std::vector<double> times = row_times(dir / "timeseries.csv");
    return !times.empty() && times.back() > 0.006;  // after the first periodic checkpoint (0.005)
  });
  run.signal(SIGHUP);
  const int status = run.wait();
  ASSERT_TRUE(ready);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 129);
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  const std::string message = read_text(err);
  EXPECT_NE(message.find("interrupted by SIGHUP"), std::string::npos) << message;
  EXPECT_GT(restart_and_compare(dir), 0.006);  // from the signal's checkpoint, not the periodic one
  fs::remove_all(dir);
  fs::remove(err);
}

// A run to 0.015 s with a checkpoint at its end, continued to 0.03 s, against the fixture's run to
// 0.03 s with the same checkpoint interval (so that the two resolved cases may be compared whole).
TEST_F(RestartCli, FinishedRunExtendedToALaterEndTimeWritesWhatOneLongerRunWrites) {
  const fs::path dir = scratch("restart_extend");
  ASSERT_EQ(run_settle("-o " + dir.string() + joined(kCase) + " --set run.end_time=0.015").status, 0);
  EXPECT_LT(row_times(dir / "timeseries.csv").back(), 0.016);

  const Result r = run_settle("--restart " + dir.string() + " --set run.end_time=0.03");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(restart_time(r.err), 0.015, 0.001);  // from the checkpoint at the first run's end
  EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(*straight_ / "timeseries.csv"));
  EXPECT_EQ(physics_of_summary(dir), physics_of_summary(*straight_));
  EXPECT_EQ(read_text(dir / "case.resolved.toml"), read_text(*straight_ / "case.resolved.toml"));
  fs::remove_all(dir);
}

// A directory without a checkpoint (a finished run that wrote none), then a truncated checkpoint,
// then --restart beside a case file, beside --set of a key other than run.end_time and with an end
// time before the checkpoint's: exit status 2, the file or flags named, and not a byte of the
// directory changed.
TEST_F(RestartCli, RefusalsExitTwoAndLeaveTheDirectoryUntouched) {
  const fs::path dir = scratch("restart_refused");
  fs::remove_all(dir);
  fs::copy(*straight_, dir, fs::copy_options::recursive);
  fs::remove(dir / "checkpoint.bin");
  const auto expect_refused = [&](const std::string& arguments, const std::vector<std::string>& named) {
    const auto before = snapshot(dir);
    const Result r = run_settle(arguments);
    EXPECT_EQ(r.status, 2) << arguments << "\n" << r.err;
    for (const auto& word : named) EXPECT_NE(r.err.find(word), std::string::npos) << word << " in: " << r.err;
    EXPECT_TRUE(snapshot(dir) == before) << arguments;
  };
  expect_refused("--restart " + dir.string(), {(dir / "checkpoint.bin").string()});

  // A checkpoint of the same case (written at t = 0.005 s, the end of this short run), cut in half.
  const fs::path with_checkpoint = scratch("restart_refused_source");
  ASSERT_EQ(run_settle("-o " + with_checkpoint.string() + joined(kCase) + " --set run.end_time=0.005" +
                       " --set run.checkpoint_interval=0.005")
                .status,
            0);
  const std::uintmax_t bytes = fs::file_size(with_checkpoint / "checkpoint.bin");
  fs::copy_file(with_checkpoint / "checkpoint.bin", dir / "checkpoint.bin");
  fs::resize_file(dir / "checkpoint.bin", bytes / 2);
  expect_refused("--restart " + dir.string(), {(dir / "checkpoint.bin").string(), "truncated"});

  fs::copy_file(with_checkpoint / "checkpoint.bin", dir / "checkpoint.bin", fs::copy_options::overwrite_existing);
  const std::string case_file = std::string(SETTLE_SOURCE_DIR) + "/cases/grain.toml";
  expect_refused(case_file + " --restart " + dir.string(), {"--restart", case_file});
  expect_refused("--restart " + dir.string() + " --set fluid.density=1100",
                 {"--restart", "--set fluid.density=1100", "run.end_time"});
  expect_refused("--restart " + dir.string() + " --set run.end_time=0.004",
                 {"--set run.end_time=0.004", "later end time"});
  fs::remove_all(dir);
  fs::remove_all(with_checkpoint);
}

// ---- promise 2: a restart continues only the run its checkpoint belongs to ----------------------

/// Rewrites a checkpoint without its section `name` (a checkpoint of an older settle).
void drop_section(const fs::path& file, const std::string& name) {
  std::vector<std::pair<std::string, std::vector<std::byte>>> sections;
  {
    const settle::CheckpointFile in(file);
    for (const std::string& n : in.section_names())
      if (n != name) {
        const auto data = in.section(n);
        sections.emplace_back(n, std::vector<std::byte>(data.begin(), data.end()));
      }
  }
  settle::CheckpointWriter out;
  for (auto& [n, data] : sections) out.add_copy(n, std::move(data));
  out.write(file);
}

// Two runs of the default case to t = 0.015 s, particle densities 1100 and 1200 kg/m^3: the second
// one's checkpoint copied into the first one's directory would splice its rows after the first
// one's (docs/checkpoints.md); a time series edited in one digit before the checkpoint is the
// same fault without a copy.
TEST_F(RestartCli, ACheckpointOfAnotherRunOrAnEditedSeriesIsRefused) {
  const fs::path dir = scratch("restart_mixed"), other = scratch("restart_mixed_other");
  ASSERT_EQ(run_settle("-o " + dir.string() + joined(kCase) + " --set run.end_time=0.015").status, 0);
  ASSERT_EQ(
      run_settle("-o " + other.string() + joined(kCase) + " --set run.end_time=0.015" + " --set particle.density=1200")
          .status,
      0);
  const std::string series = read_text(dir / "timeseries.csv");
  fs::copy_file(other / "checkpoint.bin", dir / "checkpoint.bin", fs::copy_options::overwrite_existing);
  auto before = snapshot(dir);
  Result r = run_settle("--restart " + dir.string() + " --set run.end_time=0.03");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("timeseries.csv is not the time series this checkpoint belongs to"), std::string::npos) << r.err;
  EXPECT_TRUE(snapshot(dir) == before);

  // The run's own checkpoint again, and one digit of the first row changed (same length).
  ASSERT_EQ(run_settle("-o " + dir.string() + joined(kCase) + " --set run.end_time=0.015 --overwrite").status, 0);
  std::string edited = read_text(dir / "timeseries.csv");
  const std::size_t row = edited.find('\n') + 1;                         // the first row, t = 0
  const std::size_t digit = edited.find_first_of("123456789", row + 2);  // in x, after "0,"
  edited[digit] = edited[digit] == '9' ? '8' : static_cast<char>(edited[digit] + 1);
  std::ofstream(dir / "timeseries.csv", std::ios::binary) << edited;
  before = snapshot(dir);
  r = run_settle("--restart " + dir.string() + " --set run.end_time=0.03");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("timeseries.csv is not the time series"), std::string::npos) << r.err;
  EXPECT_TRUE(snapshot(dir) == before);
  EXPECT_EQ(series.size(), edited.size());
  fs::remove_all(dir);
  fs::remove_all(other);
}

/// An ASCII STL of a box with half-edges h (m), centred on the origin, its faces wound outward.
std::string box_stl(const Eigen::Vector3d& h) {
  const auto corner = [&](int i) {
    return Eigen::Vector3d((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  };
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  std::string text = "solid box\n";
  for (const auto& f : faces)
    for (const auto& tri : {std::array<int, 3>{f[0], f[1], f[2]}, std::array<int, 3>{f[0], f[2], f[3]}}) {
      text += "facet normal 0 0 0\nouter loop\n";
      for (const int i : tri)
        text += fmt::format("vertex {:.17g} {:.17g} {:.17g}\n", corner(i).x(), corner(i).y(), corner(i).z());
      text += "endloop\nendfacet\n";
    }
  return text + "endsolid box\n";
}

// A 1 x 0.5 x 0.5 mm box, its mesh copy in DIR replaced by the same box turned 90 degrees about z
// (0.5 x 1 x 0.5 mm): the same mass and volume, which were all a restart compared.
TEST_F(RestartCli, AReplacedMeshIsRefused) {
  const fs::path dir = scratch("restart_mesh");
  const fs::path mesh = scratch("restart_mesh_box.stl");
  std::ofstream(mesh) << box_stl({0.5e-3, 0.25e-3, 0.25e-3});
  const fs::path case_file = settle::test::write_scratch_case(
      "restart_mesh_case",
      "[fluid]\ndensity = 998.2\ndynamic_viscosity = 1.0e-3\n"
      "[particle]\nshape = \"mesh\"\nfile = \"" +
          mesh.string() +
          "\"\ndensity = 1100.0\n"
          "position = [2.0e-3, 2.0e-3, 3.0e-3]\n"
          "[domain]\nsize = [4.0e-3, 4.0e-3, 6.0e-3]\n[numerics]\ncells_per_diameter = 6\n"
          "[run]\nend_time = 1.0e-3\noutput_interval = 5.0e-4\ncheckpoint_interval = 1.0e-3\n");
  ASSERT_EQ(run_settle(case_file.string() + " -o " + dir.string() + " --threads 1").status, 0);
  ASSERT_TRUE(fs::exists(dir / "particle_mesh.stl"));
  std::ofstream(dir / "particle_mesh.stl") << box_stl({0.25e-3, 0.5e-3, 0.25e-3});
  const auto before = snapshot(dir);
  const Result r = run_settle("--restart " + dir.string() + " --set run.end_time=2e-3");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("particle_mesh.stl is not the input file this run started with"), std::string::npos) << r.err;
  EXPECT_TRUE(snapshot(dir) == before);
  fs::remove_all(dir);
  fs::remove(mesh);
  fs::remove(case_file);
}

// A checkpoint without the run's fingerprint (as settle wrote before it recorded one) is continued,
// with a warning naming the file, to the same result as the run that went straight through:
// refusing it would throw away the runs of long validation cases.
TEST_F(RestartCli, ACheckpointWithoutTheFingerprintIsContinuedWithAWarning) {
  const fs::path dir = scratch("restart_legacy");
  ASSERT_EQ(run_settle("-o " + dir.string() + joined(kCase) + " --set run.end_time=0.015").status, 0);
  drop_section(dir / "checkpoint.bin", "caller/blob/run/fingerprint");
  const Result r = run_settle("--restart " + dir.string() + " --set run.end_time=0.03");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find((dir / "checkpoint.bin").string() + ": written by a settle that did not record the run's "
                                                           "fingerprint"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(read_text(dir / "timeseries.csv"), read_text(*straight_ / "timeseries.csv"));
  fs::remove_all(dir);
}

}  // namespace test_restart_cli
