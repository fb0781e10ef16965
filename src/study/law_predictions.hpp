#pragma once
// The empirical drag law beside a towed or fixed body's measured drag coefficient in a study's
// table: Hoelzer and Sommerfeld (2008, analysis/correlations.hpp), the one law settle knows whose
// shape factors depend on the body's attitude to the flow (the crosswise and lengthwise
// sphericities), so that it gives a curve against the incidence.
#include <filesystem>
#include <optional>

namespace settle::study {

/// C_D of Hoelzer and Sommerfeld for the case of `case_file` (a study's case.toml) at the
/// Reynolds number `reynolds` (based on d_eq), with the flow along the towing velocity or the
/// inflow, in the body's initial attitude. Empty for a free body (its attitude to the flow is an
/// outcome) or a case without a flow direction.
std::optional<double> holzer_sommerfeld_drag_of_case(const std::filesystem::path& case_file, double reynolds);

}  // namespace settle::study
