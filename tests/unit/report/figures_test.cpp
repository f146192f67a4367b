#include "emrm/report/figures.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/plan_figures.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace emrm::report {
namespace figures_test {

namespace fs = std::filesystem;
using campaign::CellRecord;
using campaign::OutcomeRecord;

const std::vector<std::string> kStrategies{"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident", "emrm"};

// --- a synthetic campaign ---------------------------------------------------------------------
// Regions by a simple rule: infeasible beyond 45 m of initial distance; G when the analytic stop
// boundary says the stop avoids; Y when there is still time and grip to steer; O at lower speeds;
// R otherwise. Each strategy avoids in a subset of the cells, so every rate lies strictly between
// 0 and 100 and differs between strategies.
OutcomeRecord outcome(const std::string& strategy, bool avoided, double impact_kph, int level, int unmitigated) {
  OutcomeRecord o;
  o.strategy = strategy;
  o.avoided = avoided;
  o.contact = !avoided;
  o.impact_speed_kph = avoided ? 0.0 : impact_kph;
  o.loss_level = avoided ? 0 : level;
  o.delta_loss = unmitigated - o.loss_level;
  o.min_ttc_s = avoided ? 0.5 : 0.0;
  return o;
}

CellRecord synthetic_cell(const std::string& grid, std::int64_t index, double speed, double ttc, double mu) {
  CellRecord c;
  c.grid = grid;
  c.index = index;
  c.speed_kph = speed;
  c.ttc_s = ttc;
  c.mu = mu;
  c.passage_m = 3.0;
  c.truck_speed_kph = 10.0;
  c.feasible = speed / 3.6 * ttc <= 45.0;
  if (!c.feasible) {
    c.region = "infeasible";
    return c;
  }
  const bool stoppable = sim::analytically_stoppable(speed, ttc, mu, sim::ActuationConfig{});
  const bool steerable = ttc >= 0.6 && mu >= 0.3;
  c.region = stoppable ? "G" : steerable ? "Y" : speed < 45.0 ? "O" : "R";
  // Every seventh O/R cell rests on a failed search only; the others on a certificate.
  c.evidence = c.region == "G" || c.region == "Y" ? "witness" : index % 7 == 0 ? "undecided" : "certificate";
  c.unmitigated_loss_level = speed > 50.0 ? 7 : 6;
  c.unmitigated_impact_speed_kph = speed;
  // Harm reduction: an avoidance removes the whole risk, a mitigation part of it, and half the R
  // cells lower the risk inside their loss level.
  c.unmitigated_p_mais3 = std::min(0.95, std::pow(speed / 80.0, 3.0));
  c.unmitigated_p_fatal = 0.3 * c.unmitigated_p_mais3;
  const double kept = c.region == "O" ? 0.4 : c.region == "R" ? (index % 2 == 0 ? 0.75 : 1.0) : 0.0;
  c.p_mais3_reduction = (1.0 - kept) * c.unmitigated_p_mais3;
  c.p_fatal_reduction = (1.0 - kept) * c.unmitigated_p_fatal;
  const int u = c.unmitigated_loss_level;
  const int lowered = c.region == "O" ? u - 2 : u;
  c.outcomes = {
      outcome("emergency_stop", stoppable, 0.5 * speed, c.region == "O" ? u - 1 : u, u),
      outcome("dodge", stoppable || steerable, 0.6 * speed, lowered, u),
      outcome("drift_to_avoid", stoppable || (steerable && speed < 60.0), 0.55 * speed, lowered, u),
      outcome("drift_to_accident", stoppable || (steerable && index % 3 != 0), 0.4 * speed, u - 1, u),
      outcome("emrm", stoppable || steerable, 0.45 * speed, lowered, u),
  };
  return c;
}

// The shipped campaign's four map grids: coarse 5 × 6, fine 43 × 46, speed × μ 43 × 10,
// TTC × μ 26 × 10: 2698 cells.
std::vector<CellRecord> synthetic_campaign() {
  std::vector<CellRecord> records;
  std::int64_t i = 0;
  for (int s = 0; s < 5; ++s)
    for (int t = 0; t < 6; ++t) records.push_back(synthetic_cell("coarse", i++, 30.0 + 10.5 * s, 0.25 + 0.54 * t, 1.0));
  i = 0;
  for (int s = 0; s < 43; ++s)
    for (int t = 0; t < 46; ++t) records.push_back(synthetic_cell("fine", i++, 30.0 + s, 0.25 + 0.06 * t, 1.0));
  i = 0;
  for (int s = 0; s < 43; ++s)
    for (int m = 0; m < 10; ++m) records.push_back(synthetic_cell("speed_mu", i++, 30.0 + s, 1.0, 0.1 + 0.1 * m));
  i = 0;
  for (int t = 0; t < 26; ++t)
    for (int m = 0; m < 10; ++m)
      records.push_back(synthetic_cell("ttc_mu", i++, 50.0, 0.25 + 0.108 * t, 0.1 + 0.1 * m));
  return records;
}

const std::vector<CellRecord>& campaign_records() {
  static const std::vector<CellRecord> records = synthetic_campaign();
  return records;
}

std::vector<CellRecord> without_grid(const std::string& grid) {
  std::vector<CellRecord> out;
  for (const auto& r : campaign_records())
    if (r.grid != grid) out.push_back(r);
  return out;
}

// --- checks -----------------------------------------------------------------------------------

void expect_png(const fs::path& path) {
  const std::string bytes = core::read_file(path);
  ASSERT_GT(bytes.size(), 5000u) << path;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
}

void expect_svg(const fs::path& path) {
  const std::string text = core::read_file(path);
  ASSERT_GT(text.size(), 1000u) << path;
  EXPECT_TRUE(text.rfind("<?xml", 0) == 0 || text.rfind("<svg", 0) == 0) << path;
  EXPECT_NE(text.find("</svg>"), std::string::npos) << path;
}

void expect_drawn(const Figure& f, const fs::path& dir, const std::string& name) {
  EXPECT_EQ(f.name, name);
  EXPECT_EQ(f.png, dir / (name + ".png"));
  EXPECT_EQ(f.svg, dir / (name + ".svg"));
  EXPECT_EQ(f.csv, dir / (name + ".csv"));
  EXPECT_FALSE(f.title.empty());
  expect_png(f.png);
  expect_svg(f.svg);
}

void expect_nothing_written(const Figure& f, const fs::path& dir) {
  EXPECT_FALSE(f.note.empty());
  EXPECT_FALSE(f.title.empty());  // the report still names the figure it could not draw
  EXPECT_TRUE(f.png.empty() && f.svg.empty() && f.csv.empty());
  EXPECT_TRUE(!fs::exists(dir) || fs::is_empty(dir)) << dir;
}

/// The CSV's header then its rows, as field lists.
std::vector<core::Row> csv_of(const fs::path& path) {
  std::vector<core::Row> rows;
  for (auto& r : core::parse_csv(core::read_file(path), path.string())) rows.push_back(std::move(r.fields));
  return rows;
}

double num(const std::string& field) { return std::strtod(field.c_str(), nullptr); }

// Rates recomputed here, independently of the aggregation, from the definitions of docs/results.md.
struct Rates {
  std::size_t cells = 0;
  double car_pct = 0.0, impact_kph = 0.0, mitigated_pct = 0.0;
};

Rates rates_of(const std::vector<CellRecord>& records, const std::string& strategy, double speed_kph = std::nan("")) {
  Rates r;
  std::size_t avoided = 0, mitigated = 0;
  double impact = 0.0;
  for (const auto& c : records) {
    if (!c.feasible || (!std::isnan(speed_kph) && std::abs(c.speed_kph - speed_kph) > 1e-9)) continue;
    for (const auto& o : c.outcomes) {
      if (o.strategy != strategy) continue;
      ++r.cells;
      if (o.avoided) ++avoided;
      if (!o.avoided) impact += o.impact_speed_kph;
      if ((o.avoided ? 0 : o.loss_level) < c.unmitigated_loss_level) ++mitigated;
    }
  }
  const auto n = static_cast<double>(r.cells);
  r.car_pct = 100.0 * static_cast<double>(avoided) / n;
  r.mitigated_pct = 100.0 * static_cast<double>(mitigated) / n;
  r.impact_kph = impact / n;
  return r;
}

class FigureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!core::find_program("gnuplot")) GTEST_SKIP() << "gnuplot is not installed";
  }
  fs::path out() const { return tmp_.path() / "figures"; }
  core::TempDir tmp_{"emrm-figures-test"};
};

