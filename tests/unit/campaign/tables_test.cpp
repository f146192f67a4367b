#include "emrm/campaign/tables.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace emrm::campaign {
namespace {

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

OutcomeRecord outcome(std::string strategy, bool avoided, double impact_kph, int level, int unmitigated) {
  OutcomeRecord o;
  o.strategy = std::move(strategy);
  o.avoided = avoided;
  o.contact = !avoided;
  o.impact_speed_kph = avoided ? 0.0 : impact_kph;
  o.loss_level = avoided ? 0 : level;
  o.delta_loss = unmitigated - o.loss_level;
  o.min_ttc_s = 0.5;
  return o;
}

// Two fine cells: 30 km/h avoided by everyone (G); 60 km/h avoided only by the evasive ones (Y).
std::vector<CellRecord> two_cells() {
  std::vector<CellRecord> cells(2);
  const std::vector<std::string> names{"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident",
                                       "emrm"};
  for (int i = 0; i < 2; ++i) {
    auto& c = cells[static_cast<std::size_t>(i)];
    c.grid = "fine";
    c.index = i;
    c.speed_kph = i == 0 ? 30 : 60;
    c.ttc_s = 1.0;
    c.mu = 1.0;
    c.passage_m = 3.0;
    c.feasible = true;
    c.region = i == 0 ? "G" : "Y";
    c.unmitigated_loss_level = 7;
    for (const auto& n : names) c.outcomes.push_back(outcome(n, i == 0 || n != "emergency_stop", 40.0, 7, 7));
  }
  return cells;
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

TEST(Tables, LatexEscapesSpecialCharacters) {
  EXPECT_EQ(latex_escape("a_b & 50% #1 {x} $y ~ ^ \\"),
            "a\\_b \\& 50\\% \\#1 \\{x\\} \\$y \\textasciitilde{} \\textasciicircum{} \\textbackslash{}");
  EXPECT_EQ(latex_escape("ΔLoss μ ≥ —"), "$\\Delta$Loss $\\mu$ $\\geq$ ---");
  Table t{"T", {"a_1", "b"}, {{"x%", "y"}}, {}};
  const auto tex = to_latex(t);
  EXPECT_THAT(tex, HasSubstr("\\begin{tabular}{|l|c|}"));
  EXPECT_THAT(tex, HasSubstr("a\\_1 & b \\\\ \\hline"));
  EXPECT_THAT(tex, HasSubstr("x\\% & y \\\\ \\hline"));
  EXPECT_THAT(tex, HasSubstr("\\end{tabular}"));
}

TEST(Tables, EmrmVsBaselineShowsOursBesideThePapers) {
  const auto t = emrm_vs_baseline_table(two_cells(), shipped(), "fine");
  ASSERT_GE(t.rows.size(), 4u);
  EXPECT_EQ(t.rows[0][0], "Collision Avoidance Rate (%)");
  EXPECT_EQ(t.rows[0][1], "50.0 (paper 45)");   // emergency stop
  EXPECT_EQ(t.rows[0][2], "100.0 (paper 81)");  // dodge
  EXPECT_EQ(t.rows[1][1], "20.0 (paper 18.9)");
  EXPECT_EQ(t.rows[3][1], "3.50 (paper 3.29)");
  const auto md = to_markdown(t);
  EXPECT_THAT(md, HasSubstr("is our `drift_to_avoid`"));
  EXPECT_THAT(md, HasSubstr("Where ours differ"));
  const auto csv = to_csv(t);
  EXPECT_THAT(csv, HasSubstr("(paper 45)"));
}

TEST(Tables, ByParameterUsesThePapersLayout) {
  const auto t = by_parameter_table(two_cells(), shipped(), "fine", "", "");
  ASSERT_EQ(t.rows.size(), 4u);
  EXPECT_THAT(t.rows[0][0], HasSubstr("Ego speed"));
  // Emergency stop: 30 km/h avoided (low), 60 km/h not (high).
  EXPECT_EQ(t.rows[0][4], "100 / — / 0 (paper 65 / 46 / 18)");
  EXPECT_EQ(t.rows[0][5], "1 / 0 / 1 (paper 390 / 469 / 306)");
  EXPECT_EQ(t.rows[2][1], "100 (paper 81)");
  EXPECT_THAT(to_markdown(t), HasSubstr("collision-avoidance rates"));
}

TEST(Tables, RegionsShowThePapersFineGrid) {
  const auto t = regions_table(two_cells(), shipped());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (core::Row{"fine", "2", "2", "0", "50.0", "50.0", "0.0", "0.0"}));
  EXPECT_EQ(t.rows[1][0], "fine (paper)");
  EXPECT_EQ(t.rows[1][4], "44.5");
  EXPECT_THAT(to_markdown(t), HasSubstr("TTC ≥ v/(2μg)"));
}

TEST(Tables, WritesEveryFile) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-tables-test";
  std::filesystem::remove_all(dir);
  const auto files = write_tables(dir, two_cells(), shipped());
  EXPECT_EQ(files.size(), 13u);
  for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
  std::ifstream in(dir / "tables" / "kpis.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_THAT(header, HasSubstr("mitigability_success_pct"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace emrm::campaign
