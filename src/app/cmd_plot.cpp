// Placeholder: replaced by the owner of `settle plot`.
#include "app/commands.hpp"

namespace settle::app {

void add_plot_command(CLI::App& /*app*/) {}

}  // namespace settle::app