// Drawing nothing needs no gnuplot, so these run everywhere.
class FigureEmpty : public ::testing::Test {
 protected:
  fs::path out() const { return tmp_.path() / "figures"; }
  core::TempDir tmp_{"emrm-figures-test"};
};

// --- the mitigability map ---------------------------------------------------------------------

using FigureMap = FigureTest;

TEST_F(FigureMap, DrawsAllFourPanelsWithEveryCellInItsRecordedRegion) {
  const auto f = draw_mitigability_map(campaign_records(), out());
  expect_drawn(f, out(), "mitigability_map");
  EXPECT_TRUE(f.note.empty()) << f.note;

  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "evidence"}));
  ASSERT_EQ(csv.size(), 1 + 30 + 1978 + 430 + 260);
  std::size_t line = 1;
  for (const auto& [panel, grid] : {std::pair{"a", "coarse"}, {"b", "fine"}, {"c", "speed_mu"}, {"d", "ttc_mu"}}) {
    for (const auto& cell : results::records_of_grid(campaign_records(), grid)) {
      const auto& row = csv[line++];
      ASSERT_EQ(row[0], panel);
      ASSERT_EQ(row[1], grid);
      EXPECT_NEAR(num(row[2]), cell.speed_kph, 1e-6);
      EXPECT_NEAR(num(row[3]), cell.ttc_s, 1e-6);
      EXPECT_NEAR(num(row[4]), cell.mu, 1e-6);
      EXPECT_NEAR(num(row[5]), cell.passage_m, 1e-6);
      EXPECT_EQ(row[6], cell.region) << grid << " cell " << cell.index;
      EXPECT_EQ(row[7], cell.feasible ? cell.evidence : "") << grid << " cell " << cell.index;
    }
  }
  // The caption states the region shares of each panel, as count_regions gives them.
  EXPECT_NE(f.title.find("(b) Speed × TTC, fine grid"), std::string::npos) << f.title;
}

