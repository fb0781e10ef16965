#pragma once
// ParaView data collections (.pvd) that list a run's VTK files (vtk.hpp) in time. Format: the
// Collection file of the VTK XML formats ("VTK File Formats", VTK documentation).
#include <filesystem>
#include <string>
#include <vector>

namespace settle::io {

/// A ParaView data collection (.pvd): a list of (time, file) that ParaView plays as a time
/// series. Every add() rewrites the whole .pvd atomically, so a run that stops at any moment
/// leaves a valid collection of the files written so far.
class PvdCollection {
 public:
  struct Entry {
    double time_si = 0.0;
    std::string file;  ///< as written in the .pvd: relative to the .pvd's directory
  };

  /// An empty collection at `pvd_path`; nothing is written until the first add().
  explicit PvdCollection(std::filesystem::path pvd_path);

  /// Continues a collection after a restart: reads the entries of an existing .pvd written by
  /// this class, keeps those with time <= keep_until_time_si (later ones belong to the part of
  /// the run that is being redone) and rewrites the file when it dropped any. A missing file
  /// gives an empty collection. A file that is not such a collection raises settle::InputError.
  static PvdCollection resume(std::filesystem::path pvd_path, double keep_until_time_si);

  /// Appends an entry and rewrites the .pvd. `file` is the data file's path as the program
  /// opens it (absolute or relative to the working directory: the path given to the writer); it
  /// is stored relative to the .pvd's directory, so the output folder can be moved. Times must
  /// increase strictly (std::invalid_argument otherwise).
  void add(double time_si, const std::filesystem::path& file);

  const std::vector<Entry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void rewrite() const;

  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

}  // namespace settle::io
