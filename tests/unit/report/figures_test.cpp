#include "figures_support.hpp"

namespace emrm::report {
namespace figures_test {

// --- the mitigability map ---------------------------------------------------------------------

using FigureMap = FigureTest;

TEST_F(FigureMap, DrawsAllFourPanelsWithEveryCellInItsRecordedRegion) {
  const auto f = draw_mitigability_map_t(campaign_records(), out());
  expect_drawn(f, out(), "mitigability_map");
  EXPECT_TRUE(f.note.empty()) << f.note;

  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph",
                                    "region", "evidence"}));
  ASSERT_EQ(csv.size(), 1 + 30 + 1978 + 430 + 260);
  std::size_t line = 1;
  for (const auto& [panel, grid] : {std::pair{"a", "coarse"}, {"b", "fine"}, {"c", "speed_mu"}, {"d", "ttc_mu"}}) {
    for (const auto& cell : results::records_of_grid(campaign_records(), grid)) {
      const auto& row = csv[line++];
      ASSERT_EQ(row[0], panel);
      ASSERT_EQ(row[1], grid);
      for (std::size_t k = 0; k < cell.factors.size(); ++k) EXPECT_NEAR(num(row[2 + k]), cell.factors[k], 1e-6);
      EXPECT_EQ(row[7], core::enum_name(cell.region)) << grid << " cell " << cell.index;
      EXPECT_EQ(row[8], cell.feasible ? core::enum_name(cell.evidence) : "") << grid << " cell " << cell.index;
    }
  }
  // The drawing colours each cell by its region: one rectangle per cell in the region's colour (as
  // gnuplot's SVG writes the figure's palette, docs/report.md) and one more, the key's.
  const std::string svg = core::read_file(f.svg);
  for (const auto& [name, rgb] :
       {std::pair{"G", " 44, 160,  44"}, {"Y", "255, 221,  87"}, {"O", "255, 127,  14"}, {"R", "214,  39,  40"}}) {
    const std::string region = name;  // a structured binding is not captured by a lambda in clang 14
    const std::string fill = fmt::format("<polygon fill = 'rgb({})'", rgb);
    std::size_t drawn = 0;
    for (auto at = svg.find(fill); at != std::string::npos; at = svg.find(fill, at + 1)) ++drawn;
    const auto cells = std::count_if(csv.begin() + 1, csv.end(), [&](const core::Row& r) { return r[7] == region; });
    EXPECT_GT(cells, 0) << region;
    EXPECT_EQ(drawn, static_cast<std::size_t>(cells) + 1) << region;
  }
  // The caption states the region shares of each panel, as count_regions gives them.
  EXPECT_NE(f.title.find("(b) Speed × TTC, fine grid"), std::string::npos) << f.title;
}

TEST_F(FigureMap, LeavesOutAMissingPanelAndSaysWhich) {
  const auto f = draw_mitigability_map_t(without_grid("ttc_mu"), out());
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
  const auto f = draw_mitigability_map_t(campaign_records(), out(), panels, 0.2);
  expect_drawn(f, out(), "mitigability_map");
  EXPECT_EQ(csv_of(f.csv).size(), 1 + 1978 + 260);
  EXPECT_NE(f.title.find("0.2 s"), std::string::npos) << f.title;
  EXPECT_NE(f.note.find("missing_a"), std::string::npos);
  EXPECT_NE(f.note.find("missing_b"), std::string::npos);
}

