#include "app/run_checkpoints.hpp"

#include <fmt/core.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <utility>

#include "common/atomic_file.hpp"
#include "common/stop_signals.hpp"
#include "io/case_schema.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

// Names of the caller's data in the checkpoint (docs/checkpoints.md, "settle run's sections").
constexpr const char* kOutputNextIndex = "run/output_next_index";
constexpr const char* kWallSeconds = "run/wall_seconds";
constexpr const char* kPeakDensityDeviation = "run/peak_density_deviation";
constexpr const char* kPeakLatticeSpeed = "run/peak_lattice_speed";
constexpr const char* kTimeseriesBytes = "run/timeseries_bytes";
constexpr const char* kVtkNextIndex = "run/vtk_next_index";
constexpr const char* kVtkFilesWritten = "run/vtk_files_written";
constexpr const char* kThreads = "run/threads";
constexpr const char* kSamplesBlob = "run/samples";
constexpr const char* kCaseNameBlob = "run/case_name";
constexpr const char* kIntervalBlob = "run/interval_sums";
constexpr const char* kFingerprintBlob = "run/fingerprint";

fs::path timeseries_path(const fs::path& run_dir) { return run_dir / "timeseries.csv"; }

void write_sample(RecordWriter& out, const coupling::Sample& s) {
  out.f64(s.t_si);
  out.vec3(s.position_si);
  out.vec3(s.velocity_si);
  out.vec3(s.angular_velocity_n_si);
  out.vec3(s.angular_velocity_b_si);
  // The chart as it is (set and angles), not a matrix: the sample's set and angles come back exactly.
  out.u32(s.attitude.set() == attitude::EulerSet::set1 ? 1 : 2);
  out.vec3(s.attitude.angles());
  out.vec3(s.hydrodynamic.force_si);
  out.vec3(s.hydrodynamic.torque_si);
  out.f64(s.reynolds);
  out.vec3(s.relative_flow_si);
  out.f64(s.slip_max_si);
  out.f64(s.slip_rms_si);
  out.vec3(s.contact.force_si);
  out.vec3(s.contact.torque_si);
  out.f64(s.wall_gap_si);
}

coupling::Sample read_sample(RecordReader& in, const std::string& section) {
  coupling::Sample s;
  s.t_si = in.f64();
  s.position_si = in.vec3();
  s.velocity_si = in.vec3();
  s.angular_velocity_n_si = in.vec3();
  s.angular_velocity_b_si = in.vec3();
  const std::uint32_t set = in.u32();
  if (set != 1 && set != 2) throw CheckpointError(fmt::format("checkpoint section '{}': Euler set {}", section, set));
  s.attitude = attitude::Attitude(set == 1 ? attitude::EulerSet::set1 : attitude::EulerSet::set2, in.vec3());
  s.hydrodynamic.force_si = in.vec3();
  s.hydrodynamic.torque_si = in.vec3();
  s.reynolds = in.f64();
  s.relative_flow_si = in.vec3();
  s.slip_max_si = in.f64();
  s.slip_rms_si = in.f64();
  s.contact.force_si = in.vec3();
  s.contact.torque_si = in.vec3();
  s.wall_gap_si = in.f64();
  return s;
}

std::size_t sample_record_bytes() {
  RecordWriter one;
  write_sample(one, coupling::Sample{});
  return one.take().size();
}

// A value the checkpoint must hold.
double stored_value(const coupling::CheckpointCallerData& caller, const char* name) {
  const auto it = caller.values.find(name);
  if (it == caller.values.end())
    throw CheckpointError(fmt::format("the checkpoint has no value '{}' (not written by settle run?)", name));
  return it->second;
}

// A non-negative finite value the checkpoint must hold.
double measured_value(const coupling::CheckpointCallerData& caller, const char* name) {
  const double value = stored_value(caller, name);
  if (!(value >= 0.0) || !std::isfinite(value))
    throw CheckpointError(fmt::format("value '{}' of the checkpoint is {}, not a non-negative number", name, value));
  return value;
}

