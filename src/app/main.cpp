// settle: the command-line front end. All physics lives in libsettle; this file only wires
// the subcommands together and turns errors into exit codes.
#include <cstdio>
#include <exception>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "app/console.hpp"
#include "common/error.hpp"
#include "common/stop_signals.hpp"
#include "parallel/communicator.hpp"
#include "settle/version.hpp"

namespace {

// Under mpirun every rank meets the same bad case, the same failing health check or the same
// interruption (all decided on data every rank holds alike, or agreed: coupling/runner.cpp), so rank
// 0 alone reports them and each rank exits with the code.
bool reports_errors() { return !settle::parallel::launched_by_mpi() || settle::parallel::world().rank() == 0; }

// A failure of one rank alone (an internal error, a file rank 0 cannot write) would leave the others
// waiting for its messages: it ends every process of the run.
int fail_alone(int code) {
  if (settle::parallel::launched_by_mpi() && settle::parallel::world().size() > 1)
    settle::parallel::world().abort(code);
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  settle::ignore_file_size_signal();  // a write past ulimit -f fails (EFBIG) and is reported
  CLI::App app{"settle: resolved simulation of rigid particles of any shape settling in a quiescent fluid"};
  app.set_version_flag("--version", fmt::format("settle {} (commit {}), {}", settle::version_string,
                                                settle::commit_string, settle::parallel::mpi_library_version()));
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
    if (reports_errors()) settle::app::write_stderr(fmt::format("settle: error: {}\n", e.what()));
    return 2;
  } catch (const settle::NumericalError& e) {
    if (reports_errors()) settle::app::write_stderr(fmt::format("settle: run stopped: {}\n", e.what()));
    return 3;
  } catch (const settle::RunInterrupted& e) {
    if (reports_errors()) settle::app::write_stderr(fmt::format("settle: {}\n", e.what()));
    return e.exit_status();
  } catch (const std::exception& e) {
    settle::app::write_stderr(fmt::format("settle: internal error: {}\n", e.what()));
    return fail_alone(1);
  }
  return 0;
}