TEST_F(FigureMap, SameRecordsGiveTheSameCsvBytes) {
  const auto a = draw_mitigability_map_t(campaign_records(), out() / "a");
  const auto b = draw_mitigability_map_t(campaign_records(), out() / "b");
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

std::size_t count_evidence(const std::vector<CellRecord>& records, campaign::CellEvidence evidence) {
  return static_cast<std::size_t>(std::count_if(records.begin(), records.end(), [&](const CellRecord& c) {
    return c.feasible && (c.region == sim::Region::kO || c.region == sim::Region::kR) && c.evidence == evidence;
  }));
}

TEST_F(FigureMap, MarksEveryUndecidedCellWithACrossAndSaysSoInTheKey) {
  const auto& records = campaign_records();
  const std::size_t undecided = count_evidence(records, campaign::CellEvidence::kUndecided);
  const std::size_t certified = count_evidence(records, campaign::CellEvidence::kCertificate);
  ASSERT_GT(undecided, 10u);  // the synthetic campaign has some of each
  ASSERT_GT(certified, 10u);
  const auto f = draw_mitigability_map_t(records, out());
  expect_drawn(f, out(), "mitigability_map");

  // The CSV has every cell's evidence; the undecided rows are exactly the crosses.
  const auto csv = csv_of(f.csv);
  const std::size_t evidence = column_of(csv, "evidence");
  EXPECT_EQ(static_cast<std::size_t>(
                std::count_if(csv.begin(), csv.end(), [&](const core::Row& r) { return r[evidence] == "undecided"; })),
            undecided);
  EXPECT_EQ(crosses_in(f.svg), undecided + 1);
  const std::string svg = core::read_file(f.svg);
  EXPECT_NE(svg.find("undecided (no proof either way)"), std::string::npos);
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
    if (c.evidence == campaign::CellEvidence::kUndecided) c.evidence = campaign::CellEvidence::kCertificate;
  for (auto& c : unknown) c.evidence = campaign::CellEvidence::kNone;
  const auto a = draw_mitigability_map_t(certified, out() / "certified");
  const auto b = draw_mitigability_map_t(unknown, out() / "unknown");
  EXPECT_EQ(crosses_in(a.svg), 0u);
  EXPECT_EQ(core::read_file(a.svg).find("undecided"), std::string::npos);
  // Nothing on the picture depends on the evidence then; only the CSV and the caption tell it.
  EXPECT_EQ(core::read_file(a.svg), core::read_file(b.svg));
  EXPECT_NE(a.title.find(fmt::format("All O/R cells ({}) are certified unavoidable",
                                     count_evidence(certified, campaign::CellEvidence::kCertificate))),
            std::string::npos)
      << a.title;
  EXPECT_EQ(b.title.find("certified"), std::string::npos) << b.title;
}

TEST_F(FigureEmpty, MapWithoutAnyOfItsGridsWritesNothing) {
  const auto f = draw_mitigability_map_t({}, out());
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
          cells.back().factors[3] = p;  // the passage
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
  const std::size_t undecided = count_evidence(cells, campaign::CellEvidence::kUndecided);
  ASSERT_GT(undecided, 0u);
  const auto figures = draw_grid_maps_t(cells, out());
  ASSERT_EQ(names_of(figures), (std::vector<std::string>{"map_wet", "harm_map_wet"}));
  const Figure& f = figures.front();
  expect_drawn(f, out(), "map_wet");
  EXPECT_NE(f.title.find("grid 'wet': 6 speeds × 5 TTCs, μ = 0.5"), std::string::npos) << f.title;
  // What R does not say, said where R is drawn.
  EXPECT_NE(f.title.find("not that nothing lowers the harm"), std::string::npos) << f.title;
  // Beside it the harm reduction of the same cells, whatever the grid's name.
  const Figure& harm = figures.back();
  expect_drawn(harm, out(), "harm_map_wet");
  EXPECT_NE(harm.title.find("Harm reduction by the best strategy in grid 'wet'"), std::string::npos) << harm.title;
  const auto harm_csv = csv_of(harm.csv);
  ASSERT_EQ(harm_csv.size(), 1 + cells.size());
  const std::size_t reduction = column_of(harm_csv, "p_mais3_reduction");
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (!cells[i].feasible) continue;
    EXPECT_NEAR(std::stod(harm_csv[i + 1][reduction]), cells[i].p_mais3_reduction, 1e-9) << i;
  }
  EXPECT_NE(f.title.find(fmt::format("A cross marks the {} undecided O/R cells", undecided)), std::string::npos);
  EXPECT_EQ(crosses_in(f.svg), undecided + 1);  // and the key's
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + cells.size());
  const std::size_t region = column_of(csv, "region");
  for (std::size_t i = 0; i < cells.size(); ++i) EXPECT_EQ(csv[i + 1][region], core::enum_name(cells[i].region)) << i;
}

TEST_F(FigureGridMaps, OneMapPerSliceNamedByItsValuesAndTheRestNamedInANote) {
  // Speed × TTC × μ × passage: slices along μ and passage, in ascending order of both.
  const auto cells = product_grid("g 4", {30, 40}, {0.5, 1.0}, {0.3, 0.6}, {2.0, 3.0});
  GridMapOptions options;
  options.max_slices_per_grid = 3;
  const auto figures = draw_grid_maps_t(cells, out(), options);
  // Each slice's region map, then its harm-reduction map.
  ASSERT_EQ(names_of(figures), (std::vector<std::string>{
                                   "map_g_4_mu_0.3_passage_m_2", "harm_map_g_4_mu_0.3_passage_m_2",
                                   "map_g_4_mu_0.3_passage_m_3", "harm_map_g_4_mu_0.3_passage_m_3",
                                   "map_g_4_mu_0.6_passage_m_2", "harm_map_g_4_mu_0.6_passage_m_2", "map_g_4_more"}));
  for (std::size_t i = 0; i < 6; ++i) {
    expect_drawn(figures[i], out(), figures[i].name);
    EXPECT_EQ(csv_of(figures[i].csv).size(), 1u + 4u);  // its own four cells
  }
  EXPECT_NE(figures[2].title.find("grid 'g 4', slice μ = 0.3, passage 3 m: 2 speeds × 2 TTCs"), std::string::npos)
      << figures[2].title;
  const Figure& more = figures.back();
  EXPECT_TRUE(more.png.empty() && more.csv.empty());
  EXPECT_NE(more.note.find("4 slices; the first 3 are drawn, these not: μ = 0.6, passage 3 m"), std::string::npos)
      << more.note;
}

