#pragma once
// A study's output directory (docs/studies.md, "The study directory"): study.json (the plan: every
// case's folder and inputs), one folder per case with its case.toml, and each case's status.json
// as its run goes. Written before anything runs; a second `settle study run` on the same directory
// resumes it, and refuses a directory that holds a different study.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/study_spec.hpp"

namespace settle::study {

/// The folder of case `index` inside the study directory ("case_0007").
std::string case_folder(int index);

/// The text of a case's case.toml: a comment line naming the case, the study and its inputs, then
/// the case resolved (io::write_resolved_toml), a relative mesh path made absolute; `settle run`
/// reads it back to the case's values.
std::string case_file_text(const StudySpec& spec, const StudyCase& c);

/// Reads `dir` (changes nothing): settle::InputError when it holds another study (a case.toml that
/// differs from this study's), naming the first case that differs.
void check_study_directory(const StudySpec& spec, const std::vector<StudyCase>& cases,
                           const std::filesystem::path& dir);

/// Writes the plan and each case's case.toml into `dir` (created when missing). When `dir` already
/// holds a study, its cases must be the same (case.toml byte for byte): settle::InputError
/// otherwise, naming the first that differs, and nothing is written.
void prepare_study_directory(const StudySpec& spec, const std::vector<StudyCase>& cases,
                             const std::filesystem::path& dir);

/// study.json of a prepared directory. settle::InputError when `dir` holds none.
nlohmann::ordered_json read_plan(const std::filesystem::path& dir);

/// What became of one case's run, as status.json records it.
enum class CaseState { pending, running, done, failed, interrupted };
std::string_view to_string(CaseState state);

struct CaseStatus {
  CaseState state = CaseState::pending;
  int exit_status = 0;
  double wall_seconds = 0.0;
  int attempts = 0;
};

/// A case's status.json (pending when there is none). A case whose status says done but whose
/// summary.json is missing counts as interrupted: its results are not all there. "running" is what
/// a study killed outright leaves behind as well as a live run's state.
CaseStatus read_case_status(const std::filesystem::path& case_dir);
void write_case_status(const std::filesystem::path& case_dir, const CaseStatus& status);

}  // namespace settle::study
