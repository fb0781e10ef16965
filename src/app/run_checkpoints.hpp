#pragma once
// Checkpoints of `settle run` (docs/checkpoints.md): DIR/checkpoint.bin every run.checkpoint_interval
// of simulated time and when a stop signal (SIGINT, SIGTERM, SIGHUP, ...) stops the run, and `settle run --restart DIR`, which
// continues the run in DIR from it as if it had never stopped.
//
// A checkpoint holds the simulation (coupling/checkpoint_state.hpp) and what the front end needs to
// continue its outputs: the resolved case text (exactly case.resolved.toml), the case's name, the
// run loop's state (coupling::RunStart: step, the sample schedule's next index, the samples so far,
// the wall time so far), the VTK schedule and file count, the OpenMP thread count, and the length of
// timeseries.csv at that moment (a restart cuts the file back to it: rows written after the
// checkpoint are written again).
#include <array>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/stop_signals.hpp"
#include "coupling/checkpoint_state.hpp"
#include "coupling/runner.hpp"
#include "coupling/simulation.hpp"
#include "io/schema.hpp"
#include "parallel/communicator.hpp"

namespace settle::app {

/// File name of the checkpoint inside the run directory.
inline constexpr const char* kCheckpointFileName = "checkpoint.bin";

/// Where the VTK output (run.vtk_interval) stands: what a checkpoint stores to continue it.
struct VtkProgress {
  std::int64_t next_index = 0;  ///< coupling::OutputSchedule::next_index() of the VTK schedule
  int files_written = 0;        ///< the number NNNNNN of the next fluid_NNNNNN.vti / surface_NNNNNN.vtp
};

/// A file the run reads again at a restart (the mesh copy particle_mesh.stl beside
/// case.resolved.toml), as the checkpoint records it: a restart refuses a file that differs.
struct InputFileFingerprint {
  std::string name;  ///< relative to the run directory
  std::uintmax_t bytes = 0;
  std::uint32_t crc32 = 0;
  bool operator==(const InputFileFingerprint&) const = default;
};

/// The fingerprint of `run_dir / name`. settle::InputError naming the file when it cannot be read.
InputFileFingerprint fingerprint_input_file(const std::filesystem::path& run_dir, const std::string& name);

/// The fingerprints of the files a run of `resolved` (a case whose paths are relative to
/// `run_dir`) reads: its mesh (particle.file), if any.
std::vector<InputFileFingerprint> input_files_of(const io::CaseValues& resolved, const std::filesystem::path& run_dir);

/// How far a CRC-32 of timeseries.csv has got: the first `bytes` bytes have `crc32`.
struct SeriesChecksum {
  std::uintmax_t bytes = 0;
  std::uint32_t crc32 = 0;
};

/// The samples as a checkpoint record (RecordWriter): every coupling::Sample field, bit for bit.
std::vector<std::byte> samples_record(std::span<const coupling::Sample> samples);
/// The inverse of samples_record. CheckpointError naming `section` when the record is malformed.
std::vector<coupling::Sample> samples_from_record(std::span<const std::byte> record, const std::string& section);

/// The one key `--set` may change beside `--restart`: a run continues to a later end time. Any
/// other key would make the continued run differ from the one the checkpoint belongs to.
inline constexpr const char* kRestartExtendableKey = "run.end_time";

/// `--restart DIR` takes the case and its directory from the checkpoint: a case file or -o next to
/// it is refused, and --set for any key but kRestartExtendableKey (settle::InputError naming both
/// flags).
void check_restart_flags(const std::string& restart_dir, const std::string& case_file,
                         const std::vector<std::string>& overrides, const std::string& output_dir);

/// A warning for a long run that keeps no checkpoint (run.checkpoint_interval and
/// run.checkpoint_wall_interval both 0): once it has ended, `settle run --restart DIR --set
/// run.end_time=T` has nothing to continue from, and a crash loses the whole run. Empty when
/// either interval is set or the run makes fewer than kLongRunCellUpdates cell updates.
std::optional<std::string> missing_checkpoint_advice(double checkpoint_interval_si, double checkpoint_wall_interval_s,
                                                     double cell_updates);

/// Cell updates (cells x steps) from which a run counts as long for missing_checkpoint_advice:
/// 20-30 minutes at 60-80 million updates a second, the speed of the 10^7-cell validation runs on
/// two threads of the development machine (their wall times in docs/validation.md).
inline constexpr double kLongRunCellUpdates = 1e11;

/// Writes DIR/checkpoint.bin for one run (atomically: the previous checkpoint stays whole until
/// the new one is complete). Beside the state it records the run's fingerprint, so that a restart
/// continues only the run the checkpoint belongs to: the CRC-32 of timeseries.csv up to the
/// checkpoint, and the fingerprints of the input files (docs/checkpoints.md).
class RunCheckpoints {
 public:
  /// `series`: the checksum of the part of timeseries.csv already there (a restart's; a fresh
  /// run's file starts empty).
  RunCheckpoints(std::filesystem::path run_dir, std::string resolved_case, std::string case_name,
                 std::vector<InputFileFingerprint> inputs, SeriesChecksum series);