TEST_F(FigureMap, LeavesOutAMissingPanelAndSaysWhich) {
  const auto f = draw_mitigability_map(without_grid("ttc_mu"), out());
  expect_drawn(f, out(), "mitigability_map");
  EXPECT_NE(f.note.find("'ttc_mu'"), std::string::npos) << f.note;
  EXPECT_NE(f.note.find("(d)"), std::string::npos) << f.note;
  const auto csv = csv_of(f.csv);
  EXPECT_EQ(csv.size(), 1 + 30 + 1978 + 430);
  EXPECT_TRUE(std::none_of(csv.begin(), csv.end(), [](const core::Row& r) { return r[0] == "d"; }));
}

TEST_F(FigureMap, DrawsTheLatencyShiftedBoundaryOnOtherGridNames) {
  MapPanels panels;
  panels.coarse = "fine";  // any grid may stand in any panel
  panels.fine = "missing_a";
  panels.speed_mu = "missing_b";
  panels.ttc_mu = "ttc_mu";
  const auto f = draw_mitigability_map(campaign_records(), out(), panels, 0.2);
  expect_drawn(f, out(), "mitigability_map");
  EXPECT_EQ(csv_of(f.csv).size(), 1 + 1978 + 260);
  EXPECT_NE(f.title.find("0.2 s"), std::string::npos) << f.title;
  EXPECT_NE(f.note.find("missing_a"), std::string::npos);
  EXPECT_NE(f.note.find("missing_b"), std::string::npos);
}

TEST_F(FigureMap, SameRecordsGiveTheSameCsvBytes) {
  const auto a = draw_mitigability_map(campaign_records(), out() / "a");
  const auto b = draw_mitigability_map(campaign_records(), out() / "b");
  EXPECT_EQ(core::read_file(a.csv), core::read_file(b.csv));
  EXPECT_EQ(a.title, b.title);
}

// Where a cell's region rests on a failed search (undecided), the map says so with a cross; a
// certificate needs no mark. In gnuplot's SVG each cross is one <use> of the cross symbol (pt 2,
// '#gpPt1'), and the key's sample is one more.
std::size_t crosses_in(const fs::path& svg) {
  const std::string text = core::read_file(svg);
  std::size_t n = 0;
  for (auto at = text.find("<use xlink:href='#gpPt1'"); at != std::string::npos;
       at = text.find("<use xlink:href='#gpPt1'", at + 1))
    ++n;
  return n;
}

std::size_t count_evidence(const std::vector<CellRecord>& records, const std::string& evidence) {
  return static_cast<std::size_t>(std::count_if(records.begin(), records.end(), [&](const CellRecord& c) {
    return c.feasible && (c.region == "O" || c.region == "R") && c.evidence == evidence;
  }));
}

TEST_F(FigureMap, MarksEveryUndecidedCellWithACrossAndSaysSoInTheKey) {
  const auto& records = campaign_records();
  const std::size_t undecided = count_evidence(records, "undecided");
  const std::size_t certified = count_evidence(records, "certificate");
  ASSERT_GT(undecided, 10u);  // the synthetic campaign has some of each
  ASSERT_GT(certified, 10u);
  const auto f = draw_mitigability_map(records, out());
  expect_drawn(f, out(), "mitigability_map");

  // The CSV has every cell's evidence; the undecided rows are exactly the crosses.
  const auto csv = csv_of(f.csv);
  EXPECT_EQ(static_cast<std::size_t>(
                std::count_if(csv.begin(), csv.end(), [](const core::Row& r) { return r[7] == "undecided"; })),
            undecided);
  EXPECT_EQ(crosses_in(f.svg), undecided + 1);
  const std::string svg = core::read_file(f.svg);
  EXPECT_NE(svg.find("undecided (no avoidance found,"), std::string::npos);
  EXPECT_NE(svg.find("none proven impossible)"), std::string::npos);
  EXPECT_NE(svg.find("36 undecided"), std::string::npos);  // panel (b)'s subtitle
  // The caption counts them and says what an unmarked O/R cell is.
  EXPECT_NE(f.title.find(fmt::format("A cross marks the {} undecided O/R cells", undecided)), std::string::npos)
      << f.title;
  EXPECT_NE(f.title.find(fmt::format("The unmarked O/R cells ({}) are certified unavoidable", certified)),
            std::string::npos)
      << f.title;
}

