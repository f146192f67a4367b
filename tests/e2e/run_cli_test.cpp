// `emrm run` end to end: a small plan is simulated through the campaign engine; the per-cell Wilson
// intervals follow from the stored outcomes by the closed form; a rerun resumes; results do not
// depend on the thread count; the traceability matrix gets its scenarios; bad files are bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace run_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// Wilson score interval, written out independently of the library.
std::pair<double, double> wilson(double k, double n, double z) {
  const double p = k / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

// "…): n = N → M at the observed rate (+M−N)", the tail of a shortfall line of the report.
std::string fmt_count(int n, int m) {
  return "n = " + std::to_string(n) + " → " + std::to_string(m) + " at the observed rate (+" + std::to_string(m - n) +
         ")";
}

class RunCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto example_dir = small_example("run");
    plan_ = new fs::path(example_dir.parent_path() / "plan");
    const auto r = run_emrm("plan " + quoted(example_dir / "odd.yaml") + " -o " + quoted(*plan_));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  }
  static void TearDownTestSuite() { delete plan_; }
  static fs::path* plan_;
};
fs::path* RunCli::plan_ = nullptr;

// Every table that names a cell also says where it lies: outcomes.csv carries each scenario's factor
// values (as in scenarios.csv), estimates.csv each cell's bin of every factor (from scenarios.json).
TEST_F(RunCli, TablesNameCellsByTheirFactors) {
  const auto out = plan_->parent_path() / "labelled";
  const auto r = run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto scenarios = csv_rows(*plan_ / "scenarios.csv");
  const auto outcomes = csv_rows(out / "outcomes.csv");
  ASSERT_EQ(outcomes.size(), scenarios.size());
  for (const std::string factor : {"speed_kph", "ttc_s", "mu"})
    for (std::size_t i = 1; i < outcomes.size(); ++i)
      EXPECT_DOUBLE_EQ(std::stod(outcomes[i][column_of(outcomes.front(), factor)]),
                       std::stod(scenarios[i][column_of(scenarios.front(), factor)]))
          << factor << " of " << outcomes[i][0];
  // The bins: each cell's labels are those scenarios.json gives it, and each scenario lies inside.
  const auto plan = nlohmann::json::parse(read_text(*plan_ / "scenarios.json"));
  std::map<std::string, nlohmann::json> levels;
  for (const auto& c : plan["cells"]) levels[c["cell"].get<std::string>()] = c["levels"];
  const auto estimates = csv_rows(out / "estimates.csv");
  const auto& h = estimates.front();
  ASSERT_GT(estimates.size(), 1u);
  for (std::size_t i = 1; i < estimates.size(); ++i) {
    const auto& expected = levels.at(estimates[i][column_of(h, "cell")]);
    ASSERT_FALSE(expected.empty());
    for (const auto& [factor, label] : expected.items())
      EXPECT_EQ(estimates[i][column_of(h, factor)], label.get<std::string>()) << estimates[i][0];
  }
}

