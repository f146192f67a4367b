// The emrm command line: parses arguments, calls the library, maps errors to exit codes
// (0 success, 1 the analysis found errors, 2 bad input or usage, 128 + signal after an interrupt).

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"emrm — verification and validation of an Evasive Minimum-Risk Maneuver (EMRM).\n"
               "Exit codes: 0 success, 1 the analysis or check found errors, 2 bad input or usage.",
               "emrm"};
  app.set_version_flag("--version", fmt::format("emrm {}", emrm::kVersion));
  app.require_subcommand(1);
  app.fallthrough(false);

  int exit_code = 0;
  emrm::cli::register_analyze_command(app, exit_code);
  emrm::cli::register_fsm_command(app, exit_code);
  emrm::cli::register_simulate_command(app, exit_code);
  emrm::cli::register_sweep_commands(app, exit_code);
  emrm::cli::register_reproduce_command(app, exit_code);
  emrm::cli::register_ca_command(app, exit_code);
  emrm::cli::register_plan_command(app, exit_code);
  emrm::cli::register_run_command(app, exit_code);
  emrm::cli::register_report_command(app, exit_code);
  emrm::cli::register_verify_command(app, exit_code);
  emrm::cli::register_calibrate_command(app, exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const emrm::core::Interrupted& e) {  // the work so far is stored; the message says how to resume
    std::fprintf(stderr, "%s\n", e.what());
    return 128 + e.signal();
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return static_cast<int>(emrm::ExitCode::kBadInput);
  } catch (const emrm::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return static_cast<int>(emrm::ExitCode::kBadInput);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "emrm: internal error: %s\n", e.what());
    return 70;
  }
  return exit_code;
}
