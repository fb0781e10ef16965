// PLACEHOLDER: replaced by the module's owner; registers nothing yet.
#include "app/commands.hpp"
namespace settle::app {
void add_shape_command(CLI::App& /*app*/) {}
}  // namespace settle::app