TEST_F(FigureGridMaps, AGridVaryingOneFactorIsAStrip) {
  const auto cells = product_grid("speeds", {30, 40, 50, 60, 70}, {1.0}, {1.0});
  const auto figures = draw_grid_maps_t(cells, out());
  ASSERT_EQ(names_of(figures), (std::vector<std::string>{"map_speeds", "harm_map_speeds"}));
  expect_drawn(figures.front(), out(), "map_speeds");
  EXPECT_NE(figures.front().title.find("5 speeds × 1 TTCs"), std::string::npos) << figures.front().title;
}

TEST_F(FigureEmpty, GridMapsLeaveOutTheGridsTheyAreToldTo) {
  GridMapOptions options;
  options.skip = {"coarse", "fine", "speed_mu", "ttc_mu"};
  EXPECT_TRUE(draw_grid_maps_t(campaign_records(), out(), options).empty());
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
  const auto f = draw_harm_reduction_map_t(campaign_records(), out());
  expect_drawn(f, out(), "harm_reduction_map");
  EXPECT_TRUE(f.note.empty()) << f.note;
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph", "region",
                       "unmitigated_p_mais3", "p_mais3_reduction", "unmitigated_p_fatal", "p_fatal_reduction"}));
  // The same cells in the same order as the mitigability map: one layout for both.
  const auto map = csv_of(draw_mitigability_map_t(campaign_records(), out() / "map").csv);
  ASSERT_EQ(csv.size(), map.size());
  std::size_t line = 1;
  for (const char* grid : {"coarse", "fine", "speed_mu", "ttc_mu"})
    for (const auto& cell : results::records_of_grid(campaign_records(), grid)) {
      const auto& row = csv[line];
      ASSERT_EQ(core::Row(row.begin(), row.begin() + 8), core::Row(map[line].begin(), map[line].begin() + 8));
      ++line;
      if (!cell.feasible) {
        EXPECT_EQ(core::Row(row.begin() + 8, row.end()), core::Row(4, "")) << grid << " cell " << cell.index;
        continue;
      }
      EXPECT_NEAR(num(row[8]), cell.unmitigated_p_mais3, 1e-9);
      EXPECT_NEAR(num(row[9]), cell.p_mais3_reduction, 1e-9);
      EXPECT_NEAR(num(row[10]), cell.unmitigated_p_fatal, 1e-9);
      EXPECT_NEAR(num(row[11]), cell.p_fatal_reduction, 1e-9);
      // Avoided cells count their whole unmitigated risk.
      if (cell.region == sim::Region::kG || cell.region == sim::Region::kY) {
        EXPECT_EQ(row[9], row[8]) << grid << " cell " << cell.index;
      }
    }
  EXPECT_NE(f.title.find("(b) Speed × TTC, fine grid"), std::string::npos) << f.title;
}

TEST_F(FigureHarmMap, FeasibleCellsOnTheColourScaleInfeasibleOnesGrey) {
  const auto f = draw_harm_reduction_map_t(campaign_records(), out());
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
    ASSERT_EQ(c.region, sim::Region::kR);
    c.unmitigated_loss_level = 4;
    c.unmitigated_p_mais3 = 0.09;
  }
  records[0].p_mais3_reduction = 0.07;
  records[1].p_mais3_reduction = 0.0;
  const auto f = draw_harm_reduction_map_t(records, out());
  expect_drawn(f, out(), "harm_reduction_map");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 3u);
  const std::size_t reduction = column_of(csv, "p_mais3_reduction");
  EXPECT_EQ(csv[1][reduction], "0.07");
  EXPECT_EQ(csv[2][reduction], "0");
  EXPECT_NE(f.title.find("1 of 2 O/R reduced"), std::string::npos) << f.title;
  EXPECT_NE(f.note.find("(a)"), std::string::npos) << f.note;  // only panel (b) has its grid
}

TEST_F(FigureEmpty, HarmReductionMapWithoutAnyOfItsGridsWritesNothing) {
  const auto f = draw_harm_reduction_map_t({}, out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("coarse"), std::string::npos) << f.note;
}

}  // namespace figures_test
}  // namespace emrm::report
