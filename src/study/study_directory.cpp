#include "study/study_directory.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace settle::study {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::ordered_json value_json(const io::Value& value) {
  return std::visit([](const auto& v) { return nlohmann::ordered_json(v); }, value);
}

nlohmann::ordered_json plan_json(const StudySpec& spec, const std::vector<StudyCase>& cases) {
  nlohmann::ordered_json plan;
  plan["study"] = spec.name;
  plan["study_file"] = spec.study_file.string();
  plan["base_case"] = spec.base_origin;
  nlohmann::ordered_json inputs = nlohmann::ordered_json::array();
  if (!cases.empty())
    for (const auto& input : cases.front().inputs) inputs.push_back(input.first);
  plan["inputs"] = inputs;
  plan["cases"] = nlohmann::ordered_json::array();
  for (const StudyCase& c : cases) {
    nlohmann::ordered_json entry;
    entry["index"] = c.index;
    entry["folder"] = case_folder(c.index);
    for (const auto& [name, value] : c.inputs) entry["inputs"][name] = value_json(value);
    plan["cases"].push_back(entry);
  }
  return plan;
}

// The first case whose case.toml in `dir` differs from `texts`, or -1 when they are all the same.
int first_difference(const fs::path& dir, const std::vector<std::string>& texts) {
  const nlohmann::ordered_json existing = read_plan(dir);
  if (existing["cases"].size() != texts.size()) return 0;
  for (std::size_t i = 0; i < texts.size(); ++i)
    if (read_text(dir / case_folder(static_cast<int>(i)) / "case.toml") != texts[i]) return static_cast<int>(i);
  return -1;
}

// A comment line stays one line: a control character in the study file's path becomes '?' (the
// study's name holds none: read_study refuses it). Ordinary text is kept byte for byte, so a
// directory prepared by an earlier build still holds "this study".
std::string one_line(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == '\x7f') c = '?';
  return text;
}

}  // namespace

std::string case_folder(int index) { return fmt::format("case_{:04d}", index); }

// A relative mesh path becomes absolute: the case file lives in the study directory, not beside
// the mesh.
std::string case_file_text(const StudySpec& spec, const StudyCase& c) {
  io::CaseValues values = c.values;
  if (values.has("particle.file")) {
    const fs::path mesh = values.string("particle.file");
    if (mesh.is_relative())
      values.set("particle.file", io::Value(fs::weakly_canonical(spec.base_directory / mesh).string()), "study");
  }
  return fmt::format("# Case {} of the study {} ({}): {}\n", c.index, spec.name, one_line(spec.study_file.string()),
                     describe_inputs(c.inputs)) +
         io::write_resolved_toml(values);
}

namespace {

std::vector<std::string> case_texts(const StudySpec& spec, const std::vector<StudyCase>& cases) {
  std::vector<std::string> texts;
  texts.reserve(cases.size());
  for (const StudyCase& c : cases) texts.push_back(case_file_text(spec, c));
  return texts;
}

// True when `dir` holds this study already (resume); InputError when it holds another.
bool holds_this_study(const fs::path& dir, const std::vector<std::string>& texts) {
  std::error_code error;
  if (!fs::exists(dir / "study.json", error)) return false;
  const int differs = first_difference(dir, texts);
  if (differs >= 0)
    throw InputError(fmt::format(
        "-o {}: holds another study (its case {} differs from this study's); choose another directory, or remove it",
        dir.string(), differs));
  return true;
}

}  // namespace

void check_study_directory(const StudySpec& spec, const std::vector<StudyCase>& cases, const fs::path& dir) {
  holds_this_study(dir, case_texts(spec, cases));
}

void prepare_study_directory(const StudySpec& spec, const std::vector<StudyCase>& cases, const fs::path& dir) {
  const std::vector<std::string> texts = case_texts(spec, cases);
  if (holds_this_study(dir, texts)) return;  // the same study: resume
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(fmt::format("-o: cannot create the directory {}: {}", dir.string(), error.message()));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path case_dir = dir / case_folder(cases[i].index);
    fs::create_directories(case_dir, error);
    if (error) throw InputError(fmt::format("-o: cannot create {}: {}", case_dir.string(), error.message()));
    write_file_atomically(case_dir / "case.toml", texts[i]);
  }
  // Last: a directory with study.json is complete, so an interrupted preparation starts again.
  write_file_atomically(dir / "study.json", plan_json(spec, cases).dump(2) + "\n");
}

nlohmann::ordered_json read_plan(const fs::path& dir) {
  const fs::path file = dir / "study.json";
  std::error_code error;
  if (!fs::is_regular_file(file, error))
    throw InputError(fmt::format("{}: no study.json (give the -o directory of `settle study run`)", dir.string()));
  try {
    return nlohmann::ordered_json::parse(read_text(file));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not readable JSON ({})", file.string(), e.what()));
  }
}

std::string_view to_string(CaseState state) {
  switch (state) {
    case CaseState::pending:
      return "pending";
    case CaseState::running:
      return "running";
    case CaseState::done:
      return "done";
    case CaseState::failed:
      return "failed";
    case CaseState::interrupted:
      return "interrupted";
  }
  return "pending";
}

CaseStatus read_case_status(const fs::path& case_dir) {
  CaseStatus status;
  std::error_code error;
  if (!fs::is_regular_file(case_dir / "status.json", error)) return status;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_text(case_dir / "status.json"));
  } catch (const nlohmann::json::exception&) {
    status.state = CaseState::interrupted;  // a status cut short: run the case again
    return status;
  }
  const std::string state = j.value("state", "pending");
  for (CaseState s : {CaseState::running, CaseState::done, CaseState::failed, CaseState::interrupted})
    if (state == to_string(s)) status.state = s;
  status.exit_status = j.value("exit_status", 0);
  status.wall_seconds = j.value("wall_seconds", 0.0);
  status.attempts = j.value("attempts", 0);
  // A done case without its summary is not done (its folder was tampered with).
  if (status.state == CaseState::done && !fs::is_regular_file(case_dir / "summary.json", error))
    status.state = CaseState::interrupted;
  return status;
}

void write_case_status(const fs::path& case_dir, const CaseStatus& status) {
  nlohmann::ordered_json j;
  j["state"] = to_string(status.state);
  j["exit_status"] = status.exit_status;
  j["wall_seconds"] = status.wall_seconds;
  j["attempts"] = status.attempts;
  write_file_atomically(case_dir / "status.json", j.dump(2) + "\n");
}

}  // namespace settle::study