// A whole number stored as a caller value (exact in a double up to 2^53).
std::int64_t whole_value(const coupling::CheckpointCallerData& caller, const char* name) {
  const double value = stored_value(caller, name);
  if (!(value >= 0.0 && value <= 9007199254740992.0 && std::floor(value) == value))
    throw CheckpointError(fmt::format("value '{}' of the checkpoint is {}, not a count", name, value));
  return static_cast<std::int64_t>(value);
}

const std::vector<std::byte>& blob(const coupling::CheckpointCallerData& caller, const char* name) {
  const auto it = caller.blobs.find(name);
  if (it == caller.blobs.end())
    throw CheckpointError(fmt::format("the checkpoint has no record '{}' (not written by settle run?)", name));
  return it->second;
}

// The rows of timeseries.csv up to now reach the disk before the checkpoint that counts them does.
void sync_to_disk(const fs::path& file) {
  try {
    sync_file_to_disk(file);
  } catch (const InputError& e) {
    throw CheckpointError(fmt::format("before the checkpoint: {}", e.what()));
  }
}

std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free atomic");

void on_stop_signal(int signal_number) {
  // Only the first signal counts; a second one (Ctrl-C again while the checkpoint is written) is
  // ignored: the run stops at the end of the current step anyway.
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, signal_number);
}

std::vector<std::byte> interval_record(const coupling::IntervalSums& sums) {
  RecordWriter out;
  out.u64(static_cast<std::uint64_t>(sums.steps));
  for (const body::Wrench* w : {&sums.hydrodynamic, &sums.contact}) {
    out.vec3(w->force_si);
    out.vec3(w->torque_si);
  }
  return out.take();
}

// A checkpoint written before the sums were kept has none: the first row after the restart then
// averages the steps made since.
coupling::IntervalSums interval_from_record(const coupling::CheckpointCallerData& caller) {
  coupling::IntervalSums sums;
  const auto it = caller.blobs.find(kIntervalBlob);
  if (it == caller.blobs.end()) return sums;
  RecordReader in(it->second, std::string("caller/blob/") + kIntervalBlob);
  const std::uint64_t steps = in.u64();
  if (steps > 9007199254740992ULL)
    throw CheckpointError(fmt::format("record '{}' of the checkpoint counts {} steps", kIntervalBlob, steps));
  sums.steps = static_cast<std::int64_t>(steps);
  for (body::Wrench* w : {&sums.hydrodynamic, &sums.contact}) {
    w->force_si = in.vec3();
    w->torque_si = in.vec3();
  }
  in.expect_end();
  return sums;
}

// The run's fingerprint: the checksum of timeseries.csv up to the checkpoint, and the input files.
std::vector<std::byte> fingerprint_record(const SeriesChecksum& series,
                                          const std::vector<InputFileFingerprint>& inputs) {
  RecordWriter out;
  out.u64(series.bytes);
  out.u32(series.crc32);
  out.u64(inputs.size());
  for (const InputFileFingerprint& f : inputs) {
    out.string(f.name);
    out.u64(f.bytes);
    out.u32(f.crc32);
  }
  return out.take();
}

struct RunFingerprint {
  SeriesChecksum series;
  std::vector<InputFileFingerprint> inputs;
};

RunFingerprint fingerprint_from_record(const std::vector<std::byte>& record) {
  RecordReader in(record, std::string("caller/blob/") + kFingerprintBlob);
  RunFingerprint f;
  f.series.bytes = in.u64();
  f.series.crc32 = in.u32();
  // No reserve from the stored count: a malformed count fails at the first read past the end.
  for (std::uint64_t n = in.u64(); n > 0; --n) {
    InputFileFingerprint file;
    file.name = in.string();
    file.bytes = in.u64();
    file.crc32 = in.u32();
    f.inputs.push_back(std::move(file));
  }
  in.expect_end();
  return f;
}

