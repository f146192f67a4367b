#pragma once

// What the ODD tests share: a small ODD of every factor kind as YAML, a parser over it, and
// checks that an error is reported at a given place in the text.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "input_error.hpp"

namespace emrm::scenario::test_support {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// Five factors, one of each kind (and a second continuous one that is not influential).
inline constexpr const char* kGood = R"(name: unit odd
seed: 7
factors:
  - name: v
    unit: km/h
    bins: [10, 20, 40]
    kinks: [15]
  - name: n
    type: integer
    bins: [0, 2, 5]
  - name: road
    type: categorical
    classes: [dry, wet, icy]
    values: [1.0, 0.6, 0.2]
  - name: lanes
    type: constant
    value: 2
  - name: w
    bins: [0, 1, 2, 3]
    prior: [0.2, 0.5, 0.3]
    influential: false
coverage:
  strength: 2
  n_c: 1
  n_m: 2
  epsilon: 0.3
  delta: 0.05
  budget: 100
)";

inline fs::path temp_dir() {
  const auto dir = fs::temp_directory_path() / ("emrm-odd-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

inline fs::path examples_dir() { return fs::path(EMRM_SOURCE_DIR) / "examples" / "tjunction"; }

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

inline Odd parse(const std::string& text) { return parse_odd(text, "odd.yaml", temp_dir()); }

inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test text lacks '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// 1-based line and column of the first occurrence of `needle` in `text`, moved `offset` characters.
struct Pos {
  int line = 0;
  int column = 0;
};
inline Pos pos_of(const std::string& text, const std::string& needle, int offset = 0) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << "no '" << needle << "' in the text";
  if (at == std::string::npos) return {};
  const std::size_t p = at + static_cast<std::size_t>(offset);
  Pos pos{1, 1};
  const auto line_start = text.rfind('\n', p == 0 ? 0 : p - 1);
  for (std::size_t i = 0; i < p; ++i)
    if (text[i] == '\n') ++pos.line;
  pos.column = static_cast<int>(line_start == std::string::npos || p == 0 ? p + 1 : p - line_start);
  return pos;
}

// Parses `text` and returns the InputError it must raise.
inline InputError parse_error(const std::string& text) {
  return emrm::testing::input_error_of([&] { (void)parse(text); }, text);
}

// The error of `text` lies at the first occurrence of `needle` (plus `offset`) and says `words`.
inline void expect_error_at(const std::string& text, const std::string& needle, int offset, const std::string& words) {
  SCOPED_TRACE(needle);
  const InputError e = parse_error(text);
  if (e.message() == "none") return;  // parse_error has reported the missing error
  const Pos p = pos_of(text, needle, offset);
  EXPECT_EQ(e.where().file, "odd.yaml");
  EXPECT_EQ(e.where().line, p.line) << e.what();
  EXPECT_EQ(e.where().column, p.column) << e.what();
  EXPECT_THAT(e.what(), HasSubstr(words));
  EXPECT_THAT(e.what(), HasSubstr("odd.yaml:" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": error: "));
}

// ---- a good ODD ---------------------------------------------------------------------------------

}  // namespace emrm::scenario::test_support
