#pragma once

// The whole emrm command line as one function, for main() and for the CLI fuzz target.

namespace emrm::cli {

enum class Mode {
  kRun,        ///< parse, then run the command
  kParseOnly,  ///< parse and check every argument, run nothing (the fuzz target)
};

/// Parses `argv` as emrm's command line and runs the command; returns the exit code (0 success,
/// 1 the check found errors, 2 bad input or usage, 128 + signal after an interrupt; 70 only for
/// an internal error, which is a bug).
int run_cli(int argc, char** argv, Mode mode = Mode::kRun);

/// Called inside a catch block: prints the error being handled the way the command line does
/// and returns its exit code (2 bad input, 128 + signal after an interrupt, 70 a bug).
int report_error();

}  // namespace emrm::cli
