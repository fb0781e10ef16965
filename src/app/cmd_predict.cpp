// Placeholder: replaced by the owner of `settle predict`.
#include "app/commands.hpp"

namespace settle::app {

void add_predict_command(CLI::App& /*app*/) {}

}  // namespace settle::app
