#include "study/study_spec.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/error.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "study/derived_inputs.hpp"

// GCC 12 reports the moves of io::Value (a std::variant holding a std::vector) in this file as
// maybe uninitialised and as oversized copies: known false positives of its inliner diagnostics.
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wstringop-overflow"
#endif

namespace settle::study {
namespace {

namespace fs = std::filesystem;

// A study of more cases than this is almost surely a typo in a range (a step of 0.001 for 0.1).
constexpr std::size_t kMaxCases = 100000;

std::string node_text(const toml::node& node) {
  std::ostringstream out;
  node.visit([&](auto&& n) { out << n; });
  return out.str();
}

// A TOML value as an io::Value; false for what no case key holds (tables, mixed arrays). An out
// parameter rather than std::optional<io::Value>, whose move GCC 12 warns about wrongly.
bool to_value(const toml::node& node, io::Value& out) {
  if (auto b = node.value_exact<bool>()) return out = *b, true;
  if (auto i = node.value_exact<std::int64_t>()) return out = *i, true;
  if (auto d = node.value_exact<double>()) return out = *d, true;
  if (auto s = node.value_exact<std::string>()) return out = *s, true;
  const toml::array* a = node.as_array();
  if (a == nullptr) return false;
  std::vector<double> numbers;
  for (const toml::node& element : *a) {
    const auto number = element.value<double>();  // integers too
    if (!number) return false;
    numbers.push_back(*number);
  }
  out = std::move(numbers);
  return true;
}

double number(const toml::table& range, std::string_view key, std::string_view where) {
  const auto v = range[key].value<double>();
  if (!v || !std::isfinite(*v)) throw InputError(fmt::format("{}.{}: expected a finite number", where, key));
  return *v;
}

bool all_integers(const toml::table& range) {
  for (auto&& [key, node] : range)
    if (key.str() != "spacing" && key.str() != "count" && !node.is_integer()) return false;
  return true;
}

// { from, to, step } or { from, to, count [, spacing = "linear" | "log"] }: the end points included.
std::vector<io::Value> expand_range(const toml::table& range, const std::string& where) {
  for (auto&& [key, node] : range)
    if (key.str() != "from" && key.str() != "to" && key.str() != "step" && key.str() != "count" &&
        key.str() != "spacing")
      throw InputError(fmt::format("{}: unknown key '{}' in a range (allowed: from, to, step, or count and spacing)",
                                   where, key.str()));
  const double from = number(range, "from", where), to = number(range, "to", where);
  const bool has_step = range.contains("step"), has_count = range.contains("count");
  if (has_step == has_count) throw InputError(fmt::format("{}: a range needs either step or count, not both", where));
  std::vector<double> points;
  if (has_step) {
    if (range.contains("spacing")) throw InputError(fmt::format("{}.spacing: goes with count, not step", where));
    const double step = number(range, "step", where);
    if (!(step > 0.0)) throw InputError(fmt::format("{}.step: {} is not > 0", where, step));
    if (to < from) throw InputError(fmt::format("{}: to = {} is below from = {}", where, to, from));
    const double intervals = (to - from) / step;
    if (intervals > kMaxCases) throw InputError(fmt::format("{}: more than {} values", where, kMaxCases));
    // A step that divides the interval up to round-off reaches `to` exactly.
    const auto n = static_cast<long>(std::floor(intervals + 1e-9));
    for (long i = 0; i <= n; ++i) points.push_back(from + static_cast<double>(i) * step);
  } else {
    const auto count = range["count"].value_exact<std::int64_t>();
    if (!count || *count < 1 || *count > static_cast<std::int64_t>(kMaxCases))
      throw InputError(fmt::format("{}.count: expected an integer in [1, {}]", where, kMaxCases));
    const std::string spacing = range["spacing"].value_or(std::string("linear"));
    if (spacing != "linear" && spacing != "log")
      throw InputError(fmt::format("{}.spacing: \"{}\" is not one of \"linear\", \"log\"", where, spacing));
    if (spacing == "log" && !(from > 0.0 && to > 0.0))
      throw InputError(fmt::format("{}: a log range needs from and to > 0", where));
    for (std::int64_t i = 0; i < *count; ++i) {
      const double f = *count == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(*count - 1);
      points.push_back(spacing == "log" ? from * std::pow(to / from, f) : from + f * (to - from));
    }
  }
  std::vector<io::Value> values;
  const bool integral = has_step && all_integers(range);
  for (double p : points)
    values.push_back(integral ? io::Value(static_cast<std::int64_t>(std::llround(p))) : io::Value(p));
  return values;
}

Variation read_variation(const std::string& name, const toml::node& node, const std::string& where) {
  Variation v{name, {}};
  if (const toml::table* range = node.as_table()) {
    v.values = expand_range(*range, where);
  } else if (const toml::array* list = node.as_array()) {
    for (const toml::node& element : *list) {
      io::Value value;
      if (!to_value(element, value))
        throw InputError(fmt::format("{}: {} is not a value a case key takes", where, node_text(element)));
      v.values.push_back(std::move(value));
    }
  } else {
    throw InputError(
        fmt::format("{} = {}: expected a list of values ([a, b, ...]) or a range ({{ from, to, step }} "
                    "or {{ from, to, count }})",
                    where, node_text(node)));
  }
  if (v.values.empty()) throw InputError(fmt::format("{}: no values", where));
  return v;
}

bool is_range(const toml::table& t) { return t.contains("from") || t.contains("to"); }

// [vary]: dotted case keys (nested tables in TOML) and derived inputs, each a list or a range.
void read_vary(const toml::table& table, const std::string& prefix, const std::string& origin,
               std::vector<std::pair<toml::source_position, Variation>>& out) {
  for (auto&& [key, node] : table) {
    const std::string name = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    const std::string where = fmt::format("{}: vary.{}", origin, name);
    const toml::table* sub = node.as_table();
    if (sub && !is_range(*sub)) {
      read_vary(*sub, name, origin, out);
      continue;
    }
    if (!is_derived_input(name) && io::case_schema().find(name) == nullptr) {
      std::string message = fmt::format("{}: not a case key nor a derived input ({})", where, derived_input_names());
      if (auto close = io::case_schema().suggest(name)) message += fmt::format("; did you mean {}?", *close);
      throw InputError(message);
    }
    Variation variation = read_variation(name, node, where);
    out.emplace_back(node.source().begin, std::move(variation));
  }
}

void check_known_keys(const toml::table& table, std::initializer_list<std::string_view> allowed,
                      const std::string& where) {
  for (auto&& [key, node] : table)
    if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end()) {
      std::string list;
      for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      throw InputError(fmt::format("{}: unknown key '{}' (allowed: {})", where, key.str(), list));
    }
}

void read_base(const toml::table& root, const fs::path& file, StudySpec& spec) {
  const std::string origin = file.string();
  const toml::node* path = root.at_path("study.base").node();
  const toml::table* inline_base = root["base"].as_table();
  if ((path != nullptr) == (inline_base != nullptr))
    throw InputError(
        fmt::format("{}: give the base case either as study.base = \"CASE.toml\" (a path relative to "
                    "the study file) or as a [base] table, not {}",
                    origin, path ? "both" : "neither"));
  if (path) {
    const auto relative = path->value<std::string>();
    if (!relative) throw InputError(fmt::format("{}: study.base: expected a path (a string)", origin));
    const fs::path base_file = fs::weakly_canonical(file.parent_path() / *relative);
    spec.base_case_text = io::read_toml_file(base_file, "case file");
    spec.base_origin = base_file.string();
    spec.base_directory = base_file.parent_path();
  } else {
    std::ostringstream text;
    text << toml::toml_formatter(*inline_base);
    spec.base_case_text = text.str();
    spec.base_origin = origin + " [base]";
    spec.base_directory = file.parent_path();
  }
}

// The name heads each case.toml and the Slurm script in a comment line, and names the Slurm job: a
// control character (a newline) there made every case.toml unreadable and put the rest of the
// name into the script as a command.
void read_name(const toml::table& root, const fs::path& file, StudySpec& spec) {
  const std::string origin = file.string();
  const toml::node* node = root.at_path("study.name").node();
  if (node && !node->is_string())
    throw InputError(fmt::format("{}: study.name = {}: expected a string", origin, node_text(*node)));
  spec.name = node ? *node->value<std::string>() : file.stem().string();
  if (std::any_of(spec.name.begin(), spec.name.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == '\x7f'; }))
    throw InputError(fmt::format("{}: {} {}: holds a control character; a study's name is one line of text", origin,
                                 node ? "study.name =" : "the study's name (the file's stem, no study.name given)",
                                 io::to_toml(io::Value(spec.name))));
}

