#include "emrm/results/diagnostics.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::results {
namespace diagnostics_test {

campaign::CellRecord cell(double speed, double ttc, double mu, std::string region, std::vector<bool> avoided = {}) {
  campaign::CellRecord c;
  c.grid = "g";
  c.factors = sim::TJunctionCell{speed, ttc, mu, 3.0, 10.0};
  c.feasible = true;
  c.region = core::enum_from_name<sim::Region>(region).value();
  c.unmitigated_loss_level = 7;
  const std::vector<std::string> names{"emergency_stop", "dodge"};
  for (std::size_t i = 0; i < avoided.size(); ++i) {
    campaign::OutcomeRecord o;
    o.strategy = names[i];
    o.avoided = avoided[i];
    c.outcomes.push_back(o);
  }
  return c;
}

TEST(StopBoundaryCheck, FlagsAnAnalyticallyStoppableRedCell) {
  // 72 km/h at mu 1 needs 1.019 s: TTC 2.0 is stoppable, 0.5 is not.
  std::vector<campaign::CellRecord> cells{cell(72, 2.0, 1.0, "R"), cell(72, 2.0, 1.0, "G"), cell(72, 0.5, 1.0, "G"),
                                          cell(72, 0.5, 1.0, "R"), cell(72, 2.0, 1.0, "Y")};
  cells.push_back(cell(72, 2.0, 1.0, "G"));
  cells.back().feasible = false;
  const auto c = check_stop_boundary(cells);
  EXPECT_EQ(c.feasible, 5u);
  EXPECT_EQ(c.stoppable, 3u);
  ASSERT_EQ(c.stoppable_red.size(), 1u);
  EXPECT_DOUBLE_EQ(c.stoppable_red[0].factors.time_to_collision_s(), 2.0);
  EXPECT_EQ(c.stoppable_not_green.size(), 2u);  // R and Y
  ASSERT_EQ(c.green_not_stoppable.size(), 1u);
  EXPECT_DOUBLE_EQ(c.green_not_stoppable[0].factors.time_to_collision_s(), 0.5);
  // With 1.5 s of latency, 2.0 s is no longer enough.
  EXPECT_EQ(check_stop_boundary(cells, 1.5).stoppable, 0u);
}

TEST(MonotonicityCheck, CountsReversalsAlongTtcAndMu) {
  // Along TTC at 50 km/h, mu 1 (dodge): avoided at 0.5, not at 1.0, avoided at 1.5, not at 2.0 → 2
  // reversals; the stop is monotone (no, no, yes, yes). Along mu at TTC 1.0: avoided at 0.5, not at 1.0 → 1.
  std::vector<campaign::CellRecord> cells{cell(50, 1.0, 1.0, "Y", {false, false}),
                                          cell(50, 0.5, 1.0, "Y", {false, true}),
                                          cell(50, 2.0, 1.0, "G", {true, false}), cell(50, 1.5, 1.0, "G", {true, true}),
                                          cell(50, 1.0, 0.5, "Y", {false, true})};
  // Another speed: a separate group with no reversal.
  cells.push_back(cell(60, 0.5, 1.0, "R", {false, false}));
  cells.push_back(cell(60, 1.0, 1.0, "Y", {false, true}));
  const auto m = check_monotonicity(cells);
  EXPECT_EQ(m.total_reversals, 3u);
  std::size_t ttc_dodge = 0, mu_dodge = 0, ttc_stop = 0;
  for (const auto& c : m.counts) {
    if (c.strategy == "dodge" && c.factor == "ttc") ttc_dodge = c.reversals;
    if (c.strategy == "dodge" && c.factor == "mu") mu_dodge = c.reversals;
    if (c.strategy == "emergency_stop" && c.factor == "ttc") ttc_stop = c.reversals;
  }
  EXPECT_EQ(ttc_dodge, 2u);
  EXPECT_EQ(mu_dodge, 1u);
  EXPECT_EQ(ttc_stop, 0u);
  ASSERT_EQ(m.examples.size(), 3u);
  EXPECT_DOUBLE_EQ(m.examples[0].lower.factors.time_to_collision_s(), 0.5);
  EXPECT_DOUBLE_EQ(m.examples[0].higher.factors.time_to_collision_s(), 1.0);
}

TEST(FsmCoverage, EventsAreTheOddPositionsOfATrace) {
  EXPECT_EQ(trace_events({"S1", "a", "S2", "b", "S3"}), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(trace_events({"S1"}).empty());
}

TEST(FsmCoverage, CountsTransitionsFromStoredTraces) {
  const auto g = fsm::parse_generator(R"(
name: toy
states: [A, B, C]
events: [go, back, stop]
initial: A
marked: [A, C]
transitions:
  - {from: A, event: go, to: B}
  - {from: B, event: back, to: A}
  - {from: B, event: stop, to: C}
)",
                                      "toy.yaml");
  std::vector<campaign::CellRecord> cells{cell(50, 1.0, 1.0, "G", {true, true}), cell(50, 2.0, 1.0, "G", {true, true})};
  cells[0].outcomes[0].fsm_trace = {"A", "go", "B", "back", "A", "go", "B", "stop", "C"};
  cells[0].outcomes[1].fsm_trace = {"A", "go", "B", "stop", "C"};
  cells[1].outcomes[0].fsm_trace = {"A", "go", "B", "stop", "C"};
  cells[1].outcomes[1].fsm_trace = {"A", "stop", "A"};  // not in L(G): rejected, counts nothing
  const auto c = emrm_fsm_coverage(cells, g);
  EXPECT_EQ(c.coverage.traces, 4u);
  EXPECT_EQ(c.coverage.accepted, 3u);
  EXPECT_EQ(c.coverage.counts, (std::vector<std::size_t>{4, 1, 3}));
  EXPECT_EQ(c.coverage.covered, 3u);
  EXPECT_DOUBLE_EQ(c.coverage.fraction(), 1.0);

  // The loss-evaluation machine reads only the emrm outcomes' loss-evaluation traces.
  cells[0].outcomes[1].strategy = "emrm";
  cells[0].outcomes[1].loss_evaluation_trace = {"A", "go", "B"};
  const auto l = loss_evaluation_fsm_coverage(cells, g);
  EXPECT_EQ(l.coverage.traces, 1u);
  EXPECT_EQ(l.coverage.counts, (std::vector<std::size_t>{1, 0, 0}));
  EXPECT_NEAR(l.coverage.fraction(), 1.0 / 3.0, 1e-12);
}

TEST(ReferenceCheck, SampleIsSeededAndBounded) {
  // Cells without dodge / drift_to_avoid outcomes are not candidates, so nothing is simulated.
  std::vector<campaign::CellRecord> cells{cell(50, 1.0, 1.0, "G", {true, true})};
  const auto r = check_against_reference(cells, sim::SceneConfig{}, 40, 1);
  EXPECT_EQ(r.sampled, 0u);
}

TEST(ReferenceCheck, ValidatesTheSceneItIsGiven) {
  sim::SceneConfig scene;
  scene.simulation.dt_s = 0;
  try {
    (void)check_against_reference({}, scene, 40, 1);
    FAIL() << "expected a ConfigError";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(std::string(e.message()), "scene: simulation.dt_s: expected a value in [0.0001, 0.1], got 0");
  }
}

TEST(ReferenceCheck, ComparesTheStoredOutcomeWithTheReferencePlanner) {
  // A wide-open cell the reference planner certainly dodges (30 km/h, TTC 2 s: it can even stop),
  // stored as "not avoided" by both evasive strategies: the check must count two misses.
  campaign::CellRecord c = cell(30, 2.0, 1.0, "G");
  for (const char* name : {"dodge", "drift_to_avoid"}) {
    campaign::OutcomeRecord o;
    o.strategy = name;
    o.avoided = false;
    c.outcomes.push_back(o);
  }
  const auto r = check_against_reference({c}, sim::SceneConfig{}, 5, 7, 1);
  EXPECT_EQ(r.sampled, 1u);
  ASSERT_NE(r.of("dodge"), nullptr);
  ASSERT_NE(r.of("drift_to_avoid"), nullptr);
  EXPECT_EQ(r.of("drift_to_accident"), nullptr);  // accepts contact: nothing of its own to compare
  EXPECT_EQ(r.of("dodge")->reference_avoids, 1u);
  EXPECT_EQ(r.of("dodge")->missed, 1u);
  EXPECT_EQ(r.of("drift_to_avoid")->missed, r.of("drift_to_avoid")->reference_avoids);
  EXPECT_EQ(r.disagreements.size(), r.of("dodge")->missed + r.of("drift_to_avoid")->missed);
}

TEST(Diagnostics, WritesJsonAndColouredDiagrams) {
  std::vector<campaign::CellRecord> cells{cell(30, 2.0, 1.0, "G", {true, true})};
  Diagnostics d;
  d.stop_boundary = check_stop_boundary(cells);
  d.monotonicity = check_monotonicity(cells);
  d.emrm_fsm = emrm_fsm_coverage(cells, sim::default_emrm_fsm());
  d.loss_evaluation_fsm = loss_evaluation_fsm_coverage(cells, sim::default_loss_evaluation_fsm());
  const auto j = to_json(d);
  EXPECT_TRUE(j["stop_boundary"]["ok"].get<bool>());
  EXPECT_EQ(j["fsm_coverage"]["emrm_fsm"]["total"].get<std::size_t>(), sim::default_emrm_fsm().transitions().size());
  const auto dir = std::filesystem::temp_directory_path() / "emrm-diagnostics-test";
  std::filesystem::remove_all(dir);
  const auto files = write_diagnostics(dir, d);
  EXPECT_TRUE(std::filesystem::exists(dir / "diagnostics.json"));
  EXPECT_TRUE(std::filesystem::exists(dir / "fsm" / "emrm_fsm.dot"));
  EXPECT_TRUE(std::filesystem::exists(dir / "fsm" / "loss_evaluation_fsm.dot"));
  std::filesystem::remove_all(dir);
}

TEST(Diagnostics, TheSummaryReadBackIsWhatWasWritten) {
  // Cells that give every count something to say: a reversal along TTC, a stoppable R cell, a
  // reference sample with a miss.
  std::vector<campaign::CellRecord> cells{cell(30, 2.0, 1.0, "R", {true, false}),
                                          cell(30, 2.5, 1.0, "G", {false, false}),
                                          cell(70, 0.5, 0.3, "O", {false, false})};
  for (auto& c : cells) {
    campaign::OutcomeRecord o;
    o.strategy = "drift_to_avoid";
    c.outcomes.push_back(o);
  }
  Diagnostics d;
  d.stop_boundary = check_stop_boundary(cells);
  d.monotonicity = check_monotonicity(cells);
  d.reference = check_against_reference(cells, sim::SceneConfig{}, 2, 3, 1);
  d.emrm_fsm = emrm_fsm_coverage(cells, sim::default_emrm_fsm());
  d.loss_evaluation_fsm = loss_evaluation_fsm_coverage(cells, sim::default_loss_evaluation_fsm());
  const auto dir = std::filesystem::temp_directory_path() / "emrm-diagnostics-summary-test";
  std::filesystem::remove_all(dir);
  (void)write_diagnostics(dir, d);
  const DiagnosticsSummary s = read_diagnostics_summary(dir / "diagnostics.json");
  EXPECT_EQ(s.feasible, d.stop_boundary.feasible);
  EXPECT_EQ(s.stoppable, d.stop_boundary.stoppable);
  EXPECT_EQ(s.stoppable_red, d.stop_boundary.stoppable_red.size());
  EXPECT_GE(s.stoppable_red, 1U);
  EXPECT_EQ(s.green_not_stoppable, d.stop_boundary.green_not_stoppable.size());
  EXPECT_EQ(s.total_reversals, d.monotonicity.total_reversals);
  EXPECT_GE(s.total_reversals, 1U);
  ASSERT_EQ(s.reversal_counts.size(), d.monotonicity.counts.size());
  for (std::size_t i = 0; i < s.reversal_counts.size(); ++i) {
    EXPECT_EQ(s.reversal_counts[i].strategy, d.monotonicity.counts[i].strategy);
    EXPECT_EQ(s.reversal_counts[i].factor, d.monotonicity.counts[i].factor);
    EXPECT_EQ(s.reversal_counts[i].pairs, d.monotonicity.counts[i].pairs);
    EXPECT_EQ(s.reversal_counts[i].reversals, d.monotonicity.counts[i].reversals);
  }
  EXPECT_EQ(s.sampled, d.reference.sampled);
  EXPECT_EQ(s.seed, 3U);
  ASSERT_EQ(s.reference.size(), d.reference.strategies.size());
  for (std::size_t i = 0; i < s.reference.size(); ++i) {
    EXPECT_EQ(s.reference[i].strategy, d.reference.strategies[i].strategy);
    EXPECT_EQ(s.reference[i].missed, d.reference.strategies[i].missed);
    EXPECT_EQ(s.reference[i].reference_avoids, d.reference.strategies[i].reference_avoids);
  }
  ASSERT_EQ(s.fsm_coverage.size(), 2U);
  EXPECT_EQ(s.fsm_coverage[0].name, "emrm_fsm");
  EXPECT_EQ(s.fsm_coverage[0].total, sim::default_emrm_fsm().transitions().size());
  EXPECT_EQ(s.fsm_coverage[1].covered, d.loss_evaluation_fsm.coverage.covered);
  // A count of the wrong type is refused at its line.
  std::string text;
  {
    std::ifstream in(dir / "diagnostics.json");
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto at = text.find("\"total_reversals\": ");
  const auto number = text.find(' ', at) + 1;
  text.replace(number, text.find(',', number) - number, "\"many\"");
  std::ofstream(dir / "diagnostics.json") << text;
  try {
    (void)read_diagnostics_summary(dir / "diagnostics.json");
    ADD_FAILURE() << "read a text count";
  } catch (const InputError& e) {
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
    EXPECT_NE(std::string(e.what()).find(fmt::format("diagnostics.json:{}:", line)), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace diagnostics_test
}  // namespace emrm::results
