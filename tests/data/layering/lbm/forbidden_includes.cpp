// Input of the layering check's test (tests/CMakeLists.txt): lbm may use common and Eigen, not
// coupling or JSON. Never compiled.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "lbm/grid.hpp"
