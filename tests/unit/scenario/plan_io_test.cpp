#include "emrm/scenario/plan_io.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "input_error.hpp"

namespace emrm::scenario {
namespace plan_io_test {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

fs::path temp_dir() {
  const auto dir = fs::temp_directory_path() / ("emrm-plan-io-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// Two modes that overlap, each with two transitions (one shared), a categorical and an integer
// factor, so that every column of the file carries something.
constexpr const char* kOdd = R"(name: io odd
seed: 11
factors:
  - name: speed_kph
    bins: [30, 50, 72]
  - name: ttc_s
    bins: [0.25, 1.0, 2.95]
    kinks: [0.7]
  - name: road
    type: categorical
    classes: [dry, wet]
    values: [1.0, 0.4]
  - name: n
    type: integer
    bins: [0, 2, 4]
malfunctions:
  - id: UCA1
    region: "ttc_s < 1.3"
    transitions: ["S3 -execute_maneuver-> S4", "S4 -timeout_error-> S5"]
  - id: UCA3
    region: "ttc_s < 0.7 || road < 0.5"
    transitions: ["S1 -hazard_detected-> S2", "S4 -timeout_error-> S5"]
coverage: {strength: 2, n_c: 1, n_m: 3, epsilon: 0.4, budget: 200}
)";

const Odd& io_odd() {
  static const Odd odd = parse_odd(kOdd, "io.yaml", temp_dir());
  return odd;
}
const Plan& io_plan() {
  static const Plan plan = build_plan(io_odd());
  return plan;
}

std::string nine(double v) { return fmt::format("{:.9g}", v); }

// Reads `text` as a scenarios.csv and returns the InputError it must raise.
InputError read_error(const std::string& text, const std::string& name = "bad.csv") {
  const fs::path p = write_temp(name, text);
  return emrm::testing::input_error_of([&] { (void)read_scenarios_csv(p); }, text);
}

void expect_read_error(const std::string& text, int line, int column, const std::string& words) {
  const InputError e = read_error(text);
  if (e.message() == "none") return;  // read_error has reported the missing error
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
  EXPECT_EQ(fs::path(e.where().file).filename(), "bad.csv") << e.what();
  EXPECT_THAT(e.what(), HasSubstr(words));
}

constexpr const char* kHeader = "id,step,a,b,cell,malfunctions,transitions,weight,seed\n";

// ---- writing and reading back -----------------------------------------------------------------

TEST(ScenariosCsv, RoundTripKeepsEveryColumn) {
  const Odd& odd = io_odd();
  const Plan& plan = io_plan();
  ASSERT_GT(plan.scenarios.size(), 5u);
  const fs::path p = write_temp("scenarios.csv", scenarios_csv(odd, plan));
  const ScenarioFile file = read_scenarios_csv(p);
  EXPECT_EQ(file.factors, odd.factor_names());
  ASSERT_EQ(file.rows.size(), plan.scenarios.size());
  bool saw_two_modes = false;
  bool saw_no_mode = false;
  for (std::size_t i = 0; i < file.rows.size(); ++i) {
    const Scenario& s = plan.scenarios[i];
    const ScenarioRow& r = file.rows[i];
    SCOPED_TRACE(s.id);
    EXPECT_EQ(r.id, s.id);
    EXPECT_EQ(r.step, s.step);
    ASSERT_EQ(r.values.size(), s.values.size());
    for (std::size_t k = 0; k < s.values.size(); ++k) EXPECT_EQ(nine(r.values[k]), nine(s.values[k]));
    EXPECT_EQ(r.cell, cell_key(s.cell));
    EXPECT_EQ(r.malfunctions, s.malfunctions);
    EXPECT_EQ(r.transitions, s.transitions);
    EXPECT_EQ(nine(r.weight), nine(s.weight));
    EXPECT_EQ(r.seed, s.seed);
    EXPECT_EQ(r.where.line, static_cast<int>(i) + 2);  // after the header
    EXPECT_EQ(r.where.column, 1);
    saw_two_modes = saw_two_modes || s.malfunctions.size() == 2;
    saw_no_mode = saw_no_mode || s.malfunctions.empty();
  }
  EXPECT_TRUE(saw_two_modes) << "the plan should exercise the space-separated list";
  EXPECT_TRUE(saw_no_mode) << "the plan should exercise an empty list";
}

TEST(ScenariosCsv, ValuesReadBackLieInTheCellTheFileNames) {
  // What `emrm run` simulates is the value as written: it must stay in the scenario's cell.
  const Odd shipped = load_odd(fs::path(EMRM_SOURCE_DIR) / "examples" / "tjunction" / "odd.yaml");
  const Plan plan = build_plan(shipped);
  for (const auto& [odd, p] : {std::pair<const Odd*, const Plan*>{&io_odd(), &io_plan()}, {&shipped, &plan}}) {
    const ScenarioFile file = read_scenarios_csv(write_temp("cells.csv", scenarios_csv(*odd, *p)));
    ASSERT_EQ(file.rows.size(), p->scenarios.size());
    for (const auto& r : file.rows) {
      EXPECT_EQ(cell_key(odd->cell_of(r.values)), r.cell) << r.id;
      EXPECT_TRUE(odd->admissible(r.values)) << r.id;
    }
  }
}

TEST(ScenariosCsv, ReadsBackWhatItWroteTwiceIdentically) {
  // Writing what was read gives the same text: the file is a fixed point of write ∘ read.
  const std::string text = scenarios_csv(io_odd(), io_plan());
  const ScenarioFile file = read_scenarios_csv(write_temp("again.csv", text));
  core::Row header{"id", "step"};
  for (const auto& f : file.factors) header.push_back(f);
  for (const char* c : {"cell", "malfunctions", "transitions", "weight", "seed"}) header.push_back(c);
  std::vector<core::Row> rows;
  for (const auto& r : file.rows) {
    core::Row row{r.id, r.step};
    for (double v : r.values) row.push_back(nine(v));
    row.push_back(r.cell);
    row.push_back(core::join(r.malfunctions, " "));
    row.push_back(core::join(r.transitions, "; "));
    row.push_back(nine(r.weight));
    row.push_back(std::to_string(r.seed));
    rows.push_back(row);
  }
  EXPECT_EQ(core::csv_table(header, rows), text);
}

TEST(ScenariosJson, HasOneEntryPerScenarioWithTheSameIds) {
  const auto j = scenarios_json(io_odd(), io_plan());
  ASSERT_TRUE(j.contains("scenarios"));
  const auto& list = j["scenarios"];
  ASSERT_EQ(list.size(), io_plan().scenarios.size());
  std::set<std::string> ids;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Scenario& s = io_plan().scenarios[i];
    EXPECT_EQ(list[i]["id"].get<std::string>(), s.id);
    ids.insert(list[i]["id"].get<std::string>());
    EXPECT_EQ(list[i]["cell"].get<std::string>(), cell_key(s.cell));
    EXPECT_EQ(list[i]["seed"].get<std::uint64_t>(), s.seed);
    EXPECT_DOUBLE_EQ(list[i]["values"]["ttc_s"].get<double>(), s.values[1]);
    EXPECT_EQ(list[i]["cell_levels"]["road"].get<std::string>(), io_odd().factors[2].level_label(s.cell[2]));
    EXPECT_EQ(list[i]["malfunctions"].get<std::vector<std::string>>(), s.malfunctions);
  }
  EXPECT_EQ(ids.size(), list.size());
  EXPECT_EQ(j["settings"]["seed"].get<std::uint64_t>(), 11u);
  EXPECT_EQ(j["stop"]["targets_met"].get<bool>(), io_plan().targets_met);
  EXPECT_EQ(j["steps"].size(), io_plan().steps.size());
  EXPECT_EQ(j["factors"].size(), 4u);
}

TEST(CoverageComparison, PlanFirstThenTheBaselinesBySameCode) {
  const auto reports = coverage_comparison(io_odd(), io_plan());
  ASSERT_EQ(reports.size(), 3u);  // no manual grid declared
  EXPECT_EQ(reports[0].name, "emrm plan");
  EXPECT_EQ(reports[1].name, "HARA only");
  EXPECT_EQ(reports[2].name, "STPA only");
  EXPECT_EQ(reports[0].scenarios, io_plan().scenarios.size());
  EXPECT_TRUE(reports[0].all());
  const auto j = coverage_json(reports);
  EXPECT_EQ(j["plan"]["name"].get<std::string>(), "emrm plan");
  EXPECT_EQ(j["baselines"].size(), 2u);
  const auto [header, rows] = coverage_table(reports);
  EXPECT_THAT(header, ElementsAre("metric", "emrm plan", "HARA only", "STPA only"));
  for (const auto& row : rows) EXPECT_EQ(row.size(), header.size());
}

void expect_same_count(const CoverageCount& a, const CoverageCount& b, const std::string& what) {
  EXPECT_EQ(a.covered, b.covered) << what;
  EXPECT_EQ(a.total, b.total) << what;
  EXPECT_EQ(a.missing, b.missing) << what;
  EXPECT_EQ(a.fraction(), b.fraction()) << what;  // the same double: derived from the same counts
}

TEST(CoverageJson, ReadsBackEveryFieldWritePlanWrote) {
  const auto written = coverage_comparison(io_odd(), io_plan());
  const fs::path dir = temp_dir() / "coverage-json";
  write_plan(dir, io_odd(), io_plan(), written);
  const auto read = read_coverage_json(dir / "coverage.json");
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    const auto& r = read[i];
    const auto& w = written[i];
    EXPECT_EQ(r.name, w.name);
    EXPECT_EQ(r.scenarios, w.scenarios);
    EXPECT_EQ(r.inadmissible, w.inadmissible);
    EXPECT_EQ(r.tests_per_malfunction, w.tests_per_malfunction);  // in the written order
    expect_same_count(r.hazards, w.hazards, w.name + " hazards");
    expect_same_count(r.malfunctions, w.malfunctions, w.name + " malfunctions");
    expect_same_count(r.transitions, w.transitions, w.name + " transitions");
    expect_same_count(r.cells, w.cells, w.name + " cells");
    expect_same_count(r.boundaries, w.boundaries, w.name + " boundaries");
    expect_same_count(r.twise, w.twise, w.name + " twise");
    EXPECT_EQ(std::tuple(r.c1, r.c2, r.c3, r.c4), std::tuple(w.c1, w.c2, w.c3, w.c4));
  }
  // What is read writes the same file again.
  EXPECT_EQ(coverage_json(read).dump(2) + "\n", core::read_input_file(dir / "coverage.json"));
}

TEST(CoverageJson, AMissingOrMistypedFieldIsNamedWithItsPlace) {
  const std::string good = coverage_json(coverage_comparison(io_odd(), io_plan())).dump(2);
  const auto error_for = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.rfind(from);  // in the last baseline
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return emrm::testing::input_error_of([&] { (void)parse_coverage_json(text, "coverage.json"); }, text);
  };
  EXPECT_THAT(error_for("\"covered\": ", "\"kovered\": ").what(),
              HasSubstr("coverage.json: error: baselines[1].twise.covered: expected a value"));
  EXPECT_THAT(error_for("\"c4\": false", "\"c4\": 0").what(), HasSubstr("baselines[1].c4: expected true or false"));
  EXPECT_THAT(error_for("\"scenarios\": ", "\"scenarios\": -").what(),
              HasSubstr("baselines[1].scenarios: expected a non-negative integer"));
  EXPECT_THAT(emrm::testing::input_error_of([] { (void)parse_coverage_json("{\"plan\": ", "c.json"); }, "").what(),
              HasSubstr("c.json:1:1: error: not valid JSON"));
  EXPECT_THAT(emrm::testing::input_error_of([] { (void)parse_coverage_json("[]", "c.json"); }, "").what(),
              HasSubstr("expected a coverage report"));
}

