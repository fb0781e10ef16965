#include "ibm/delta.hpp"

#include <string>

#include "common/error.hpp"

namespace settle::ibm {

std::string_view to_string(DeltaKernel kernel) { return kernel == DeltaKernel::Roma3 ? "roma3" : "peskin4"; }

DeltaKernel delta_kernel_from_string(std::string_view name, std::string_view key) {
  if (name == "roma3") return DeltaKernel::Roma3;
  if (name == "peskin4") return DeltaKernel::Peskin4;
  throw InputError(std::string(key) + ": unknown delta kernel \"" + std::string(name) +
                   "\"; allowed: \"roma3\", \"peskin4\"");
}

AxisStencil axis_stencil(DeltaKernel kernel, double x) {
  AxisStencil s;
  s.width = stencil_width(kernel);
  // The support (x - h, x + h) holds exactly `width` integers unless x - h is itself an integer,
  // where the end point has zero weight; starting at floor(x - h) + 1 picks the interior ones.
  s.first = static_cast<int>(std::floor(x - support_half_width(kernel))) + 1;
  for (int j = 0; j < s.width; ++j) s.weight[j] = delta_1d(kernel, x - (s.first + j));
  return s;
}

Stencil stencil_at(DeltaKernel kernel, double x, double y, double z) {
  return Stencil{{axis_stencil(kernel, x), axis_stencil(kernel, y), axis_stencil(kernel, z)}};
}

}  // namespace settle::ibm
