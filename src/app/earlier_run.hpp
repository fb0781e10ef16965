#pragma once
// What a fresh `settle run` into DIR does with the files an earlier run left there (docs/errors.md,
// "Promises": nothing the user wrote is ever deleted). A run replaces or removes a file only when
// it recognises it as settle's by its format; a file or folder of the user's where the run would
// write is a refusal (exit status 2) before anything in DIR changes, never a deletion:
//  - summary.json: JSON with the keys settle run writes (case, steps, stop_reason); removed at
//    the start (it marks a finished run);
//  - timeseries.csv: empty, or starting with its contract header (t,x,y,z,...); replaced;
//  - timeseries.json: JSON naming "file": "timeseries.csv" and its "columns"; replaced;
//  - case.resolved.toml: holding the derived block settle run appends; replaced;
//  - checkpoint.bin and checkpoint.bin.tmp: a checkpoint's signature (SETTLECK; the .tmp may be cut
//    before it); removed;
//  - checkpoint.bin.parts/: only step-NNNNNNNNNNNN/rank-NNNNN.bin parts with that signature;
//    removed;
//  - vtk/: its files of settle's names (fluid.pvd, surface.pvd, fluid_NNNNNN.vti or .pvti and its
//    folder of pieces, surface_NNNNNN.vtp, and their .tmp) must be VTK XML; they are removed, and
//    vtk/ when it is left empty. Files of other names in vtk/ are left alone;
//  - the mesh copy particle_mesh.<ext>, which a run with a mesh overwrites: an STL file;
//  - plots/: the PNG files of settle plot's names (velocity.png, ...) with the PNG signature;
//    removed, and plots/ when it is left empty;
//  - run.log: the console's log, starting with "settle run: "; removed (left alone when it is the
//    file this process's stderr writes, as under settle study, which appends a case's attempts).
// A fresh run finds these as an earlier run's results and refuses the directory unless --overwrite.
#include <filesystem>
#include <string>
#include <vector>

namespace settle::app {

/// The earlier run's files that a fresh run removes, in the order to remove them (files before the
/// folders that hold them; a folder goes only when it is empty then).
struct EarlierRun {
  std::vector<std::filesystem::path> files;
  std::vector<std::filesystem::path> folders;
  std::filesystem::path checkpoint;  ///< whose parts (coupling::checkpoint_parts_directory) go too
  /// The earlier run's results found (summary.json, timeseries.csv, ..., vtk/, plots/): a fresh
  /// run refuses the directory unless --overwrite (a rerun never mixes with another run's files).
  std::vector<std::string> results;
};

/// The title of the block of derived numbers settle run appends to case.resolved.toml (and by
/// which it recognises that file as its own).
inline constexpr const char* kDerivedBlockTitle = "# [derived] chosen by settle run";

/// Reads `dir` (changes nothing; an absent `dir` has no earlier run). `mesh_copy_name` is the
/// mesh copy the run writes (empty without a mesh). settle::InputError naming the first entry that
/// is in the run's way but not settle's, and saying how to proceed.
EarlierRun survey_earlier_run(const std::filesystem::path& dir, const std::string& mesh_copy_name);

/// The log settle run keeps in every run directory.
inline constexpr const char* kRunLogFileName = "run.log";

/// True when `file` is the file this process's stderr writes (settle study sends a case's console
/// to its run.log).
bool is_standard_error(const std::filesystem::path& file);

/// The same for `settle run --restart DIR`, which continues the files of DIR: summary.json (removed:
/// the continued run is not finished) and case.resolved.toml (rewritten from the checkpoint) must
/// be settle's.
EarlierRun survey_restarted_run(const std::filesystem::path& dir);

/// Removes what survey_earlier_run or survey_restarted_run found. settle::InputError naming a file that cannot be removed.
void remove_earlier_run(const EarlierRun& earlier);

/// The name of the copy a run keeps of the mesh file `source`: particle_mesh with its extension.
std::string mesh_copy_name(const std::filesystem::path& source);

}  // namespace settle::app
