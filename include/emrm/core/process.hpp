#pragma once

// Running the external tools emrm draws with (Graphviz, gnuplot): found on PATH, started
// without a shell, standard error captured for the message when they fail.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace emrm::core {

/// `program` itself if it contains '/', else the first executable match on PATH.
[[nodiscard]] std::optional<std::filesystem::path> find_program(const std::string& program);

/// A private temporary folder, removed with everything in it when this goes out of scope.
class TempDir {
 public:
  /// Throws emrm::Error if the folder cannot be created.
  explicit TempDir(const std::string& prefix = "emrm");
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir();
  [[nodiscard]] const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
};

struct ProcessResult {
  int exit_code = -1;        ///< the exit status, or 128 + signal
  std::string error_output;  ///< what it wrote on standard error, trailing newlines removed
};

/// Runs `program` with `args` (no shell); standard input from /dev/null, standard output
/// discarded. Throws emrm::Error if it cannot be started.
[[nodiscard]] ProcessResult run_program(const std::filesystem::path& program, const std::vector<std::string>& args);

/// The whole content of a file ("" if it cannot be read).
[[nodiscard]] std::string read_file(const std::filesystem::path& path);

}  // namespace emrm::core