TEST_F(FigureMap, WithoutUndecidedCellsTheMapIsDrawnAsWithoutEvidence) {
  std::vector<CellRecord> certified = campaign_records(), unknown = campaign_records();
  for (auto& c : certified)
    if (c.evidence == "undecided") c.evidence = "certificate";
  for (auto& c : unknown) c.evidence.clear();
  const auto a = draw_mitigability_map(certified, out() / "certified");
  const auto b = draw_mitigability_map(unknown, out() / "unknown");
  EXPECT_EQ(crosses_in(a.svg), 0u);
  EXPECT_EQ(core::read_file(a.svg).find("undecided"), std::string::npos);
  // Nothing on the picture depends on the evidence then; only the CSV and the caption tell it.
  EXPECT_EQ(core::read_file(a.svg), core::read_file(b.svg));
  EXPECT_NE(a.title.find(
                fmt::format("All O/R cells ({}) are certified unavoidable", count_evidence(certified, "certificate"))),
            std::string::npos)
      << a.title;
  EXPECT_EQ(b.title.find("certified"), std::string::npos) << b.title;
}

TEST_F(FigureEmpty, MapWithoutAnyOfItsGridsWritesNothing) {
  const auto f = draw_mitigability_map({}, out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("coarse"), std::string::npos) << f.note;
}

// --- maps of any grid -------------------------------------------------------------------------

using FigureGridMaps = FigureTest;

/// A grid `name` over the product of the values given, in expansion order.
std::vector<CellRecord> product_grid(const std::string& name, const std::vector<double>& speeds,
                                     const std::vector<double>& ttcs, const std::vector<double>& mus,
                                     const std::vector<double>& passages = {3.0}) {
  std::vector<CellRecord> cells;
  std::int64_t i = 0;
  for (const double m : mus)
    for (const double p : passages)
      for (const double v : speeds)
        for (const double t : ttcs) {
          cells.push_back(synthetic_cell(name, i++, v, t, m));
          cells.back().passage_m = p;
        }
  return cells;
}

std::vector<std::string> names_of(const std::vector<Figure>& figures) {
  std::vector<std::string> names;
  for (const auto& f : figures) names.push_back(f.name);
  return names;
}

TEST_F(FigureGridMaps, AGridOfAnyNameIsMappedWithItsUndecidedCellsCrossed) {
  const auto cells = product_grid("wet", {30, 35, 40, 45, 50, 55}, {0.25, 0.5, 0.75, 1.0, 1.25}, {0.5});
  const std::size_t undecided = count_evidence(cells, "undecided");
  ASSERT_GT(undecided, 0u);
  const auto figures = draw_grid_maps(cells, out());
  ASSERT_EQ(names_of(figures), std::vector<std::string>{"map_wet"});
  const Figure& f = figures.front();
  expect_drawn(f, out(), "map_wet");
  EXPECT_NE(f.title.find("grid 'wet': 6 speeds × 5 TTCs, μ = 0.5"), std::string::npos) << f.title;
  EXPECT_NE(f.title.find(fmt::format("A cross marks the {} undecided O/R cells", undecided)), std::string::npos);
  EXPECT_EQ(crosses_in(f.svg), undecided + 1);  // and the key's
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) EXPECT_EQ(csv[i + 1][6], cells[i].region) << i;
}

TEST_F(FigureGridMaps, OneMapPerSliceNamedByItsValuesAndTheRestNamedInANote) {
  // Speed × TTC × μ × passage: slices along μ and passage, in ascending order of both.
  const auto cells = product_grid("g 4", {30, 40}, {0.5, 1.0}, {0.3, 0.6}, {2.0, 3.0});
  GridMapOptions options;
  options.max_slices_per_grid = 3;
  const auto figures = draw_grid_maps(cells, out(), options);
  ASSERT_EQ(names_of(figures), (std::vector<std::string>{"map_g_4_mu_0.3_passage_m_2", "map_g_4_mu_0.3_passage_m_3",
                                                         "map_g_4_mu_0.6_passage_m_2", "map_g_4_more"}));
  for (std::size_t i = 0; i < 3; ++i) {
    expect_drawn(figures[i], out(), figures[i].name);
    EXPECT_EQ(csv_of(figures[i].csv).size(), 1u + 4u);  // its own four cells
  }
  EXPECT_NE(figures[1].title.find("grid 'g 4', slice μ = 0.3, passage 3 m: 2 speeds × 2 TTCs"), std::string::npos)
      << figures[1].title;
  const Figure& more = figures.back();
  EXPECT_TRUE(more.png.empty() && more.csv.empty());
  EXPECT_NE(more.note.find("4 slices; the first 3 are drawn, these not: μ = 0.6, passage 3 m"), std::string::npos)
      << more.note;
}

TEST_F(FigureGridMaps, AGridVaryingOneFactorIsAStrip) {
  const auto cells = product_grid("speeds", {30, 40, 50, 60, 70}, {1.0}, {1.0});
  const auto figures = draw_grid_maps(cells, out());
  ASSERT_EQ(names_of(figures), std::vector<std::string>{"map_speeds"});
  expect_drawn(figures.front(), out(), "map_speeds");
  EXPECT_NE(figures.front().title.find("5 speeds × 1 TTCs"), std::string::npos) << figures.front().title;
}

TEST_F(FigureEmpty, GridMapsLeaveOutTheGridsTheyAreToldTo) {
  GridMapOptions options;
  options.skip = {"coarse", "fine", "speed_mu", "ttc_mu"};
  EXPECT_TRUE(draw_grid_maps(campaign_records(), out(), options).empty());
}

