// End-to-end: `emrm sweep --adaptive` as a user runs it (docs/adaptive.md): the summary line, the
// method column, a rerun that resumes, a full sweep over an adaptive one, thread counts, verify,
// and bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_emrm.hpp"
#include "test_scale.hpp"

namespace emrm::e2e {
namespace adaptive_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// 5 speeds x 12 TTCs at mu 1: G, Y and R cells with boundaries between them, about 35 feasible.
constexpr const char* kCampaign =
    "seed: 2\n"
    "grids:\n"
    "  - name: map\n"
    "    speed_kph: [30, 40, 50, 60, 70]\n"
    "    ttc_s: {from: 0.25, to: 2.45, levels: 12}\n"
    "    mu: 1.0\n"
    "    passage_m: 3.0\n";

// The same over 3 speeds and 8 TTCs, for the sanitized builds where the full sweep of the
// threads test is most of its time.
constexpr const char* kSmallCampaign =
    "seed: 2\n"
    "grids:\n"
    "  - name: map\n"
    "    speed_kph: [30, 50, 70]\n"
    "    ttc_s: {from: 0.25, to: 2.35, levels: 8}\n"
    "    mu: 1.0\n"
    "    passage_m: 3.0\n";

fs::path campaign_file(const std::string& name, const std::string& text = kCampaign) {
  const fs::path dir = scratch_dir(name);
  write_text(dir / "campaign.yaml", "scene: " + example("scene.yaml") + "\n" + text);
  return dir / "campaign.yaml";
}

// regions.csv as rows of cells, each a map from column to value.
std::vector<std::map<std::string, std::string>> regions(const fs::path& dir) {
  std::istringstream in(read_text(dir / "regions.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> columns;
  for (std::istringstream header(line); std::getline(header, line, ',');) columns.push_back(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::istringstream fields(line);
    for (const auto& c : columns) std::getline(fields, row[c], ',');
    rows.push_back(row);
  }
  return rows;
}

std::string fmt_count(std::size_t simulated, std::size_t feasible) {
  return "simulated " + std::to_string(simulated) + " of " + std::to_string(feasible) + " cells";
}

// Exit 2 and the message on the first line (an option's error adds CLI11's "Run with --help").
void expect_bad_input_first_line(const RunResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err.substr(0, r.err.find('\n')), HasSubstr(what)) << r.err;
  EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
}

TEST(AdaptiveCli, SimulatesAFractionAndSaysWhichCellsWereInferred) {
  const fs::path campaign = campaign_file("adaptive-map");
  const fs::path out = campaign.parent_path() / "out";
  const RunResult r = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(out) + " --adaptive --verify-sample 3");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("grid 'map': simulated "));
  EXPECT_THAT(r.out, HasSubstr("verification: "));
  std::size_t simulated = 0, inferred = 0, feasible = 0;
  for (const auto& row : regions(out)) {
    if (row.at("feasible") != "1") {
      EXPECT_EQ(row.at("method"), "");
      continue;
    }
    ++feasible;
    simulated += row.at("method") == "simulated";
    inferred += row.at("method") == "inferred";
  }
  EXPECT_GT(inferred, 0U);
  EXPECT_EQ(simulated + inferred, feasible);
  EXPECT_THAT(r.out, HasSubstr(fmt_count(simulated, feasible)));
  EXPECT_THAT(read_text(out / "cells.json"), HasSubstr("\"inferred_from\""));
  // Resumed: the rerun simulates nothing and writes the same map.
  const std::string before = read_text(out / "regions.csv");
  const RunResult again =
      run_emrm("sweep " + quoted(campaign) + " -o " + quoted(out) + " --adaptive --verify-sample 3");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_THAT(again.out, HasSubstr(": 0 simulated,"));
  EXPECT_EQ(read_text(out / "regions.csv"), before);
  // verify checks the grounds of every inferred cell and replays the simulated ones.
  const RunResult verified = run_emrm("verify " + quoted(out));
  EXPECT_EQ(verified.exit_code, 0) << verified.out << verified.err;
  EXPECT_THAT(verified.out, HasSubstr("inferred by an adaptive sweep"));
}

