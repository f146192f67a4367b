#include "emrm/results/paper_reference.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace emrm::results {
namespace paper_reference_test {

using ::testing::HasSubstr;

std::string shipped_reference_text() {
  std::ifstream in(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/paper_reference.yaml");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

PaperReference shipped() {
  return load_paper_reference(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/paper_reference.yaml");
}

TEST(PaperReference, ShippedFileLoadsEveryNumber) {
  const auto p = shipped();
  EXPECT_EQ(p.fine_grid.feasible_cells, 1165);
  EXPECT_DOUBLE_EQ(p.fine_grid.regions_pct.g, 44.5);
  EXPECT_DOUBLE_EQ(p.fine_grid.regions_pct.r, 18.2);
  ASSERT_EQ(p.emrm_vs_baseline.columns.size(), 4u);
  EXPECT_EQ(p.emrm_vs_baseline.columns[0].strategy, "emergency_stop");
  EXPECT_DOUBLE_EQ(p.emrm_vs_baseline.columns[0].mean_residual_impact_speed_kph, 18.9);
  EXPECT_DOUBLE_EQ(p.emrm_vs_baseline.columns[2].delta_loss, 4.75);
  const auto* speed = p.by_parameter_row("speed");
  ASSERT_NE(speed, nullptr);
  EXPECT_EQ(*speed->values.of("dodge"), (std::vector<double>{96, 83, 46}));
  EXPECT_EQ(speed->tests, (std::vector<int>{390, 469, 306}));
  EXPECT_EQ(p.by_parameter_row("passage")->tests, (std::vector<int>{8}));
  EXPECT_DOUBLE_EQ(p.claims.emergency_stop_never_avoids_above_kph, 56);
  EXPECT_DOUBLE_EQ(p.claims.coverage_pct.stpa_only, 19);
}

TEST(PaperReference, WrongVersionFailsAtItsLineAndColumn) {
  std::string text = shipped_reference_text();
  text.replace(text.find("version: 1"), 10, "version: 2");
  try {
    (void)parse_paper_reference(text, "ref.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "ref.yaml");
    EXPECT_GT(e.where().line, 0);
    EXPECT_EQ(e.where().column, 10);
    EXPECT_THAT(e.what(), HasSubstr("version 2"));
  }
}

TEST(PaperReference, BadValuesFailWithLocation) {
  const std::string good = shipped_reference_text();
  const auto fails = [&](const std::string& from, const std::string& to, const std::string& message) {
    std::string text = good;
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    try {
      (void)parse_paper_reference(text, "ref.yaml");
      ADD_FAILURE() << "expected InputError for " << to;
    } catch (const InputError& e) {
      EXPECT_GT(e.where().line, 0) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  };
  fails("G: 44.5", "G: 144.5", "percentage");
  fails("dodge: [96, 83, 46]", "dodge: [96, 83]", "2 entries for 3 levels");
  fails("factor: speed", "factor: weather", "unknown factor");
  fails("strategy: dodge", "strategy: swerve", "unknown strategy");
  fails("feasible_cells: 1165", "feasible_cell: 1165", "feasible_cell");
  fails("delta_loss: 3.29", "delta_loss: lots", "");
}

}  // namespace paper_reference_test
}  // namespace emrm::results
