#include "study/study_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "study/coefficient_fit.hpp"
#include "study/grid_convergence.hpp"
#include "study/law_predictions.hpp"
#include "study/study_directory.hpp"
#include "study/study_spec.hpp"

namespace settle::study {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

constexpr const char* kCellsKey = "numerics.cells_per_diameter";
constexpr const char* kIncidenceKey = "incidence_deg";

// Figures whose grid convergence and ensemble statistics are reported.
const std::vector<std::string> kConvergedFigures{"drag_coefficient", "lift_coefficient", "torque_coefficient",
                                                 "terminal_velocity_m_s", "terminal_vertical_velocity_m_s"};
const std::vector<std::string> kEnsembleFigures{"terminal_velocity_m_s", "terminal_vertical_velocity_m_s",
                                                "path_angle_deg", "tilt_mean_deg", "drag_coefficient"};

constexpr const char* kHolzerSommerfeldColumn = "drag_coefficient_holzer_sommerfeld";

// The law at the run's Reynolds number, for a done towed or fixed body (null otherwise).
json law_drag(const fs::path& case_dir, const json& summary) {
  if (!summary.is_object() || !summary.contains("reynolds") || !summary["reynolds"].is_number()) return json();
  const std::optional<double> c =
      holzer_sommerfeld_drag_of_case(case_dir / "case.toml", summary["reynolds"].get<double>());
  return c ? json(*c) : json();
}

bool is_input(const StudyTable& t, const std::string& name) {
  return std::find(t.inputs.begin(), t.inputs.end(), name) != t.inputs.end();
}

json read_json(const fs::path& file) {
  std::error_code error;
  if (!fs::is_regular_file(file, error)) return json();
  std::ifstream in(file);
  try {
    return json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return json();
  }
}

std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    return s.find_first_of(",\"\n") == std::string::npos ? s : "\"" + s + "\"";  // quotes: none in our values
  }
  if (v.is_number_float()) return fmt::format("{}", v.get<double>());
  if (v.is_array()) {
    std::string s;
    for (const auto& e : v) {
      if (!s.empty()) s += ' ';
      s += csv_cell(e);
    }
    return s;
  }
  return v.dump();
}

// Rows grouped by every input except `varied` (as their JSON text), in the order first met.
std::vector<std::pair<json, std::vector<const json*>>> group_by_others(const StudyTable& t, const std::string& varied) {
  std::vector<std::pair<json, std::vector<const json*>>> groups;
  for (const json& row : t.rows) {
    json key = json::object();
    for (const auto& name : t.inputs)
      if (name != varied) key[name] = row[name];
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == key; });
    if (it == groups.end()) {
      groups.emplace_back(key, std::vector<const json*>{});
      it = groups.end() - 1;
    }
    it->second.push_back(&row);
  }
  return groups;
}

bool has_number(const json& row, const std::string& figure) {
  return row.value("status", "") == "done" && row.contains(figure) && row[figure].is_number() &&
         std::isfinite(row[figure].get<double>());
}

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(); }

json grid_convergence_json(const StudyTable& t) {
  json out = json::array();
  if (std::find(t.inputs.begin(), t.inputs.end(), kCellsKey) == t.inputs.end()) return out;
  for (const auto& [others, rows] : group_by_others(t, kCellsKey))
    for (const std::string& figure : kConvergedFigures) {
      std::vector<std::pair<double, double>> points;  // (cells per diameter, value), finest first
      for (const json* row : rows)
        if (has_number(*row, figure))
          points.emplace_back((*row)[kCellsKey].get<double>(), (*row)[figure].get<double>());
      std::sort(points.begin(), points.end(), [](auto& a, auto& b) { return a.first > b.first; });
      if (points.size() < 3 || points[2].first >= points[1].first || points[1].first >= points[0].first) continue;
      if (points[0].second == points[1].second && points[1].second == points[2].second)
        continue;  // an input, as a towed body's speed
      const GridConvergence g = grid_convergence({1.0 / points[0].first, 1.0 / points[1].first, 1.0 / points[2].first,
                                                  points[0].second, points[1].second, points[2].second});
      json entry;
      entry["inputs"] = others;
      entry["figure"] = figure;
      entry["cells_per_diameter"] = json::array({points[0].first, points[1].first, points[2].first});
      entry["values"] = json::array({points[0].second, points[1].second, points[2].second});
      entry["observed_order"] = optional_number(g.observed_order);
      entry["extrapolated"] = optional_number(g.extrapolated);
      entry["gci_fine"] = optional_number(g.gci_fine);
      entry["oscillatory"] = g.oscillatory;
      entry["order_confirmed"] = g.order_confirmed;
      out.push_back(entry);
    }
  return out;
}