// --- a planned run ------------------------------------------------------------------------------

using FigurePlanMaps = FigureTest;

// Factors a (2 levels), k (constant), b (3 levels), c (2 levels); one scenario per cell; the cells
// with a = 1, b = 2 infeasible; success when a + b is even.
PlannedRun synthetic_run() {
  PlannedRun run;
  run.factors = {{"a", "m", {"[0, 1)", "[1, 2]"}},
                 {"k", "", {"7"}},
                 {"b", "s", {"low", "mid", "high"}},
                 {"c", "1", {"[0, 5)", "[5, 9]"}}};
  run.acceptance = "emrm avoided";
  std::int64_t i = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 2; ++c) {
        PlannedScenario s;
        s.id = fmt::format("S{}", i);
        s.levels = {a, 0, b, c};
        s.record = synthetic_cell("plan", i++, 30.0 + 10.0 * a + c, 0.5 + 0.5 * b, 1.0);
        s.feasible = !(a == 1 && b == 2);
        s.success = (a + b) % 2 == 0 ? 1 : 0;
        run.scenarios.push_back(std::move(s));
      }
  return run;
}

TEST_F(FigurePlanMaps, OneMapPerPairOfFactorsPooledOverTheOthers) {
  const auto figures = draw_plan_maps(synthetic_run(), out(), 2);
  ASSERT_EQ(names_of(figures), (std::vector<std::string>{"plan_map_a_b", "plan_map_a_c", "plan_map_more"}));
  expect_drawn(figures[0], out(), "plan_map_a_b");
  EXPECT_NE(figures[0].title.find("Planned run, a × b: estimated success (emrm avoided)"), std::string::npos)
      << figures[0].title;
  EXPECT_NE(figures.back().note.find("these not: b × c"), std::string::npos) << figures.back().note;

  // a × b: six pairs of levels, two scenarios each (c pooled).
  const auto csv = csv_of(figures[0].csv);
  ASSERT_EQ(csv.size(), 1u + 6u);
  for (std::size_t r = 1; r < csv.size(); ++r) {
    const int a = std::stoi(csv[r][1]), b = std::stoi(csv[r][4]);
    EXPECT_EQ(csv[r][6], "2");
    const bool feasible = !(a == 1 && b == 2);
    EXPECT_EQ(csv[r][7], feasible ? "2" : "0");
    EXPECT_EQ(csv[r][8], feasible && (a + b) % 2 == 0 ? "2" : "0");
    EXPECT_EQ(csv[r][9].empty(), !feasible);  // no rate without a feasible scenario
  }
}

// --- the harm-reduction map -------------------------------------------------------------------

using FigureHarmMap = FigureTest;

TEST_F(FigureHarmMap, EveryCellWithItsReductionsOnTheMapsPanels) {
  const auto f = draw_harm_reduction_map(campaign_records(), out());
  expect_drawn(f, out(), "harm_reduction_map");
  EXPECT_TRUE(f.note.empty()) << f.note;
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "unmitigated_p_mais3",
                       "p_mais3_reduction", "unmitigated_p_fatal", "p_fatal_reduction"}));
  // The same cells in the same order as the mitigability map: one layout for both.
  const auto map = csv_of(draw_mitigability_map(campaign_records(), out() / "map").csv);
  ASSERT_EQ(csv.size(), map.size());
  std::size_t line = 1;
  for (const char* grid : {"coarse", "fine", "speed_mu", "ttc_mu"})
    for (const auto& cell : results::records_of_grid(campaign_records(), grid)) {
      const auto& row = csv[line];
      ASSERT_EQ(core::Row(row.begin(), row.begin() + 7), core::Row(map[line].begin(), map[line].begin() + 7));
      ++line;
      if (!cell.feasible) {
        EXPECT_EQ(core::Row(row.begin() + 7, row.end()), core::Row(4, "")) << grid << " cell " << cell.index;
        continue;
      }
      EXPECT_NEAR(num(row[7]), cell.unmitigated_p_mais3, 1e-9);
      EXPECT_NEAR(num(row[8]), cell.p_mais3_reduction, 1e-9);
      EXPECT_NEAR(num(row[9]), cell.unmitigated_p_fatal, 1e-9);
      EXPECT_NEAR(num(row[10]), cell.p_fatal_reduction, 1e-9);
      // Avoided cells count their whole unmitigated risk.
      if (cell.region == "G" || cell.region == "Y") {
        EXPECT_EQ(row[8], row[7]) << grid << " cell " << cell.index;
      }
    }
  EXPECT_NE(f.title.find("(b) Speed × TTC, fine grid"), std::string::npos) << f.title;
}

