#include "app/earlier_run.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/run_checkpoints.hpp"
#include "common/atomic_file.hpp"
#include "common/checkpoint_file.hpp"
#include "common/error.hpp"
#include "coupling/checkpoint_state.hpp"
#include "io/output_files.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

// Larger files are not settle's summary or resolved case (those are kilobytes), and are not read.
constexpr std::uintmax_t kMaxTextBytes = 64u << 20;
constexpr std::string_view kVtkSignature = "<?xml version=\"1.0\"?>\n<VTKFile ";

std::optional<std::string> small_text(const fs::path& file) {
  std::error_code error;
  if (!fs::is_regular_file(fs::symlink_status(file, error)) || fs::file_size(file, error) > kMaxTextBytes)
    return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool settle_summary(const fs::path& file) {
  const std::optional<std::string> text = small_text(file);
  if (!text) return false;
  const nlohmann::json j = nlohmann::json::parse(*text, nullptr, false);
  return j.is_object() && j.contains("case") && j.contains("steps") && j.contains("stop_reason");
}

bool settle_timeseries(const fs::path& file) {
  std::error_code error;
  if (fs::is_regular_file(fs::symlink_status(file, error)) && fs::file_size(file, error) == 0) return true;
  const std::vector<std::string>& columns = io::timeseries_columns();
  std::string header;
  for (std::size_t i = 0; i < io::kContractColumnCount; ++i) header += (i ? "," : "") + columns[i];
  return file_starts_with(file, header);
}

// timeseries.json: the sidecar of timeseries.csv (io::timeseries_sidecar_json).
bool settle_timeseries_sidecar(const fs::path& file) {
  const std::optional<std::string> text = small_text(file);
  if (!text) return false;
  const nlohmann::json j = nlohmann::json::parse(*text, nullptr, false);
  return j.is_object() && j.value("file", "") == "timeseries.csv" && j.contains("columns");
}

bool settle_resolved_case(const fs::path& file) {
  const std::optional<std::string> text = small_text(file);
  return text && text->find(std::string("\n") + kDerivedBlockTitle) != std::string::npos;
}

// An ASCII STL starts with "solid"; a binary one is 84 bytes and 50 per triangle its header counts.
bool stl_file(const fs::path& file) {
  if (file_starts_with(file, "solid")) return true;
  std::error_code error;
  if (!fs::is_regular_file(fs::symlink_status(file, error))) return false;
  const std::uintmax_t bytes = fs::file_size(file, error);
  std::ifstream in(file, std::ios::binary);
  std::array<char, 84> header{};
  if (error || !in.read(header.data(), header.size())) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, header.data() + 80, sizeof count);
  return bytes == 84u + 50u * static_cast<std::uintmax_t>(count);
}

// `prefix`, at least `digits` decimal digits, `suffix` (settle's numbered output names).
bool numbered(const std::string& name, std::string_view prefix, std::size_t digits, std::string_view suffix) {
  if (name.size() < prefix.size() + digits + suffix.size() || !name.starts_with(prefix) || !name.ends_with(suffix))
    return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()),
                     name.end() - static_cast<std::ptrdiff_t>(suffix.size()),
                     [](char c) { return c >= '0' && c <= '9'; });
}

std::string without_tmp(const std::string& name) {
  return name.ends_with(".tmp") ? name.substr(0, name.size() - 4) : name;
}

bool vtk_file_name(const std::string& name) {
  const std::string n = without_tmp(name);
  return n == "fluid.pvd" || n == "surface.pvd" || numbered(n, "fluid_", 6, ".vti") ||
         numbered(n, "fluid_", 6, ".pvti") || numbered(n, "surface_", 6, ".vtp");
}

bool vtk_file(const fs::path& file) { return file_starts_with(file, kVtkSignature, file.extension() == ".tmp"); }

[[noreturn]] void refuse(const fs::path& dir, const fs::path& entry, std::string_view what) {
  throw InputError(
      fmt::format("-o {}: {} is not {}; settle run writes there and would replace or remove it. Move it "
                  "away, or choose another -o directory",
                  dir.string(), entry.string(), what));
}

// A folder of pieces of one parallel frame (fluid_NNNNNN/piece_NNNNN.vti).
void survey_vtk_pieces(const fs::path& dir, const fs::path& folder, EarlierRun& earlier) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (!numbered(without_tmp(name), "piece_", 5, ".vti")) continue;  // not settle's name: left alone
    if (!vtk_file(entry.path())) refuse(dir, entry.path(), "a VTK file settle wrote");
    earlier.files.push_back(entry.path());
  }
  earlier.folders.push_back(folder);
}

void survey_vtk(const fs::path& dir, EarlierRun& earlier) {
  const fs::path vtk = dir / "vtk";
  std::error_code error;
  const fs::file_status status = fs::symlink_status(vtk, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) refuse(dir, vtk, "the folder of VTK files settle wrote");
  for (const auto& entry : fs::directory_iterator(vtk, error)) {
    const std::string name = entry.path().filename().string();
    if (numbered(name, "fluid_", 6, "") && fs::is_directory(entry.symlink_status(error))) {
      survey_vtk_pieces(dir, entry.path(), earlier);
    } else if (vtk_file_name(name)) {
      if (!vtk_file(entry.path())) refuse(dir, entry.path(), "a VTK file settle wrote");
      earlier.files.push_back(entry.path());
    }
  }
  earlier.folders.push_back(vtk);
}

bool exists_at(const fs::path& path) {
  std::error_code error;
  return fs::exists(fs::symlink_status(path, error));
}

constexpr std::array<std::string_view, 6> kPlotNames{"velocity.png",    "trajectory.png", "trajectory_3d.png",
                                                     "orientation.png", "forces.png",     "reference.png"};
