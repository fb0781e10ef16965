// settle: the command-line front end. All physics lives in libsettle; this file only wires
// the subcommands together and turns errors into exit codes.
#include <cstdio>
#include <exception>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "parallel/communicator.hpp"
#include "settle/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"settle: resolved simulation of rigid particles of any shape settling in a quiescent fluid"};
  app.set_version_flag("--version",
                       fmt::format("settle {}, {}", settle::version_string, settle::parallel::mpi_library_version()));
  app.require_subcommand(1);
  settle::app::add_attitude_command(app);
  settle::app::add_shape_command(app);
  settle::app::add_bench_command(app);
  settle::app::add_schema_command(app);
  settle::app::add_run_command(app);
  settle::app::add_predict_command(app);
  settle::app::add_analyze_command(app);
  settle::app::add_plot_command(app);
  settle::app::add_study_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed (exit code 0); every other parse error (unknown
    // flag, missing or malformed value) is a usage error the user can fix: exit 2, as InputError.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const settle::InputError& e) {
    fmt::print(stderr, "settle: error: {}\n", e.what());
    return 2;
  } catch (const settle::NumericalError& e) {
    fmt::print(stderr, "settle: run stopped: {}\n", e.what());
    return 3;
  } catch (const settle::RunInterrupted& e) {
    fmt::print(stderr, "settle: {}\n", e.what());
    return e.exit_status();
  } catch (const std::exception& e) {
    fmt::print(stderr, "settle: internal error: {}\n", e.what());
    return 1;
  }
  return 0;
}