std::string checksum_text(std::uintmax_t bytes, std::uint32_t crc) {
  return fmt::format("{} bytes, CRC-32 {:08x}", bytes, crc);
}

}  // namespace

InputFileFingerprint fingerprint_input_file(const fs::path& run_dir, const std::string& name) {
  const fs::path file = run_dir / name;
  std::error_code error;
  const std::uintmax_t bytes = fs::file_size(file, error);
  if (error) throw InputError(fmt::format("{}: cannot read it: {}", file.string(), error.message()));
  return {name, bytes, crc32_of_file(file, 0, bytes)};
}

std::vector<InputFileFingerprint> input_files_of(const io::CaseValues& resolved, const fs::path& run_dir) {
  if (!resolved.has("particle.file")) return {};
  return {fingerprint_input_file(run_dir, resolved.string("particle.file"))};
}

std::vector<std::byte> samples_record(std::span<const coupling::Sample> samples) {
  RecordWriter out;
  out.u64(samples.size());
  for (const coupling::Sample& s : samples) write_sample(out, s);
  return out.take();
}

std::vector<coupling::Sample> samples_from_record(std::span<const std::byte> record, const std::string& section) {
  RecordReader in(record, section);
  const std::uint64_t count = in.u64();
  // Checked before anything is allocated: a corrupt count must not ask for terabytes.
  if (record.size() - sizeof count != count * sample_record_bytes())
    throw CheckpointError(
        fmt::format("checkpoint section '{}': {} bytes cannot hold {} samples", section, record.size(), count));
  std::vector<coupling::Sample> samples;
  samples.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) samples.push_back(read_sample(in, section));
  in.expect_end();
  return samples;
}

void check_restart_flags(const std::string& restart_dir, const std::string& case_file,
                         const std::vector<std::string>& overrides, const std::string& output_dir) {
  if (restart_dir.empty()) return;
  const std::string why =
      "the case, its settings and the output directory of a restart are those stored in the "
      "checkpoint";
  if (!case_file.empty())
    throw InputError(
        fmt::format("--restart {} and the case file {} exclude each other: {}", restart_dir, case_file, why));
  for (const std::string& assignment : overrides)
    if (io::override_key(assignment) != kRestartExtendableKey)
      throw InputError(
          fmt::format("--restart {} and --set {} exclude each other: {}; only --set {}=T continues the "
                      "run to a later end time",
                      restart_dir, assignment, why, kRestartExtendableKey));
  if (!output_dir.empty())
    throw InputError(fmt::format("--restart {} and -o {} exclude each other: {} (the run continues in {})", restart_dir,
                                 output_dir, why, restart_dir));
}

std::optional<std::string> missing_checkpoint_advice(double checkpoint_interval_si, double checkpoint_wall_interval_s,
                                                     double cell_updates) {
  if (checkpoint_interval_si > 0.0 || checkpoint_wall_interval_s > 0.0 || cell_updates < kLongRunCellUpdates)
    return std::nullopt;
  return fmt::format(
      "run.checkpoint_interval: this run makes {:.2g} cell updates and keeps no checkpoint (run.checkpoint_interval "
      "and run.checkpoint_wall_interval are 0): after it ends it cannot be continued to a later run.end_time "
      "(settle run --restart), and a crash loses all of it; set run.checkpoint_wall_interval (e.g. 1800 s) or "
      "run.checkpoint_interval (docs/checkpoints.md)",
      cell_updates);
}

// RunCheckpoints

RunCheckpoints::RunCheckpoints(fs::path run_dir, std::string resolved_case, std::string case_name,
                               std::vector<InputFileFingerprint> inputs, SeriesChecksum series)
    : run_dir_(std::move(run_dir)),
      file_(run_dir_ / kCheckpointFileName),
      resolved_case_(std::move(resolved_case)),
      case_name_(std::move(case_name)),
      inputs_(std::move(inputs)),
      series_(series) {}

