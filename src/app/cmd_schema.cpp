// `settle schema`: the keys a case file may hold, from the one declaration in io/case_schema.
#include <fmt/core.h>

#include "app/commands.hpp"
#include "io/case_schema.hpp"

namespace settle::app {

void add_schema_command(CLI::App& app) {
  auto markdown = std::make_shared<bool>(false);
  CLI::App* cmd =
      app.add_subcommand("schema", "List every case-file key with its type, default, allowed range, unit and meaning.");
  cmd->add_flag("--markdown", *markdown, "print a Markdown table (as in docs/case-file.md) instead of TOML");
  cmd->callback([markdown] {
    const io::Schema& schema = io::case_schema();
    if (*markdown) {
      fmt::print("{}", io::schema_markdown(schema));
      return;
    }
    // A TOML document of the defaults, with each key's unit and meaning as a comment; keys
    // without a default are listed commented out.
    io::CaseValues defaults(schema);
    for (const io::KeySpec& k : schema.keys())
      if (k.default_value) defaults.set(k.path, *k.default_value, "schema default", false);
    fmt::print("{}", io::write_resolved_toml(defaults));
    for (const io::KeySpec& k : schema.keys())
      if (!k.default_value)
        fmt::print("# {} ({}{}): {}, no default\n", k.path, io::to_string(k.kind), k.unit.empty() ? "" : ", " + k.unit,
                   k.doc);
  });
}

}  // namespace settle::app
