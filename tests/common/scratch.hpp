#pragma once

// A fresh scratch folder for a test: TMP/emrm-SUITE-PID/NAME, emptied (and not created: a writer
// that makes its own folder is tested too).

#include <unistd.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace emrm::test {

inline std::filesystem::path scratch_dir(std::string_view suite, const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("emrm-" + std::string(suite) + "-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace emrm::test