// The report's statistics section: per cell whether the precision target is met, and for each cell
// that misses it how many tests would meet it at the observed rate (a tighter target is set by
// editing estimates.json, as a user would ask "and at ±0.15?").
TEST_F(RunCli, TheReportSaysWhichCellsMissTheirTargetAndWhatWouldMeetIt) {
  const auto out = plan_->parent_path() / "statistics";
  const auto r = run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  auto j = nlohmann::ordered_json::parse(read_text(out / "estimates.json"));
  constexpr double kTarget = 0.15;
  j["epsilon"] = kTarget;
  write_text(out / "estimates.json", j.dump(2));
  ASSERT_EQ(run_emrm("report " + quoted(out)).exit_code, 0);
  const std::string html = read_text(out / "report.html");

  const double z = 1.959963985;
  std::size_t tracked = 0, met = 0;
  std::string example;  // the first cell that misses: "CELL (bins…): n = N → M"
  for (const auto& c : j["cells"]) {
    if (!c["tracked"].get<bool>()) continue;
    ++tracked;
    const auto n = c["n"].get<int>(), k = c["successes"].get<int>();
    if (0.5 * (c["wilson"][1].get<double>() - c["wilson"][0].get<double>()) <= kTarget) {
      ++met;
      continue;
    }
    if (!example.empty()) continue;
    int m = n;  // the least m at which the observed rate's Wilson half-width is within the target
    for (;; ++m) {
      const auto [low, high] = wilson(static_cast<double>(k) / n * m, m, z);
      if (0.5 * (high - low) <= kTarget) break;
    }
    example = c["cell"].get<std::string>() + " (";
    example += fmt_count(n, m);
  }
  ASSERT_GT(tracked, met) << "the tighter target must leave some cell short";
  EXPECT_THAT(html, HasSubstr(std::to_string(met) + " of " + std::to_string(tracked) + " tracked cells meet it"));
  EXPECT_THAT(html, HasSubstr(std::to_string(tracked - met) + " tracked cells miss the target"));
  const auto start = example.find(" (");
  EXPECT_THAT(html, HasSubstr(example.substr(0, start + 2)));
  EXPECT_THAT(html, HasSubstr(example.substr(start + 2)));
  EXPECT_THAT(html, HasSubstr("Hoeffding"));
}

// A scenarios.json edited by hand: a seed of 1e300 (undefined behaviour converting it) or -1 (it
// wrapped) and an epsilon outside (0, 0.5) are bad input, not a run with other settings.
TEST_F(RunCli, EditedSettingsOutOfRangeAreBadInput) {
  const std::vector<std::pair<std::string, std::string>> edits{
      {"seed", "1e300"}, {"seed", "-1"}, {"epsilon", "-0.3"}, {"epsilon", "5"}};
  for (const auto& [key, value] : edits) {
    const fs::path copy = plan_->parent_path() / ("plan_" + key);
    fs::remove_all(copy);
    fs::copy(*plan_, copy, fs::copy_options::recursive);
    auto j = nlohmann::ordered_json::parse(read_text(copy / "scenarios.json"));
    j["settings"][key] = nlohmann::ordered_json::parse(value);
    write_text(copy / "scenarios.json", j.dump());
    const auto r = run_emrm("run " + quoted(copy / "scenarios.csv") + " -o " + quoted(copy / "out"));
    EXPECT_EQ(r.exit_code, 2) << key << " " << value << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("settings." + key + ": expected")) << key << " " << value;
  }
}

