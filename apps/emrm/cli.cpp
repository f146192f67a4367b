// The emrm command line: parses arguments, calls the library, maps errors to exit codes
// (0 success, 1 the analysis found errors, 2 bad input or usage, 128 + signal after an interrupt).
// main() is one call of run_cli; the CLI fuzz target calls it with Mode::kParseOnly.

#include "cli.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/core/text.hpp"
#include "emrm/openscenario/family.hpp"
#include "emrm/version.hpp"
#include "options.hpp"

namespace {

// An option the command does not have, with the nearest it has: CLI11 would first complain about
// a required option the misspelling was meant to be ("--speed-kph is required").
std::optional<std::string> unknown_option(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return std::nullopt;
  const CLI::App* command = nullptr;
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    commands.push_back(sub->get_name());
    if (sub->get_name() == argv[1]) command = sub;
  }
  if (command == nullptr && argv[1][0] != '-')  // CLI11 would say "A subcommand is required"
    return fmt::format("emrm: unknown command '{}'{}; see 'emrm --help'", emrm::cli::shortened(argv[1]),
                       emrm::core::did_you_mean(argv[1], commands));
  if (command == nullptr) return std::nullopt;
  for (int i = 2; i < argc; ++i) {
    std::string word = argv[i];
    if (word == "--") break;
    if (word.size() < 2 || word[0] != '-' || emrm::core::parse_finite_number(word)) continue;
    word = word.substr(0, word.find('='));
    if (word.rfind("--", 0) != 0 && word.size() > 2) continue;  // -abc: CLI11's own business
    if (command->get_option_no_throw(word) != nullptr) continue;
    std::vector<std::string> names;
    for (const CLI::Option* o : command->get_options())
      for (const auto& l : o->get_lnames()) names.push_back("--" + l);
    return fmt::format("emrm {}: unknown option '{}'{}; see 'emrm {} --help'", argv[1], emrm::cli::shortened(word),
                       emrm::core::did_you_mean(word, names), argv[1]);
  }
  return std::nullopt;
}

// CLI11's message with every over-long word (a 10 MB number, say) cut short.
std::string short_words(const std::string& message) {
  std::string out;
  std::size_t start = 0;
  while (start <= message.size()) {
    const std::size_t end = std::min(message.find(' ', start), message.size());
    if (!out.empty() || start > 0) out += ' ';
    out += emrm::cli::shortened(std::string_view(message).substr(start, end - start), 60);
    start = end + 1;
  }
  return out;
}

}  // namespace

namespace emrm::cli {

int run_cli(int argc, char** argv, Mode mode) {
  CLI::App app{
      "emrm — verification and validation of an Evasive Minimum-Risk Maneuver (EMRM).\n"
      "Exit codes: 0 success, 1 the analysis or check found errors, 2 bad input or usage.",
      "emrm"};
  app.set_version_flag("--version", fmt::format("emrm {}", emrm::kVersion));
  app.require_subcommand(1);
  app.fallthrough(false);

  // The family of imported OpenSCENARIO scenarios and `--scene FILE.xosc`, for every command.
  static const emrm::openscenario::Registration openscenario_family;

  int exit_code = 0;
  emrm::cli::register_analyze_command(app, exit_code);
  emrm::cli::register_fsm_command(app, exit_code);
  emrm::cli::register_families_command(app, exit_code);
  emrm::cli::register_simulate_command(app, exit_code);
  emrm::cli::register_sweep_commands(app, exit_code);
  emrm::cli::register_reproduce_command(app, exit_code);
  emrm::cli::register_ca_command(app, exit_code);
  emrm::cli::register_plan_command(app, exit_code);
  emrm::cli::register_run_command(app, exit_code);
  emrm::cli::register_report_command(app, exit_code);
  emrm::cli::register_verify_command(app, exit_code);
  emrm::cli::register_diagnose_command(app, exit_code);
  emrm::cli::register_boundary_command(app, exit_code);
  emrm::cli::register_calibrate_command(app, exit_code);
  emrm::cli::register_export_command(app, exit_code);
  emrm::cli::register_assess_command(app, exit_code);
  emrm::cli::register_import_command(app, exit_code);
  // Every check of the arguments, none of the work: CLI11 calls this once they all passed, before
  // the command's callback (which owns the command's options, so it must stay).
  struct Parsed {};
  if (mode == Mode::kParseOnly) app.parse_complete_callback([] { throw Parsed{}; });

  if (const auto message = unknown_option(app, argc, argv)) {
    std::fprintf(stderr, "%s\n", message->c_str());
    return static_cast<int>(emrm::ExitCode::kBadInput);
  }
  try {
    app.parse(argc, argv);
  } catch (const Parsed&) {
    return static_cast<int>(emrm::ExitCode::kSuccess);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s\nRun with --help for more information.\n", short_words(e.what()).c_str());
    return static_cast<int>(emrm::ExitCode::kBadInput);
  } catch (...) {
    return report_error();
  }
  return exit_code;
}

int report_error() {
  try {
    throw;
  } catch (const emrm::core::Interrupted& e) {  // the work so far is stored; the message says how to resume
    std::fprintf(stderr, "%s\n", e.what());
    return 128 + e.signal();
  } catch (const emrm::Error& e) {
    // FILE:LINE:COLUMN: error: ..., or with no file to name the same "error:" a reader looks for.
    const bool said = std::string_view(e.what()).find("error: ") != std::string_view::npos;
    std::fprintf(stderr, "%s%s\n", said ? "" : "error: ", e.what());
    return static_cast<int>(emrm::ExitCode::kBadInput);
  } catch (const std::filesystem::filesystem_error& e) {  // a path the system refuses (too long, no access)
    std::fprintf(stderr, "%s: error: %s\n", emrm::cli::shortened(e.path1().string(), 80).c_str(),
                 e.code().message().c_str());
    return static_cast<int>(emrm::ExitCode::kBadInput);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "emrm: internal error: %s\n", e.what());
    return 70;
  }
}

}  // namespace emrm::cli