TEST_F(FigureHarmMap, FeasibleCellsOnTheColourScaleInfeasibleOnesGrey) {
  const auto f = draw_harm_reduction_map(campaign_records(), out());
  const auto csv = csv_of(f.csv);
  double largest = 0.0;
  for (std::size_t i = 1; i < csv.size(); ++i)
    if (!csv[i][8].empty()) largest = std::max(largest, num(csv[i][8]));
  // The scale runs from 0 to the largest reduction, and the caption says so.
  EXPECT_NE(f.title.find(fmt::format("(0 to {:.3f})", largest)), std::string::npos) << f.title;
  const std::string svg = core::read_file(f.svg);
  EXPECT_NE(svg.find("reduction of P(MAIS3+) by the best strategy"), std::string::npos);
  EXPECT_NE(svg.find("<title>infeasible</title>"), std::string::npos);
  // Per panel, the feasible cells are one series and the infeasible ones another: panel (b) of
  // the synthetic campaign has both.
  EXPECT_NE(svg.find("gnuplot_plot_1b"), std::string::npos);
  EXPECT_NE(svg.find("gnuplot_plot_2b"), std::string::npos);
  EXPECT_EQ(svg.find("<title>G fully avoidable</title>"), std::string::npos);  // not the region map's key
}

TEST_F(FigureHarmMap, MitigationInsideALossLevelShows) {
  // Two R cells at L4: one whose best strategy lowers P(MAIS3+) from 0.09 to 0.02, one that
  // changes nothing. The region map shows both red alike; this map tells them apart.
  std::vector<CellRecord> records{synthetic_cell("fine", 0, 60.0, 0.25, 1.0),
                                  synthetic_cell("fine", 1, 61.0, 0.25, 1.0)};
  for (auto& c : records) {
    ASSERT_EQ(c.region, "R");
    c.unmitigated_loss_level = 4;
    c.unmitigated_p_mais3 = 0.09;
  }
  records[0].p_mais3_reduction = 0.07;
  records[1].p_mais3_reduction = 0.0;
  const auto f = draw_harm_reduction_map(records, out());
  expect_drawn(f, out(), "harm_reduction_map");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[1][8], "0.07");
  EXPECT_EQ(csv[2][8], "0");
  EXPECT_NE(f.title.find("1 of 2 O/R reduced"), std::string::npos) << f.title;
  EXPECT_NE(f.note.find("(a)"), std::string::npos) << f.note;  // only panel (b) has its grid
}

TEST_F(FigureEmpty, HarmReductionMapWithoutAnyOfItsGridsWritesNothing) {
  const auto f = draw_harm_reduction_map({}, out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("coarse"), std::string::npos) << f.note;
}

// --- loss comparison --------------------------------------------------------------------------

using FigureLoss = FigureTest;

TEST_F(FigureLoss, RatesAreThoseOfTheFeasibleCellsOfTheGrid) {
  const auto f = draw_loss_comparison(campaign_records(), "fine", out());
  expect_drawn(f, out(), "loss_comparison");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"strategy", "cells", "collision_avoidance_rate_pct", "mean_impact_speed_kph"}));
  ASSERT_EQ(csv.size(), 1 + kStrategies.size());
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  for (std::size_t i = 0; i < kStrategies.size(); ++i) {
    const auto& row = csv[i + 1];
    EXPECT_EQ(row[0], kStrategies[i]);  // the fixed order, whatever the records' order
    const Rates r = rates_of(fine, kStrategies[i]);
    EXPECT_EQ(row[1], std::to_string(r.cells));
    EXPECT_NEAR(num(row[2]), r.car_pct, 1e-4) << kStrategies[i];
    EXPECT_NEAR(num(row[3]), r.impact_kph, 1e-4) << kStrategies[i];
  }
  // Sanity of the synthetic data: the rates differ, so a mix-up of strategies would show.
  EXPECT_LT(num(csv[1][2]), num(csv[2][2]));
}

TEST_F(FigureEmpty, LossComparisonOfAMissingGridWritesNothing) {
  const auto f = draw_loss_comparison(campaign_records(), "no_such_grid", out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

TEST_F(FigureEmpty, LossComparisonOfAGridWithoutFeasibleCellsWritesNothing) {
  std::vector<CellRecord> records{synthetic_cell("far", 0, 72.0, 2.95, 1.0)};
  ASSERT_FALSE(records.front().feasible);
  const auto f = draw_loss_comparison(records, "far", out());
  expect_nothing_written(f, out());
}

// --- sweep curves -----------------------------------------------------------------------------

using FigureSweep = FigureTest;

TEST_F(FigureSweep, OneRowPerSpeedAndStrategyWithTheRatesAtThatSpeed) {
  const auto f = draw_sweep_curves(campaign_records(), "fine", out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"speed_kph", "strategy", "cells", "collision_avoidance_rate_pct", "mitigability_success_pct"}));
  ASSERT_EQ(csv.size(), 1 + 43 * kStrategies.size());  // every speed has a feasible cell
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  std::size_t line = 1;
  for (int s = 0; s < 43; ++s) {
    const double speed = 30.0 + s;
    for (const auto& strategy : kStrategies) {
      const auto& row = csv[line++];
      EXPECT_NEAR(num(row[0]), speed, 1e-9);
      EXPECT_EQ(row[1], strategy);
      const Rates r = rates_of(fine, strategy, speed);
      EXPECT_EQ(row[2], std::to_string(r.cells));
      EXPECT_NEAR(num(row[3]), r.car_pct, 1e-4) << strategy << " at " << speed;
      EXPECT_NEAR(num(row[4]), r.mitigated_pct, 1e-4) << strategy << " at " << speed;
    }
  }
}