void read_orientations(const toml::table& root, const std::string& origin, StudySpec& spec) {
  const toml::table* t = root["orientations"].as_table();
  if (!t) return;
  check_known_keys(*t, {"count", "seed"}, origin + ": [orientations]");
  const auto count = (*t)["count"].value_exact<std::int64_t>();
  const auto seed = (*t)["seed"].value_exact<std::int64_t>();
  if (!count || *count < 1 || *count > static_cast<std::int64_t>(kMaxCases))
    throw InputError(fmt::format("{}: orientations.count: expected an integer in [1, {}]", origin, kMaxCases));
  if (!seed || *seed < 0) throw InputError(fmt::format("{}: orientations.seed: expected an integer >= 0", origin));
  spec.orientations = {static_cast<int>(*count), static_cast<std::uint64_t>(*seed)};
}

// A value of the study as the case key's kind wants it (an integer list for a real key is fine).
io::Value as_kind(const io::Value& v, io::Kind kind) {
  if (kind == io::Kind::Real && std::holds_alternative<std::int64_t>(v))
    return io::Value(static_cast<double>(std::get<std::int64_t>(v)));
  if (kind == io::Kind::Integer && std::holds_alternative<double>(v)) {
    const double d = std::get<double>(v);
    if (d == std::floor(d) && std::abs(d) < 9.0e15) return io::Value(static_cast<std::int64_t>(d));
  }
  return v;
}