// ---- reading errors, each at its line and column -----------------------------------------------

TEST(ScenariosCsvErrors, WrongHeader) {
  expect_read_error("ident,step,a,b,cell,malfunctions,transitions,weight,seed\n", 1, 1, "'ident', not 'id'");
  expect_read_error("id,stage,a,b,cell,malfunctions,transitions,weight,seed\n", 1, 4, "'stage', not 'step'");
  expect_read_error("id,step,a,b,cell,malfunctions,transitions,wt,seed\n", 1, 43, "'wt', not 'weight'");
}

TEST(ScenariosCsvErrors, MissingTrailingColumns) {
  expect_read_error("id,step,a,b,cell\n", 1, 1, "columns");
  // Eight columns, but the last five are not cell … seed: the missing one is named at its place.
  expect_read_error("id,step,a,b,cell,malfunctions,transitions,weight\n", 1, 11, "'b', not 'cell'");
}

TEST(ScenariosCsvErrors, RowWithTooFewFields) {  // refused at the short row's last field
  const std::string row = "S002,boundary,1,2,c0.0,,1,5";
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,1,5\n" + row + "\n", 3,
                    static_cast<int>(row.size()), "expected 9 fields as in the header, got 8");
}

TEST(ScenariosCsvErrors, ValueThatIsNotANumber) {
  expect_read_error(std::string(kHeader) + "S001,boundary,1,x2,c0.0,,,1,5\n", 2, 17, "'x2'");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,,c0.0,,,1,5\n", 2, 17, "finite number");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2.5abc,c0.0,,,1,5\n", 2, 17, "2.5abc");
}