void RunCheckpoints::write(const coupling::Simulation& sim, const coupling::RunStart& loop, const VtkProgress& vtk) {
  // Rank 0 writes the time series and the part of the checkpoint that records its length.
  std::uintmax_t timeseries_bytes = 0;
  if (sim.communicator().rank() == 0) {
    const fs::path timeseries = timeseries_path(run_dir_);
    sync_to_disk(timeseries);
    std::error_code error;
    timeseries_bytes = fs::file_size(timeseries, error);
    if (error)
      throw CheckpointError(
          fmt::format("{}: cannot measure it for the checkpoint: {}", timeseries.string(), error.message()));
    if (timeseries_bytes < series_.bytes)
      throw CheckpointError(fmt::format("{}: holds {} bytes, fewer than the {} of the last checkpoint",
                                        timeseries.string(), timeseries_bytes, series_.bytes));
    try {
      series_.crc32 =
          crc32_of_file(timeseries, series_.bytes, timeseries_bytes - series_.bytes, series_.crc32);  // the new rows
    } catch (const InputError& e) {
      throw CheckpointError(fmt::format("before the checkpoint: {}", e.what()));
    }
    series_.bytes = timeseries_bytes;
  }
  coupling::CheckpointCallerData data;
  data.resolved_case = resolved_case_;
  data.values[kOutputNextIndex] = static_cast<double>(loop.next_output_index);
  data.values[kWallSeconds] = loop.wall_seconds;
  data.values[kPeakDensityDeviation] = loop.extremes.density_deviation;
  data.values[kPeakLatticeSpeed] = loop.extremes.lattice_speed;
  data.values[kTimeseriesBytes] = static_cast<double>(timeseries_bytes);
  data.values[kVtkNextIndex] = static_cast<double>(vtk.next_index);
  data.values[kVtkFilesWritten] = static_cast<double>(vtk.files_written);
  data.values[kThreads] = static_cast<double>(omp_get_max_threads());
  data.blobs[kSamplesBlob] = samples_record(loop.samples);
  data.blobs[kIntervalBlob] = interval_record(loop.interval);
  const auto name = std::as_bytes(std::span(case_name_));
  data.blobs[kCaseNameBlob] = std::vector<std::byte>(name.begin(), name.end());
  data.blobs[kFingerprintBlob] = fingerprint_record(series_, inputs_);
  coupling::write_checkpoint(sim, data, file_);
}

// RestartPoint