TEST_F(FigureSweep, LeavesOutSpeedsWithoutAFeasibleCell) {
  // Only 30 km/h is feasible here; 70 km/h cells are all beyond the initial distance.
  std::vector<CellRecord> records;
  for (int t = 0; t < 4; ++t) {
    records.push_back(synthetic_cell("g", 2 * t, 30.0, 0.5 + 0.5 * t, 1.0));
    records.push_back(synthetic_cell("g", 2 * t + 1, 70.0, 2.5 + 0.1 * t, 1.0));
  }
  const auto f = draw_sweep_curves(records, "g", out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + kStrategies.size());
  for (std::size_t i = 1; i < csv.size(); ++i) EXPECT_EQ(csv[i][0], "30");
}

TEST_F(FigureEmpty, SweepOfAMissingGridWritesNothing) {
  const auto f = draw_sweep_curves(campaign_records(), "no_such_grid", out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

TEST_F(FigureSweep, ABinnedSweepHasOnePointPerBinAndStrategy) {
  // The fine grid's 43 speeds in three bins: below 40, 40 to 55, above.
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  std::vector<int> levels;
  for (const auto& c : fine) levels.push_back(c.speed_kph < 40.0 ? 0 : c.speed_kph < 55.0 ? 1 : 2);
  const PlanFactor speed{"speed_kph", "km/h", {"[30, 40)", "[40, 55)", "[55, 72]"}};
  const auto f = draw_binned_sweep_curves(fine, levels, speed, out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + 3 * kStrategies.size());
  for (std::size_t line = 1; line < csv.size(); ++line) {
    const int level = std::stoi(csv[line][0]);
    EXPECT_EQ(csv[line][1], speed.levels[static_cast<std::size_t>(level)]);
    std::vector<CellRecord> in_bin;
    for (std::size_t i = 0; i < fine.size(); ++i)
      if (levels[i] == level) in_bin.push_back(fine[i]);
    const Rates r = rates_of(in_bin, csv[line][2]);
    EXPECT_EQ(csv[line][3], std::to_string(r.cells));
    EXPECT_NEAR(num(csv[line][4]), r.car_pct, 1e-4);
  }
}

// --- coverage comparison ----------------------------------------------------------------------

scenario::CoverageCount count(std::size_t covered, std::size_t total) {
  scenario::CoverageCount c;
  c.covered = covered;
  c.total = total;
  return c;
}

scenario::CoverageReport coverage_report(std::string name, std::size_t scenarios, std::size_t hazards, std::size_t ucas,
                                         std::size_t cells) {
  scenario::CoverageReport r;
  r.name = std::move(name);
  r.scenarios = scenarios;
  r.hazards = count(hazards, 8);
  r.malfunctions = count(ucas, 4);
  r.transitions = count(3, 6);
  r.cells = count(cells, 200);
  r.twise = count(10, 40);
  r.boundaries = count(0, 0);
  return r;
}

std::vector<scenario::CoverageReport> coverage_reports() {
  // The coverage.json `emrm plan` writes (scenario::coverage_json), read back as a report does.
  const std::vector<scenario::CoverageReport> reports{
      coverage_report("emrm plan", 212, 8, 4, 200), coverage_report("HARA only", 8, 6, 1, 1),
      coverage_report("STPA only", 4, 8, 4, 4), coverage_report("manual grid", 30, 5, 2, 30)};
  return scenario::parse_coverage_json(scenario::coverage_json(reports).dump(2), "coverage.json");
}

using FigureCoverage = FigureTest;

TEST_F(FigureCoverage, OneRowPerMethodWithItsPercentages) {
  const auto f = draw_coverage_comparison(coverage_reports(), out());
  expect_drawn(f, out(), "coverage_comparison");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"method", "scenarios", "hazard_pct", "uca_pct", "transition_pct", "cell_pct", "twise_pct"}));
  ASSERT_EQ(csv.size(), 5u);
  const std::vector<core::Row> expected{
      {"emrm plan", "212"}, {"HARA only", "8"}, {"STPA only", "4"}, {"manual grid", "30"}};
  const double hazard[] = {100.0, 75.0, 100.0, 62.5};
  const double uca[] = {100.0, 25.0, 100.0, 50.0};
  const double cell[] = {100.0, 0.5, 2.0, 15.0};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& row = csv[i + 1];
    EXPECT_EQ(row[0], expected[i][0]);
    EXPECT_EQ(row[1], expected[i][1]);
    EXPECT_NEAR(num(row[2]), hazard[i], 1e-9);
    EXPECT_NEAR(num(row[3]), uca[i], 1e-9);
    EXPECT_NEAR(num(row[4]), 50.0, 1e-9);
    EXPECT_NEAR(num(row[5]), cell[i], 1e-9);
    EXPECT_NEAR(num(row[6]), 25.0, 1e-9);
  }
}

TEST_F(FigureEmpty, CoverageWithoutReportsWritesNothing) {
  expect_nothing_written(draw_coverage_comparison({}, out()), out());
}

// --- traceability matrix ----------------------------------------------------------------------