TEST(ScenariosCsvErrors, NanOrInfiniteValue) {
  expect_read_error(std::string(kHeader) + "S001,boundary,nan,2,c0.0,,,1,5\n", 2, 15, "finite");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,inf,c0.0,,,1,5\n", 2, 17, "finite");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,nan,5\n", 2, 26, "weight");
}

TEST(ScenariosCsvErrors, NegativeWeight) {
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,-0.5,5\n", 2, 26, "weight");
}

TEST(ScenariosCsvErrors, BadSeed) {
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,1,-5\n", 2, 28, "seed");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,1,12x\n", 2, 28, "seed");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,1,\n", 2, 28, "seed");
  expect_read_error(std::string(kHeader) + "S001,boundary,1,2,c0.0,,,1,99999999999999999999\n", 2, 28, "seed");
  // The largest 64-bit seed is fine.
  const auto file =
      read_scenarios_csv(write_temp("max.csv", std::string(kHeader) + "S1,x,1,2,c0.0,,,1,18446744073709551615\n"));
  EXPECT_EQ(file.rows.at(0).seed, 18446744073709551615ULL);
}

TEST(ScenariosCsvErrors, DuplicateId) {
  expect_read_error(std::string(kHeader) +
                        "S001,boundary,1,2,c0.0,,,1,5\nS002,boundary,1,2,c0.0,,,1,6\n"
                        "S001,top_up,1,2,c0.0,,,1,7\n",
                    4, 1, "duplicate scenario id 'S001'");
}