RestartPoint::RestartPoint(fs::path run_dir) : run_dir_(std::move(run_dir)), file_(run_dir_ / kCheckpointFileName) {
  std::error_code error;
  if (!fs::is_directory(run_dir_, error))
    throw InputError(fmt::format("--restart {}: no such run directory", run_dir_.string()));
  if (!fs::exists(file_, error))
    throw CheckpointError(
        fmt::format("{}: no checkpoint to restart from (settle run writes one every "
                    "run.checkpoint_interval and when a signal such as SIGINT, SIGTERM or SIGHUP stops it)",
                    file_.string()));
  try {
    checkpoint_.emplace(file_);
    const coupling::CheckpointCallerData& caller = checkpoint_->caller();
    resolved_case_ = caller.resolved_case;
    const auto& name = blob(caller, kCaseNameBlob);
    case_name_.assign(reinterpret_cast<const char*>(name.data()), name.size());
    time_si_ = checkpoint_->time_si();
    timeseries_bytes_ = static_cast<std::uintmax_t>(whole_value(caller, kTimeseriesBytes));
    vtk_.next_index = whole_value(caller, kVtkNextIndex);
    const std::int64_t files = whole_value(caller, kVtkFilesWritten);
    if (files > std::numeric_limits<int>::max())
      throw CheckpointError(fmt::format("value '{}' of the checkpoint is {}", kVtkFilesWritten, files));
    vtk_.files_written = static_cast<int>(files);
    loop_.step = checkpoint_->steps();
    loop_.next_output_index = whole_value(caller, kOutputNextIndex);
    loop_.wall_seconds = caller.values.count(kWallSeconds) ? caller.values.at(kWallSeconds) : 0.0;
    loop_.extremes.density_deviation = measured_value(caller, kPeakDensityDeviation);
    loop_.extremes.lattice_speed = measured_value(caller, kPeakLatticeSpeed);
    const std::int64_t threads = whole_value(caller, kThreads);
    if (threads < 1 || threads > std::numeric_limits<int>::max())
      throw CheckpointError(fmt::format("value '{}' of the checkpoint is {}", kThreads, threads));
    threads_ = static_cast<int>(threads);
    loop_.samples = samples_from_record(blob(caller, kSamplesBlob), std::string("caller/blob/") + kSamplesBlob);
    loop_.interval = interval_from_record(caller);
  } catch (const CheckpointError& e) {
    // Every message names the file (the section readers name only the section).
    const std::string message = e.what();
    if (message.rfind(file_.string(), 0) == 0) throw;
    throw CheckpointError(fmt::format("{}: {}", file_.string(), message));
  }
  values_.emplace(io::parse_case(io::case_schema(), resolved_case_, file_.string() + " (its resolved case)"));

  const fs::path timeseries = timeseries_path(run_dir_);
  const std::uintmax_t size = fs::file_size(timeseries, error);
  if (error)
    throw InputError(
        fmt::format("{}: cannot continue the run: {} ({})", file_.string(), timeseries.string(), error.message()));
  if (size < timeseries_bytes_)
    throw InputError(
        fmt::format("{}: cannot continue the run: {} holds {} bytes, fewer than the {} it held at the "
                    "checkpoint (rows before the checkpoint are missing)",
                    file_.string(), timeseries.string(), size, timeseries_bytes_));
  const auto record = checkpoint_->caller().blobs.find(kFingerprintBlob);
  check_fingerprint(record == checkpoint_->caller().blobs.end() ? nullptr : &record->second);
}

// The run's files against the checkpoint's record of them (RunCheckpoints): a checkpoint copied
// from another run, a time series edited or a mesh replaced is refused before anything changes.
void RestartPoint::check_fingerprint(const std::vector<std::byte>* record) {
  const fs::path timeseries = timeseries_path(run_dir_);
  series_ = {timeseries_bytes_, crc32_of_file(timeseries, 0, timeseries_bytes_)};
  if (record == nullptr) {
    // Written before settle recorded the fingerprint (format version 3 without it): accepted,
    // since refusing would throw away a long run, but the user is told what was not checked.
    const io::CaseValues& values = *values_;
    if (values.has("particle.file")) inputs_ = {fingerprint_input_file(run_dir_, values.string("particle.file"))};
    warnings_.push_back(fmt::format(
        "{}: written by a settle that did not record the run's fingerprint, so this restart cannot check that {} "
        "and the input files in {} belong to it; continue only a directory you know is this run's",
        file_.string(), timeseries.string(), run_dir_.string()));
    return;
  }
  RunFingerprint stored;
  try {
    stored = fingerprint_from_record(*record);
  } catch (const CheckpointError& e) {
    throw CheckpointError(fmt::format("{}: {}", file_.string(), e.what()));
  }
  if (stored.series.bytes != series_.bytes || stored.series.crc32 != series_.crc32)
    throw CheckpointError(fmt::format(
        "{}: {} is not the time series this checkpoint belongs to: its first {} bytes have CRC-32 {:08x}, the "
        "checkpoint recorded {} (the directory holds another run's files, or the file was edited); restart a run "
        "from its own checkpoint",
        file_.string(), timeseries.string(), series_.bytes, series_.crc32,
        checksum_text(stored.series.bytes, stored.series.crc32)));
  for (const InputFileFingerprint& expected : stored.inputs) {
    const fs::path input = run_dir_ / expected.name;
    std::error_code error;
    if (!fs::is_regular_file(input, error))
      throw CheckpointError(fmt::format("{}: the run's input file {} is missing (the checkpoint recorded {})",
                                        file_.string(), input.string(), checksum_text(expected.bytes, expected.crc32)));
    const InputFileFingerprint found = fingerprint_input_file(run_dir_, expected.name);
    if (!(found == expected))
      throw CheckpointError(fmt::format(
          "{}: {} is not the input file this run started with: {}, where the checkpoint recorded {}; put the "
          "original back",
          file_.string(), input.string(), checksum_text(found.bytes, found.crc32),
          checksum_text(expected.bytes, expected.crc32)));
  }
  inputs_ = std::move(stored.inputs);
}

