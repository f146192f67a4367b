#pragma once

// Runs the real emrm binary for end-to-end tests and captures what it printed.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace emrm::e2e {

struct RunResult {
  int exit_code = -1;
  std::string out;  ///< standard output
  std::string err;  ///< standard error
};

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// A fresh, empty folder for one test, under the build tree's temp folder.
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("emrm-e2e-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string example(const std::string& name) {
  return std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/" + name;
}

/// Runs `emrm ARGS` through the shell (ARGS is shell text; quote paths yourself).
inline RunResult run_emrm(const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-e2e-run-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto out_path = dir / ("out" + std::to_string(counter));
  const auto err_path = dir / ("err" + std::to_string(counter++));
  const std::string command = std::string("'") + EMRM_BINARY + "' " + args + " >'" + out_path.string() + "' 2>'" +
                              err_path.string() + "' </dev/null";
  const int status = std::system(command.c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = read_text(out_path);
  result.err = read_text(err_path);
  return result;
}

/// The stems of the figures report.html holds (`<figure id="fig-STEM">`) that start with `prefix`,
/// in page order. (No std::regex: GCC 12 warns inside it under the sanitizers' -O1.)
inline std::vector<std::string> figure_ids(const std::string& html, const std::string& prefix = "") {
  std::vector<std::string> ids;
  const std::string open = "<figure id=\"fig-";
  for (auto at = html.find(open); at != std::string::npos; at = html.find(open, at + 1)) {
    const auto start = at + open.size();
    const auto end = html.find('"', start);
    if (end == std::string::npos) break;
    std::string id = html.substr(start, end - start);
    if (id.rfind(prefix, 0) == 0) ids.push_back(std::move(id));
  }
  return ids;
}

/// Single-quotes a path for run_emrm's shell text. (The std::string overload is a better match
/// than std::quoted, which argument-dependent lookup would otherwise find.)
inline std::string quoted(const std::string& path) { return "'" + path + "'"; }
inline std::string quoted(const std::filesystem::path& path) { return quoted(path.string()); }

/// The rows of a CSV file emrm wrote, split into fields (quoted fields may hold commas; emrm's
/// exports put no newline inside a field).
inline std::vector<std::vector<std::string>> csv_rows(const std::filesystem::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(file));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::string field;
    bool in_quotes = false;
    for (char c : line) {
      if (c == '"')
        in_quotes = !in_quotes;
      else if (c == ',' && !in_quotes)
        fields.push_back(std::exchange(field, {}));
      else
        field += c;
    }
    fields.push_back(field);
    rows.push_back(std::move(fields));
  }
  return rows;
}

/// The position of column `name` in a header row; a test failure when it is missing.
inline std::size_t column_of(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  EXPECT_NE(it, header.end()) << "column " << name;
  return static_cast<std::size_t>(it - header.begin());
}

/// Bad input as the house has it: exit code 2 and one line naming `what`.
inline void expect_bad_input(const RunResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr(what));
}

}  // namespace emrm::e2e