TEST(AdaptiveCli, TheMapDoesNotDependOnTheThreadCountAndAFullSweepReplacesTheInferredCells) {
  const fs::path campaign = campaign_file("adaptive-threads", test::sample(kCampaign, kSmallCampaign));
  const fs::path one = campaign.parent_path() / "one", two = campaign.parent_path() / "two";
  ASSERT_EQ(run_emrm("sweep " + quoted(campaign) + " -o " + quoted(one) + " --adaptive --threads 1").exit_code, 0);
  ASSERT_EQ(run_emrm("sweep " + quoted(campaign) + " -o " + quoted(two) + " --adaptive --threads 2").exit_code, 0);
  EXPECT_EQ(read_text(one / "regions.csv"), read_text(two / "regions.csv"));
  // A full sweep into the same folder simulates what was inferred; G is exact either way.
  const auto adaptive = regions(one);
  const RunResult full = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(one));
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const auto simulated = regions(one);
  ASSERT_EQ(adaptive.size(), simulated.size());
  for (std::size_t i = 0; i < simulated.size(); ++i) {
    if (simulated[i].at("feasible") != "1") continue;
    EXPECT_EQ(simulated[i].at("method"), "simulated");
    EXPECT_EQ(adaptive[i].at("region") == "G", simulated[i].at("region") == "G")
        << "cell " << i << ": " << adaptive[i].at("region") << " vs " << simulated[i].at("region");
  }
}

TEST(AdaptiveCli, AdaptiveInTheCampaignFileAndDegenerateGrids) {
  const fs::path campaign = campaign_file("adaptive-file",
                                          "grids:\n"
                                          "  - name: one\n"
                                          "    adaptive: true\n"
                                          "    speed_kph: 50\n"
                                          "    ttc_s: 1.0\n"
                                          "  - name: line\n"
                                          "    adaptive: true\n"
                                          "    speed_kph: 50\n"
                                          "    ttc_s: {from: 0.3, to: 1.8, levels: 6}\n"
                                          "  - name: full\n"
                                          "    speed_kph: [40, 60]\n");
  const fs::path out = campaign.parent_path() / "out";
  const RunResult r = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("grid 'one': simulated 1 of 1 cells (100.0 %)"));
  EXPECT_THAT(r.out, HasSubstr("grid 'line': simulated "));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("grid 'full'")));
}

TEST(AdaptiveCli, BadInputIsRefusedWithOneLine) {
  const fs::path campaign = campaign_file("adaptive-bad");
  const fs::path out = campaign.parent_path() / "out";
  const std::string sweep = "sweep " + quoted(campaign) + " -o " + quoted(out) + " --adaptive ";
  for (const char* value : {"-1", "nan", "abc", "1e3", "2000000", "inf"})
    expect_bad_input_first_line(run_emrm(sweep + "--verify-sample " + value), "--verify-sample");
  expect_bad_input_first_line(run_emrm(sweep + "--initial-levels 1"), "--initial-levels");
  expect_bad_input_first_line(run_emrm(sweep + "--stride 0"), "--stride");
  for (const char* value : {"0", "-1", "nan", "abc", "1001", "2.5"})
    expect_bad_input_first_line(run_emrm(sweep + "--spread " + value), "--spread");
  for (const char* value : {"exact", "", "1", "Predict"})
    expect_bad_input_first_line(run_emrm(sweep + "--brackets '" + value + "'"), "--brackets");
  expect_bad_input_first_line(run_emrm(sweep + "--adaptive-levels 3"), "unknown option '--adaptive-levels'");
  expect_bad_input_first_line(run_emrm(sweep + "--shard 1/2"), "--shard cannot split an adaptive sweep");
  const fs::path listed = campaign_file("adaptive-listed",
                                        "grids:\n"
                                        "  - name: listed\n"
                                        "    adaptive: true\n"
                                        "    cells:\n"
                                        "      - {speed_kph: 50, ttc_s: 1.0}\n");
  const RunResult r = run_emrm("sweep " + quoted(listed) + " -o " + quoted(listed.parent_path() / "out"));
  expect_bad_input_first_line(r, "adaptive needs a product grid");
  EXPECT_THAT(r.err, HasSubstr("campaign.yaml:4:"));
  const fs::path word = campaign_file("adaptive-word", "grids:\n  - name: g\n    adaptive: maybe\n    speed_kph: 50\n");
  expect_bad_input_first_line(run_emrm("sweep " + quoted(word) + " -o " + quoted(word.parent_path() / "out")),
                              "campaign.yaml:4:");
  EXPECT_FALSE(fs::exists(out / "regions.csv"));
}

}  // namespace adaptive_cli_test
}  // namespace emrm::e2e