TEST_F(RunCli, EstimatesFollowFromTheOutcomes) {
  const auto out = plan_->parent_path() / "results";
  const auto r = run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("S(all) = "));

  // Successes per cell from outcomes.csv; the intervals of estimates.csv by the closed form.
  const auto outcomes = csv_rows(out / "outcomes.csv");
  std::map<std::string, std::pair<int, int>> per_cell;
  double weighted = 0.0, weights = 0.0;
  for (std::size_t i = 1; i < outcomes.size(); ++i) {
    const auto& h = outcomes.front();
    if (outcomes[i][column_of(h, "feasible")] != "yes") continue;
    const int y = std::stoi(outcomes[i][column_of(h, "success")]);
    auto& [k, n] = per_cell[outcomes[i][column_of(h, "cell")]];
    k += y;
    ++n;
    const double w = std::stod(outcomes[i][column_of(h, "weight")]);
    weighted += w * y;
    weights += w;
  }
  ASSERT_FALSE(per_cell.empty());
  const auto estimates = csv_rows(out / "estimates.csv");
  const auto& h = estimates.front();
  EXPECT_EQ(estimates.size() - 1, per_cell.size());
  for (std::size_t i = 1; i < estimates.size(); ++i) {
    const auto& [k, n] = per_cell.at(estimates[i][column_of(h, "cell")]);
    EXPECT_EQ(std::stoi(estimates[i][column_of(h, "n")]), n);
    EXPECT_EQ(std::stoi(estimates[i][column_of(h, "successes")]), k);
    const auto [low, high] = wilson(k, n, 1.959963985);
    EXPECT_NEAR(std::stod(estimates[i][column_of(h, "wilson_low")]), low, 1e-5);
    EXPECT_NEAR(std::stod(estimates[i][column_of(h, "wilson_high")]), high, 1e-5);
    // Hoeffding: eps = sqrt(ln(2/delta) / (2n)) at delta 0.05.
    EXPECT_NEAR(std::stod(estimates[i][column_of(h, "hoeffding_epsilon")]), std::sqrt(std::log(40.0) / (2.0 * n)),
                1e-5);
  }
  // S(all) is the weighted success rate.
  const auto j = nlohmann::json::parse(read_text(out / "estimates.json"));
  EXPECT_NEAR(j["weighted_success"]["all"]["estimate"].get<double>(), weighted / weights, 1e-5);  // 6-digit weights

  // The traceability matrix of the analysis layer, scenarios filled: every UCA row names scenarios
  // whose malfunctions include that UCA.
  const auto trace = csv_rows(out / "traceability.csv");
  const auto& th = trace.front();
  int with_scenarios = 0;
  for (std::size_t i = 1; i < trace.size(); ++i) with_scenarios += !trace[i][column_of(th, "scenarios")].empty();
  EXPECT_GT(with_scenarios, 0);

  // A rerun resumes and simulates nothing.
  const auto again = run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(out));
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_THAT(again.out, HasSubstr("0 simulated"));
}

TEST_F(RunCli, ResultsDoNotDependOnTheThreadCount) {
  const auto one = plan_->parent_path() / "one";
  const auto two = plan_->parent_path() / "two";
  ASSERT_EQ(run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(one) + " --threads 1").exit_code, 0);
  ASSERT_EQ(run_emrm("run " + quoted(*plan_ / "scenarios.csv") + " -o " + quoted(two) + " --threads 2").exit_code, 0);
  EXPECT_EQ(read_text(one / "outcomes.csv"), read_text(two / "outcomes.csv"));
  EXPECT_EQ(read_text(one / "estimates.csv"), read_text(two / "estimates.csv"));
}

TEST_F(RunCli, BadScenarioFilesAreBadInputWithLocation) {
  const auto dir = plan_->parent_path() / "bad";
  fs::create_directories(dir);
  const std::string good = read_text(*plan_ / "scenarios.csv");
  const auto second_line = good.find('\n') + 1;

  // A value that is not a number, in row 2: the message names line 2.
  std::string text = good;
  const auto comma = text.find(',', text.find(',', second_line) + 1);  // after id and step
  text.insert(comma + 1, "x");
  write_text(dir / "scenarios.csv", text);
  auto r = run_emrm("run " + quoted(dir / "scenarios.csv") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_THAT(r.err, HasSubstr("scenarios.csv:2:"));
  EXPECT_THAT(r.err, HasSubstr("expected a finite number"));

  // A missing column.
  write_text(dir / "scenarios.csv", "id,step,speed_kph\nS1,boundary,30\n");
  r = run_emrm("run " + quoted(dir / "scenarios.csv") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("scenarios.csv:1:1"));

  // A file that does not exist.
  r = run_emrm("run " + quoted(dir / "nothing.csv") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("does not exist"));

  // A value the simulator rejects (negative speed).
  std::string negative = good;
  const auto speed = negative.find(',', negative.find(',', second_line) + 1) + 1;
  negative.replace(speed, negative.find(',', speed) - speed, "-5");
  write_text(dir / "scenarios.csv", negative);
  r = run_emrm("run " + quoted(dir / "scenarios.csv") + " -o " + quoted(dir / "out2"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("scenarios.csv:2:"));
}

}  // namespace run_cli_test
}  // namespace emrm::e2e
