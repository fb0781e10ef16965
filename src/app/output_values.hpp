#pragma once
// Values the subcommands print or write in the same form: a vector as a JSON array, bytes in GiB.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace settle::app {

inline constexpr double kBytesPerGiB = 1024.0 * 1024.0 * 1024.0;

inline nlohmann::json vector_json(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

}  // namespace settle::app
