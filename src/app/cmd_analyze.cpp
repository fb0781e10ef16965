// Placeholder: replaced by the owner of `settle analyze`.
#include "app/commands.hpp"

namespace settle::app {

void add_analyze_command(CLI::App& /*app*/) {}

}  // namespace settle::app