double as_number(const io::Value& v, std::string_view name) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  throw InputError(fmt::format("vary.{}: expected numbers", name));
}

// Case keys first, in the file's order, then the derived inputs, which read them (galileo sets the
// viscosity that reynolds reads, reynolds the speed that travel_diameters reads; incidence turns
// the attitude the case or an ensemble gave; the window inputs last, on the body and the
// direction of travel that are then final).
int derived_rank(std::string_view name) {
  if (name == "galileo") return 1;
  if (name == "reynolds") return 2;
  if (name == "incidence_deg") return 3;
  if (name == "travel_diameters") return 4;  // reads the speed reynolds set
  if (is_window_input(name)) return 5;
  return 0;
}

io::CaseValues build_case(const StudySpec& spec, const io::CaseValues& base,
                          const std::vector<std::pair<std::string, io::Value>>& inputs,
                          const std::optional<Eigen::Quaterniond>& attitude) {
  io::CaseValues values = base;
  std::vector<const std::pair<std::string, io::Value>*> ordered;
  for (const auto& input : inputs) ordered.push_back(&input);
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](auto* a, auto* b) { return derived_rank(a->first) < derived_rank(b->first); });
  const std::string origin = spec.study_file.string() + " [vary]";
  if (attitude) set_attitude(values, *attitude);
  for (const auto* input : ordered)
    if (input->first != kOrientationInput && !is_derived_input(input->first))
      values.set(input->first, as_kind(input->second, io::case_schema().find(input->first)->kind), origin);
  // After the case keys, as `settle run` applies it after --set: a varied fluid.temperature or
  // fluid.preset must change the fluid (applied to the base before them, every case kept the
  // base's density and viscosity); before the derived inputs, which read them.
  io::apply_fluid_preset(values);
  for (const auto* input : ordered)
    if (is_derived_input(input->first))
      set_derived_input(values, input->first, as_number(input->second, input->first), spec.base_directory);
  return values;
}

void check_conflicts(const StudySpec& spec) {
  const auto varies = [&](std::string_view name) {
    return std::any_of(spec.variations.begin(), spec.variations.end(),
                       [&](const Variation& v) { return v.name == name; });
  };
  const std::string origin = spec.study_file.string();
  if (varies("reynolds") && varies("particle.towing_velocity"))
    throw InputError(fmt::format("{}: vary.reynolds sets particle.towing_velocity, which is varied too", origin));
  if (varies("travel_diameters") && varies("run.end_time"))
    throw InputError(fmt::format("{}: vary.travel_diameters sets run.end_time, which is varied too", origin));
  if (varies("galileo") && varies("fluid.dynamic_viscosity"))
    throw InputError(fmt::format("{}: vary.galileo sets fluid.dynamic_viscosity, which is varied too", origin));
  const bool varies_window = std::any_of(spec.variations.begin(), spec.variations.end(),
                                         [](const Variation& v) { return is_window_input(v.name); });
  if (varies_window && (varies("domain.size") || varies("particle.position")))
    throw InputError(fmt::format(
        "{}: the window inputs (domain_*_diameters) set domain.size and particle.position, which are varied too",
        origin));
  if (spec.orientations.count > 0 && varies("particle.euler"))
    throw InputError(fmt::format("{}: [orientations] sets particle.euler, which is varied too", origin));
  for (std::size_t i = 0; i < spec.variations.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (spec.variations[i].name == spec.variations[j].name)
        throw InputError(fmt::format("{}: vary.{} is given twice", origin, spec.variations[i].name));
}

}  // namespace

