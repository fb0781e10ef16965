#pragma once
// The declaration of every key a settle case file may hold (docs/architecture.md, "Case file"). This is the
// one place where keys, types, defaults, ranges, units and docs are written; the reader, the
// resolved-case writer and the user guide's key table all come from it.
#include "io/schema.hpp"

namespace settle::io {

/// The case schema (built once, on first use).
const Schema& case_schema();

}  // namespace settle::io