TEST(ScenariosCsvErrors, EmptyFile) {
  expect_read_error("", 1, 1, "empty");
  expect_read_error("\n\n", 1, 1, "empty");
}

TEST(ScenariosCsvErrors, LinesCountTheNewlinesInsideQuotedFields) {
  // Row S001 spans lines 2-4; the bad weight of S002 is on line 5.
  const std::string text = std::string(kHeader) +
                           "S001,boundary,1,2,c0.0,\"M1\",\"S1 -a, b-> S2\nS2 -c-> S3\n\",1,5\n"
                           "S002,boundary,1,2,c0.0,,,oops,6\n";
  expect_read_error(text, 5, 26, "weight");
}

TEST(ScenariosCsv, QuotedFieldWithCommasAndNewlinesParses) {
  const std::string text =
      std::string(kHeader) +
      "S001,\"boundary, edge\",1.5,-2e-3,c0.1,\"M1 M2\",\"S1 -a,b-> S2; S2 -x\ny-> S3\",0.25,42\r\n";
  const auto file = read_scenarios_csv(write_temp("quoted.csv", text));
  EXPECT_THAT(file.factors, ElementsAre("a", "b"));
  ASSERT_EQ(file.rows.size(), 1u);
  const auto& r = file.rows[0];
  EXPECT_EQ(r.step, "boundary, edge");
  EXPECT_THAT(r.values, ElementsAre(1.5, -2e-3));
  EXPECT_EQ(r.cell, "c0.1");
  EXPECT_THAT(r.malfunctions, ElementsAre("M1", "M2"));
  EXPECT_THAT(r.transitions, ElementsAre("S1 -a,b-> S2", "S2 -x\ny-> S3"));
  EXPECT_DOUBLE_EQ(r.weight, 0.25);
  EXPECT_EQ(r.seed, 42u);
}

