#pragma once
// `settle study collect`: one row per case (its inputs, the figures of its summary.json and its
// status), and the analyses a study's shape calls for (docs/studies.md, "Collecting"): grid
// convergence when numerics.cells_per_diameter varies, coefficient fits when incidence_deg
// varies, ensemble statistics when the orientation does.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace settle::study {

/// One figure of the table: its column name (with its unit) and where summary.json keeps it.
struct FigureColumn {
  const char* column;
  const char* summary_path;  ///< JSON pointer into summary.json
};

/// The figures collected, in column order.
const std::vector<FigureColumn>& figure_columns();

struct StudyTable {
  std::string study;
  std::vector<std::string> inputs;  ///< the varied inputs' names
  nlohmann::ordered_json rows;      ///< array of {index, folder, status, <input>..., <figure>...}
};

/// Reads study.json, each case's status.json and summary.json. Figures a case lacks are null.
/// Each row also has drag_coefficient_holzer_sommerfeld, the law for a towed or fixed body at the
/// run's Reynolds number and the case's attitude (law_predictions.hpp).
StudyTable collect_table(const std::filesystem::path& dir);

/// The table as CSV: a header line, then a row per case; empty cells for nulls.
std::string table_csv(const StudyTable& table);

/// The analyses of the table: "grid_convergence", "coefficient_fits", "ensembles" (each an array,
/// empty when the study does not vary what it needs).
nlohmann::ordered_json study_analyses(const StudyTable& table);

}  // namespace settle::study