  /// The simulation, the loop's state and the front end's. timeseries.csv must hold every row
  /// handed out so far (TimeseriesWriter flushes each row); it is synced to the disk first, so
  /// that the length stored is there after a crash, and its checksum is carried on over the bytes
  /// added since the last checkpoint.
  void write(const coupling::Simulation& simulation, const coupling::RunStart& loop, const VtkProgress& vtk);
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path run_dir_;
  std::filesystem::path file_;
  std::string resolved_case_;
  std::string case_name_;
  std::vector<InputFileFingerprint> inputs_;
  SeriesChecksum series_;
};

/// `settle run --restart DIR`: DIR/checkpoint.bin opened, verified and decoded, before anything in
/// DIR is changed. Every refusal is an CheckpointError or settle::InputError (exit 2) naming
/// the file.
class RestartPoint {
 public:
  explicit RestartPoint(std::filesystem::path run_dir);

  const std::filesystem::path& run_dir() const { return run_dir_; }
  const std::filesystem::path& file() const { return file_; }
  /// The resolved case text stored in the checkpoint, and its values (relative paths in it, e.g.
  /// the mesh copy particle_mesh.stl, are relative to run_dir()).
  const std::string& resolved_case() const { return resolved_case_; }
  const io::CaseValues& case_values() const { return *values_; }
  /// Applies `--set run.end_time=T` (check_restart_flags let nothing else through) to the values
  /// and to the resolved case's text. T must lie after the checkpoint's time (settle::InputError
  /// naming the flag and that time).
  void apply_overrides(const std::vector<std::string>& overrides);
  const std::string& case_name() const { return case_name_; }
  double time_si() const { return time_si_; }
  std::uintmax_t timeseries_bytes() const { return timeseries_bytes_; }
  const VtkProgress& vtk() const { return vtk_; }
  /// OpenMP threads of the run that wrote the checkpoint (the restart's default: bit-for-bit
  /// continuation needs the same count).
  int threads() const { return threads_; }
  /// The loop's state at the checkpoint (its samples included).
  const coupling::RunStart& loop() const { return loop_; }
  /// The checksum of timeseries.csv up to the checkpoint, and the run's input files (both checked
  /// against the checkpoint's record when it has one).
  SeriesChecksum series() const { return series_; }
  const std::vector<InputFileFingerprint>& inputs() const { return inputs_; }
  /// Warnings for the user (a checkpoint written before settle recorded the run's fingerprint).
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// Puts the saved state into `simulation`, built from case_values(), and releases the file's
  /// memory mapping (restore once).
  void restore(coupling::Simulation& simulation);
  /// Hands the loop's state to coupling::run (moves the samples out).
  coupling::RunStart take_loop_state() { return std::move(loop_); }

 private:
  std::filesystem::path run_dir_;
  std::filesystem::path file_;
  std::optional<coupling::SimulationCheckpoint> checkpoint_;
  std::string resolved_case_;
  std::optional<io::CaseValues> values_;
  std::string case_name_;
  double time_si_ = 0.0;
  std::uintmax_t timeseries_bytes_ = 0;
  VtkProgress vtk_;
  int threads_ = 1;
  coupling::RunStart loop_;
  SeriesChecksum series_;
  std::vector<InputFileFingerprint> inputs_;
  std::vector<std::string> warnings_;

  void check_fingerprint(const std::vector<std::byte>* record);
};

/// The stop signals (common/stop_signals.hpp: SIGINT, SIGTERM, SIGHUP, ...), while this object
/// lives, only set a flag (async-signal-safe: a lock-free atomic store): the run loop polls raised()
/// after every step and stops there. The previous handlers come back on destruction. One object
/// at a time.
class InterruptSignals {
 public:
  InterruptSignals();
  ~InterruptSignals();
  InterruptSignals(const InterruptSignals&) = delete;
  InterruptSignals& operator=(const InterruptSignals&) = delete;

  bool raised() const;
  /// The signal that arrived first (0: none).
  int signal_number() const;
  /// The signal that stopped a run split over `ranks`, which stop together when any of them saw
  /// one: the first of kStopSignals that any rank saw, else 0. A collective call.
  int signal_number_seen_by_any(parallel::Communicator& ranks) const;

 private:
  std::array<struct sigaction, kStopSignals.size()> previous_{};
};

/// The settle::RunInterrupted for a run that `signal_number` stopped after writing `checkpoint`: the
/// message says where the run stopped, that no summary.json was written and how to continue.
RunInterrupted interrupted_error(int signal_number, const coupling::RunResult& result,
                                 const std::filesystem::path& run_dir, const std::filesystem::path& checkpoint);

}  // namespace settle::app