void RestartPoint::apply_overrides(const std::vector<std::string>& overrides) {
  if (overrides.empty()) return;
  for (const std::string& assignment : overrides) io::apply_override(*values_, assignment);
  const double end_time_s = values_->real(kRestartExtendableKey);
  if (!(end_time_s > time_si_))
    throw InputError(
        fmt::format("--set {}={}: the checkpoint {} is at t = {:.9g} s; a restart runs on to a later "
                    "end time",
                    kRestartExtendableKey, end_time_s, file_.string(), time_si_));
  resolved_case_ = io::rewrite_resolved_value(resolved_case_, *values_, kRestartExtendableKey);
}

void RestartPoint::restore(coupling::Simulation& sim) {
  if (!checkpoint_) throw std::logic_error("RestartPoint::restore: already restored");
  checkpoint_->restore(sim);
  checkpoint_.reset();  // gives back the mapping of the file (as large as the fluid)
}

// InterruptSignals

InterruptSignals::InterruptSignals() {
  g_stop_signal.store(0);
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  // Restart interrupted system calls (file writes): the loop polls the flag between steps.
  action.sa_flags = SA_RESTART;
  for (std::size_t i = 0; i < kStopSignals.size(); ++i) sigaction(kStopSignals[i], &action, &previous_[i]);
}

InterruptSignals::~InterruptSignals() {
  for (std::size_t i = 0; i < kStopSignals.size(); ++i) sigaction(kStopSignals[i], &previous_[i], nullptr);
}

bool InterruptSignals::raised() const { return g_stop_signal.load(std::memory_order_relaxed) != 0; }
int InterruptSignals::signal_number() const { return g_stop_signal.load(); }

int InterruptSignals::signal_number_seen_by_any(parallel::Communicator& ranks) const {
  // mpirun passes a signal on to its ranks at different moments, and the run loop stops them all
  // when one has it: the ranks that had not yet seen it must still name it (and exit with its status).
  const int mine = signal_number();
  std::vector<double> seen_here;
  for (const int s : kStopSignals) seen_here.push_back(mine == s ? 1.0 : 0.0);
  const std::vector<double> seen = parallel::sum_in_rank_order(ranks, seen_here);
  for (std::size_t i = 0; i < kStopSignals.size(); ++i)
    if (seen[i] > 0.0) return kStopSignals[i];
  return mine;
}

RunInterrupted interrupted_error(int signal_number, const coupling::RunResult& result, const fs::path& run_dir,
                                 const fs::path& checkpoint) {
  return RunInterrupted(
      fmt::format("run interrupted by {} at t = {:.6g} s (step {}): checkpoint written to {}; the run is not "
                  "finished, so no summary.json was written. Continue it with: settle run --restart {}",
                  signal_name(signal_number), result.simulated_time_si, result.steps, checkpoint.string(),
                  run_dir.string()),
      signal_number);
}

}  // namespace settle::app