constexpr std::string_view kPngSignature = "\x89PNG\r\n\x1a\n";

void survey_plots(const fs::path& dir, EarlierRun& earlier) {
  const fs::path plots = dir / "plots";
  std::error_code error;
  const fs::file_status status = fs::symlink_status(plots, error);
  if (!fs::exists(status) || !fs::is_directory(status)) return;  // a file of the user's: settle writes no plots/ file
  for (const std::string_view name : kPlotNames) {
    const fs::path file = plots / name;
    if (!exists_at(file)) continue;
    if (!file_starts_with(file, kPngSignature)) refuse(dir, file, "a PNG figure settle plot wrote");
    earlier.files.push_back(file);
    earlier.results.push_back("plots/" + std::string(name));
  }
  earlier.folders.push_back(plots);
}

void survey_log(const fs::path& dir, EarlierRun& earlier) {
  const fs::path log = dir / kRunLogFileName;
  if (!exists_at(log) || is_standard_error(log)) return;
  std::error_code error;
  const bool empty = fs::is_regular_file(fs::symlink_status(log, error)) && fs::file_size(log, error) == 0;
  if (!empty && !file_starts_with(log, "settle run: ")) refuse(dir, log, "the log settle run wrote");
  earlier.files.push_back(log);
  earlier.results.emplace_back(kRunLogFileName);
}

void add_result(EarlierRun& earlier, const fs::path& file) {
  if (exists_at(file)) earlier.results.push_back(file.filename().string());
}

}  // namespace

bool is_standard_error(const fs::path& file) {
  struct stat err {};
  struct stat other {};
  return ::fstat(STDERR_FILENO, &err) == 0 && ::stat(file.c_str(), &other) == 0 && err.st_dev == other.st_dev &&
         err.st_ino == other.st_ino;
}

std::string mesh_copy_name(const fs::path& source) { return "particle_mesh" + source.extension().string(); }

EarlierRun survey_earlier_run(const fs::path& dir, const std::string& mesh_copy) {
  EarlierRun earlier;
  if (!exists_at(dir)) return earlier;
  const fs::path summary = dir / "summary.json";
  if (exists_at(summary)) {
    if (!settle_summary(summary)) refuse(dir, summary, "a summary settle run wrote");
    earlier.files.push_back(summary);
  }
  const fs::path timeseries = dir / "timeseries.csv";
  if (exists_at(timeseries) && !settle_timeseries(timeseries))
    refuse(dir, timeseries, "a time series settle run wrote (its header t,x,y,z,...)");
  const fs::path sidecar = io::timeseries_sidecar_path(timeseries);
  if (exists_at(sidecar) && !settle_timeseries_sidecar(sidecar))
    refuse(dir, sidecar, "the column list settle run writes beside timeseries.csv");
  const fs::path resolved = dir / "case.resolved.toml";
  if (exists_at(resolved) && !settle_resolved_case(resolved)) refuse(dir, resolved, "a resolved case settle run wrote");
  const fs::path checkpoint = dir / kCheckpointFileName;
  if (exists_at(checkpoint)) {
    if (!is_checkpoint_file(checkpoint)) refuse(dir, checkpoint, "a settle checkpoint (no SETTLECK signature)");
    earlier.files.push_back(checkpoint);
  }
  const fs::path temporary = dir / (std::string(kCheckpointFileName) + ".tmp");
  if (exists_at(temporary)) {
    if (!is_checkpoint_file(temporary, true)) refuse(dir, temporary, "a settle checkpoint being written");
    earlier.files.push_back(temporary);
  }
  if (const auto foreign = coupling::foreign_entry_in_parts(checkpoint))
    refuse(dir, *foreign, "a part of a settle checkpoint (step-NNNNNNNNNNNN/rank-NNNNN.bin)");
  earlier.checkpoint = checkpoint;
  if (!mesh_copy.empty() && exists_at(dir / mesh_copy) && !stl_file(dir / mesh_copy))
    refuse(dir, dir / mesh_copy, "an STL file (a run with a mesh keeps its copy under this name)");
  survey_vtk(dir, earlier);
  for (const fs::path& file : {summary, timeseries, resolved, checkpoint}) add_result(earlier, file);
  if (earlier.files.end() != std::find_if(earlier.files.begin(), earlier.files.end(), [](const fs::path& f) {
        return f.parent_path().filename() == "vtk" || f.parent_path().parent_path().filename() == "vtk";
      }))
    earlier.results.emplace_back("vtk/");
  survey_plots(dir, earlier);
  survey_log(dir, earlier);
  return earlier;
}

EarlierRun survey_restarted_run(const fs::path& dir) {
  EarlierRun earlier;
  const fs::path summary = dir / "summary.json";
  if (exists_at(summary)) {
    if (!settle_summary(summary)) refuse(dir, summary, "a summary settle run wrote");
    earlier.files.push_back(summary);
  }
  const fs::path resolved = dir / "case.resolved.toml";
  if (exists_at(resolved) && !settle_resolved_case(resolved)) refuse(dir, resolved, "a resolved case settle run wrote");
  return earlier;
}

void remove_earlier_run(const EarlierRun& earlier) {
  for (const fs::path& file : earlier.files) {
    std::error_code error;
    fs::remove(file, error);
    if (error)
      throw InputError(fmt::format("-o: cannot remove the earlier run's {}: {}", file.string(), error.message()));
  }
  // The parts of a checkpoint written across processes (the survey refused any entry not settle's).
  if (!earlier.checkpoint.empty()) coupling::remove_checkpoint_parts(earlier.checkpoint);
  for (const fs::path& folder : earlier.folders) {
    std::error_code ignored;
    fs::remove(folder, ignored);  // only when empty: other files stay, and their folder with them
  }
}

}  // namespace settle::app