template <class Fit>
json fit_json(const json& others, const char* figure, const char* form, const std::vector<double>& phi,
              const std::vector<double>& c, const Fit& fit) {
  json entry;
  entry["inputs"] = others;
  entry["figure"] = figure;
  entry["form"] = form;
  if constexpr (std::is_same_v<Fit, DragIncidenceFit>) {
    entry["coefficients"] = {{"C_D0", fit.c_0}, {"C_D90", fit.c_90}, {"a", fit.exponent}};
  } else {
    entry["coefficients"] = {{"A", fit.amplitude}, {"b1", fit.sin_exponent}, {"b2", fit.cos_exponent}};
  }
  entry["rms_residual"] = fit.rms_residual;
  entry["max_residual"] = fit.max_residual;
  entry["incidence_deg"] = phi;
  entry["values"] = c;
  return entry;
}

json coefficient_fits_json(const StudyTable& t) {
  json out = json::array();
  if (std::find(t.inputs.begin(), t.inputs.end(), kIncidenceKey) == t.inputs.end()) return out;
  for (const auto& group : group_by_others(t, kIncidenceKey)) {
    const json& others = group.first;
    const std::vector<const json*>& rows = group.second;  // a lambda may not capture a structured binding in clang 14
    const auto series = [&](const std::string& figure, std::vector<double>& phi, std::vector<double>& c) {
      for (const json* row : rows)
        if (has_number(*row, figure)) {
          const double p = (*row)[kIncidenceKey].get<double>();
          if (p >= 0.0 && p <= 90.0) phi.push_back(p), c.push_back((*row)[figure].get<double>());
        }
      return phi.size() >= 4;  // three parameters: a fourth point makes the residual mean something
    };
    std::vector<double> phi, c;
    if (series("drag_coefficient", phi, c))
      out.push_back(
          fit_json(others, "drag_coefficient", "C_D0 + (C_D90 - C_D0) sin^a(phi)", phi, c, fit_drag_incidence(phi, c)));
    for (const char* figure : {"lift_coefficient", "torque_coefficient"}) {
      phi.clear(), c.clear();
      if (series(figure, phi, c))
        out.push_back(fit_json(others, figure, "A sin^b1(phi) cos^b2(phi)", phi, c, fit_sin_cos(phi, c)));
    }
  }
  return out;
}

json ensembles_json(const StudyTable& t) {
  json out = json::array();
  if (std::find(t.inputs.begin(), t.inputs.end(), kOrientationInput) == t.inputs.end()) return out;
  for (const auto& [others, rows] : group_by_others(t, kOrientationInput)) {
    json entry;
    entry["inputs"] = others;
    entry["cases"] = rows.size();
    json figures = json::object();
    for (const std::string& figure : kEnsembleFigures) {
      std::vector<double> v;
      for (const json* row : rows)
        if (has_number(*row, figure)) v.push_back((*row)[figure].get<double>());
      if (v.empty()) continue;
      double mean = 0.0;
      for (double x : v) mean += x / static_cast<double>(v.size());
      double square = 0.0;
      for (double x : v) square += (x - mean) * (x - mean);
      const double spread = v.size() > 1 ? std::sqrt(square / static_cast<double>(v.size() - 1)) : 0.0;
      figures[figure] = {{"count", v.size()},
                         {"mean", mean},
                         {"standard_deviation", spread},
                         {"min", *std::min_element(v.begin(), v.end())},
                         {"max", *std::max_element(v.begin(), v.end())}};
    }
    entry["figures"] = figures;
    std::map<std::string, int> regimes;
    for (const json* row : rows)
      if ((*row).value("status", "") == "done" && (*row)["regime"].is_string())
        ++regimes[(*row)["regime"].get<std::string>()];
    entry["regimes"] = regimes;
    out.push_back(entry);
  }
  return out;
}

}  // namespace

