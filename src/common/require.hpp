#pragma once
// Checks of a single input number, with the message every part of settle uses for it.
#include <string_view>

namespace settle {

/// Throws settle::InputError "<name>: must be finite and > 0, got <value>" unless `value` is
/// finite and positive. `name` is what the user wrote: a case key, a flag or a described quantity.
void require_positive(double value, std::string_view name);

}  // namespace settle