safety::TraceRow trace(std::string uca, std::string hazard, std::string loss, std::vector<std::string> scenarios) {
  safety::TraceRow r;
  r.uca = std::move(uca);
  r.hazard = std::move(hazard);
  r.loss = std::move(loss);
  r.scenarios = std::move(scenarios);
  return r;
}

using FigureTraceability = FigureTest;

TEST_F(FigureTraceability, OneRowPerUcaAndHazardWithItsScenarioCount) {
  // As traceability_matrix gives them: a row per (UCA, hazard, loss), the UCA's scenarios on each.
  const std::vector<safety::TraceRow> rows{
      trace("UCA1", "H8", "L1", {"S001", "S002", "S003"}),
      trace("UCA1", "H8", "L2", {"S001", "S002", "S003"}),
      trace("UCA1", "H1", "L3", {"S001", "S002", "S003"}),
      trace("UCA2", "H2", "L3", {}),
      trace("UCA2", "H1", "L3", {}),
      trace("UCA3", "H9", "L7", {"S010"}),
  };
  const auto f = draw_traceability(rows, out());
  expect_drawn(f, out(), "traceability_matrix");
  const auto csv = csv_of(f.csv);
  const std::vector<core::Row> expected{
      {"uca", "hazard", "losses", "scenarios"},
      {"UCA1", "H8", "L1 L2", "3"},
      {"UCA1", "H1", "L3", "3"},
      {"UCA2", "H2", "L3", "0"},
      {"UCA2", "H1", "L3", "0"},
      {"UCA3", "H9", "L7", "1"},
  };
  EXPECT_EQ(csv, expected);
}

TEST_F(FigureEmpty, TraceabilityWithoutRowsWritesNothing) {
  expect_nothing_written(draw_traceability({}, out()), out());
}

// --- a whole campaign -------------------------------------------------------------------------

using FigureCampaign = FigureTest;

// The six figures of `emrm report` for a campaign the size of the shipped one (1978 + 430 + 260 + 30
// cells). The time is recorded for the record (docs/report.md), not asserted: speed claims belong
// to benchmarks.
TEST_F(FigureCampaign, DrawsAllSixFiguresOfAShippedSizeCampaign) {
  const auto& records = campaign_records();
  std::vector<safety::TraceRow> rows;
  for (int u = 1; u <= 4; ++u)
    for (int h = 1; h <= 9; h += u) {
      std::vector<std::string> scenarios;
      for (int s = 0; s < (u * h) % 7; ++s) scenarios.push_back("S" + std::to_string(100 * u + s));
      rows.push_back(trace("UCA" + std::to_string(u), "H" + std::to_string(h), "L7", scenarios));
    }
  const auto coverage = coverage_reports();

  const auto start = std::chrono::steady_clock::now();
  const std::vector<Figure> figures{
      draw_mitigability_map(records, out()),        draw_harm_reduction_map(records, out()),
      draw_loss_comparison(records, "fine", out()), draw_sweep_curves(records, "fine", out()),
      draw_coverage_comparison(coverage, out()),    draw_traceability(rows, out())};
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("render_seconds", std::to_string(seconds));
  std::cout << "[ figures  ] six figures of " << records.size() << " cells rendered in " << seconds << " s\n";

  const std::vector<std::string> names{"mitigability_map", "harm_reduction_map",  "loss_comparison",
                                       "sweep_curves",     "coverage_comparison", "traceability_matrix"};
  for (std::size_t i = 0; i < figures.size(); ++i) {
    expect_drawn(figures[i], out(), names[i]);
    EXPECT_TRUE(figures[i].note.empty()) << figures[i].note;
  }
  // To look at them: EMRM_FIGURES_TEST_KEEP=DIR keeps a copy of the figures in DIR.
  if (const char* keep = std::getenv("EMRM_FIGURES_TEST_KEEP"))
    fs::copy(out(), keep, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

}  // namespace figures_test
}  // namespace emrm::report

namespace emrm::report {
namespace figures_test {

// --- the brakes' sensitivity ---------------------------------------------------------------------

using FigureBrakes = FigureTest;

TEST_F(FigureBrakes, GFallsAlongBothCurvesAndTheCsvHoldsThem) {
  const auto f = draw_brake_sensitivity(campaign_records(), "fine", sim::ActuationConfig{}, out());
  expect_drawn(f, out(), "brake_sensitivity");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"parameter", "value", "g_pct"}));
  ASSERT_EQ(csv.size(), 1u + 7u + 7u);
  for (std::size_t k = 2; k <= 7; ++k) EXPECT_LT(std::stod(csv[k][2]), std::stod(csv[k - 1][2]));    // dead time up
  for (std::size_t k = 10; k <= 14; ++k) EXPECT_LT(std::stod(csv[k][2]), std::stod(csv[k - 1][2]));  // cap down
}

TEST_F(FigureBrakes, AGridWithoutCellsIsANoteNotAFigure) {
  const auto f = draw_brake_sensitivity(campaign_records(), "no_such_grid", sim::ActuationConfig{}, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

}  // namespace figures_test
}  // namespace emrm::report