TEST(ScenariosCsv, MissingFileIsAnError) { EXPECT_THROW((void)read_scenarios_csv(temp_dir() / "no_such.csv"), Error); }

// ---- core::parse_csv -----------------------------------------------------------------------------

TEST(ParseCsv, AcceptsCrlfAndSkipsBlankLines) {
  const auto records = core::parse_csv("a,b\r\n\r\nc,d\r\n", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_THAT(records[0].fields, ElementsAre("a", "b"));
  EXPECT_THAT(records[1].fields, ElementsAre("c", "d"));
  EXPECT_THAT(records[1].lines, ElementsAre(3, 3));
  EXPECT_THAT(records[1].columns, ElementsAre(1, 3));
}

TEST(ParseCsv, LastLineWithoutNewlineAndEmptyFields) {
  const auto records = core::parse_csv("a,,c\n,,", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_THAT(records[0].fields, ElementsAre("a", "", "c"));
  EXPECT_THAT(records[1].fields, ElementsAre("", "", ""));
}

TEST(ParseCsv, EscapedQuotesCommasAndNewlinesInsideQuotes) {
  const auto records = core::parse_csv("x,\"he said \"\"hi, there\"\"\",\"two\nlines\",y\nz\n", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_THAT(records[0].fields, ElementsAre("x", "he said \"hi, there\"", "two\nlines", "y"));
  // Where each field starts: the quote of a quoted field; "y" after the embedded newline.
  EXPECT_THAT(records[0].lines, ElementsAre(1, 1, 1, 2));
  EXPECT_THAT(records[0].columns, ElementsAre(1, 3, 27, 8));
  EXPECT_THAT(records[1].lines, ElementsAre(3));
}

TEST(ParseCsv, RoundTripsWhatCsvLineWrites) {
  const core::Row fields{"plain", "with,comma", "with \"quote\"", "two\nlines", "", "crlf\r\nend"};
  const auto records = core::parse_csv(core::csv_line(fields) + core::csv_line(fields), "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].fields, fields);
  EXPECT_EQ(records[1].fields, fields);
}

TEST(ParseCsv, UnterminatedQuoteIsReportedWhereTheFieldStarts) {
  try {
    (void)core::parse_csv("a,b\nc,\"never\nclosed,here\n", "t.csv");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "t.csv");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 3);
    EXPECT_THAT(e.what(), HasSubstr("unterminated"));
  }
}

TEST(ParseCsv, TextAfterAClosingQuoteIsAnError) {
  try {
    (void)core::parse_csv("a,\"b\"c\n", "t.csv");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 1);
    EXPECT_EQ(e.where().column, 6);
  }
}

}  // namespace plan_io_test
}  // namespace emrm::scenario