StudySpec read_study(const fs::path& study_file) {
  return parse_study(io::read_toml_file(study_file, "study file"), study_file);
}

StudySpec parse_study(std::string_view text, const fs::path& study_file) {
  StudySpec spec;
  spec.study_file = fs::absolute(study_file);
  const std::string origin = study_file.string();
  toml::table root;
  try {
    root = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", origin, where.line, where.column, e.description()));
  }
  check_known_keys(root, {"study", "base", "vary", "orientations"}, origin);
  if (const toml::table* study = root["study"].as_table())
    check_known_keys(*study, {"name", "base"}, origin + ": [study]");
  read_name(root, study_file, spec);
  read_base(root, spec.study_file, spec);
  if (const toml::table* vary = root["vary"].as_table()) {
    std::vector<std::pair<toml::source_position, Variation>> found;
    read_vary(*vary, "", origin, found);
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& f : found) spec.variations.push_back(std::move(f.second));
  }
  read_orientations(root, origin, spec);
  if (spec.variations.empty() && spec.orientations.count == 0)
    throw InputError(fmt::format("{}: nothing to vary: give a [vary] table or [orientations]", origin));
  check_conflicts(spec);
  return spec;
}

std::string describe_inputs(const std::vector<std::pair<std::string, io::Value>>& inputs) {
  std::string text;
  for (const auto& [name, value] : inputs) text += (text.empty() ? "" : ", ") + name + " = " + io::to_toml(value);
  return text;
}

std::vector<StudyCase> expand(const StudySpec& spec) {
  // The fluid preset is applied to each case (build_case), not to the base.
  const io::CaseValues base = io::parse_case(io::case_schema(), spec.base_case_text, spec.base_origin);
  std::size_t total = spec.orientations.count > 0 ? static_cast<std::size_t>(spec.orientations.count) : 1;
  for (const Variation& v : spec.variations) {
    total *= v.values.size();
    if (total > kMaxCases) throw InputError(fmt::format("{}: more than {} cases", spec.study_file.string(), kMaxCases));
  }
  const std::vector<Eigen::Quaterniond> rotations = uniform_rotations(spec.orientations.count, spec.orientations.seed);
  std::vector<StudyCase> cases;
  cases.reserve(total);
  for (std::size_t index = 0; index < total; ++index) {
    // Mixed radix: the orientation varies fastest, then the last [vary] entry.
    std::size_t rest = index;
    std::optional<Eigen::Quaterniond> attitude;
    std::vector<std::pair<std::string, io::Value>> inputs(spec.variations.size());
    if (!rotations.empty()) {
      attitude = rotations[rest % rotations.size()];
      rest /= rotations.size();
    }
    for (std::size_t k = spec.variations.size(); k-- > 0;) {
      const Variation& v = spec.variations[k];
      inputs[k] = {v.name, v.values[rest % v.values.size()]};
      rest /= v.values.size();
    }
    if (attitude)
      inputs.emplace_back(kOrientationInput, io::Value(static_cast<std::int64_t>(index % rotations.size())));
    const std::string name = fmt::format("case_{:04d}", index);
    try {
      io::CaseValues values = build_case(spec, base, inputs, attitude);
      (void)io::simulation_setup(values, spec.base_directory, name);  // the set-up's own cross-key checks
      cases.push_back({static_cast<int>(index), std::move(inputs), std::move(values)});
    } catch (const InputError& e) {
      throw InputError(
          fmt::format("{}: case {} ({}): {}", spec.study_file.string(), index, describe_inputs(inputs), e.what()));
    }
  }
  return cases;
}

}  // namespace settle::study
