#pragma once

#include <stdexcept>
#include <string>

namespace emrm {

/// Where something was written in a user's file. Lines and columns count from 1;
/// 0 means "unknown" (for example a file that could not be opened).
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;

  /// "file:line:column", or less when line/column are unknown.
  [[nodiscard]] std::string str() const;
};

/// Root of every exception emrm throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad user input: a file that is malformed, of the wrong type, missing a field, out of range.
/// what() reads "FILE:LINE:COLUMN: error: MESSAGE", or "error: MESSAGE" without a file (a
/// configuration built in code); the CLI maps it to exit code 2.
class InputError : public Error {
 public:
  InputError(SourceLocation where, std::string message);

  [[nodiscard]] const SourceLocation& where() const noexcept { return where_; }
  [[nodiscard]] const std::string& message() const noexcept { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

/// Bad command-line usage that the argument parser could not catch; exit code 2.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Exit codes shared by every command.
enum class ExitCode : int { kSuccess = 0, kFindings = 1, kBadInput = 2 };

}  // namespace emrm