const std::vector<FigureColumn>& figure_columns() {
  static const std::vector<FigureColumn> columns{
      {"reynolds", "/reynolds"},
      {"galileo", "/galileo"},
      {"drag_coefficient", "/drag_coefficient"},
      {"lift_coefficient", "/lift_coefficient"},
      {"torque_coefficient", "/torque_coefficient"},
      {"terminal_velocity_m_s", "/terminal_velocity"},
      {"terminal_vertical_velocity_m_s", "/terminal_vertical_velocity"},
      // Free bodies: the mean over the averaging window, the terminal one only when reached (the
      // two columns above are empty otherwise).
      {"late_mean_velocity_m_s", "/late_mean_velocity"},
      {"late_mean_vertical_velocity_m_s", "/late_mean_vertical_velocity"},
      {"path_angle_deg", "/lateral/path_angle_deg"},
      {"lateral_amplitude_m", "/lateral/amplitude"},
      {"tilt_mean_deg", "/tilt/mean_deg"},
      {"tilt_amplitude_deg", "/tilt/amplitude_deg"},
      {"regime", "/regime"},
      {"terminal_state_reached", "/terminal_state/reached"},
      {"simulated_time_s", "/simulated_time"},
      {"steps", "/steps"},
  };
  return columns;
}

StudyTable collect_table(const fs::path& dir) {
  const json plan = read_plan(dir);
  StudyTable table;
  table.study = plan["study"].get<std::string>();
  for (const auto& name : plan["inputs"]) table.inputs.push_back(name.get<std::string>());
  table.rows = json::array();
  for (const json& entry : plan["cases"]) {
    const int index = entry["index"].get<int>();
    const fs::path case_dir = dir / case_folder(index);
    const CaseStatus status = read_case_status(case_dir);
    json row;
    row["index"] = index;
    row["folder"] = case_folder(index);
    row["status"] = to_string(status.state);
    for (const auto& name : table.inputs) row[name] = entry["inputs"][name];
    const json summary = status.state == CaseState::done ? read_json(case_dir / "summary.json") : json();
    for (const FigureColumn& f : figure_columns()) {
      if (is_input(table, f.column)) continue;  // the study's own value (a run's Re of a towed body is the same)
      const json::json_pointer pointer(f.summary_path);
      row[f.column] = summary.is_object() && summary.contains(pointer) ? summary[pointer] : json();
    }
    row[kHolzerSommerfeldColumn] = law_drag(case_dir, summary);
    row["wall_seconds"] = status.wall_seconds;
    table.rows.push_back(row);
  }
  return table;
}

std::string table_csv(const StudyTable& table) {
  std::string out;
  std::vector<std::string> columns{"index", "folder", "status"};
  columns.insert(columns.end(), table.inputs.begin(), table.inputs.end());
  for (const FigureColumn& f : figure_columns())
    if (!is_input(table, f.column)) columns.emplace_back(f.column);
  columns.emplace_back(kHolzerSommerfeldColumn);
  columns.emplace_back("wall_seconds");
  // Separator and cell appended apart: GCC 12 took `"," + std::string` (a prepend into a
  // temporary) for a copy of up to 2^63 bytes (-Wstringop-overflow).
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) out += ',';
    out += columns[i];
  }
  out += "\n";
  for (const json& row : table.rows) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (i > 0) out += ',';
      out += csv_cell(row[columns[i]]);
    }
    out += "\n";
  }
  return out;
}

json study_analyses(const StudyTable& table) {
  json out;
  out["grid_convergence"] = grid_convergence_json(table);
  out["coefficient_fits"] = coefficient_fits_json(table);
  out["ensembles"] = ensembles_json(table);
  return out;
}

}  // namespace settle::study
