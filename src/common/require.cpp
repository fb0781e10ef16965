#include "common/require.hpp"

#include <cmath>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle {

void require_positive(double value, std::string_view name) {
  if (!(std::isfinite(value) && value > 0.0))
    throw InputError(fmt::format("{}: must be finite and > 0, got {}", name, value));
}

}  // namespace settle
