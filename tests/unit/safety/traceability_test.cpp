#include "emrm/safety/traceability.hpp"

#include <gtest/gtest.h>

#include <set>

#include "emrm/safety/load.hpp"
#include "example_case.hpp"

namespace emrm::safety {
namespace traceability_test {

SafetyCase example() { return parse_safety_case(testing::example_text(), "safety.yaml"); }

TEST(Mapping, EveryShippedUcaReachesAHazardAndALoss) {
  const auto sc = example();
  const auto mapping = map_hara_stpa(sc);
  ASSERT_EQ(mapping.size(), sc.ucas.size());
  for (const auto& m : mapping) {
    EXPECT_FALSE(m.hazards.empty()) << m.uca;
    EXPECT_FALSE(m.losses.empty()) << m.uca;
  }
}

TEST(Mapping, LossesAreTheUnionOverHazardsInSeverityOrder) {
  const auto sc = example();
  const auto mapping = map_hara_stpa(sc);
  // UCA2 -> H2 (L1, L3, L4) and H6 (L1, L3): union L1, L3, L4, all reversible.
  const auto& uca2 = mapping[1];
  EXPECT_EQ(uca2.losses, (std::vector<std::string>{"L1", "L3", "L4"}));
  EXPECT_EQ(uca2.risk.worst_loss, "L4");
  EXPECT_FALSE(uca2.risk.irreversible);
  EXPECT_EQ(uca2.risk.asil, Asil::kQM);
  // UCA1 -> H8, H1, H9: reaches L7, and the highest ASIL among them is B.
  EXPECT_EQ(mapping[0].risk.worst_loss, "L7");
  EXPECT_TRUE(mapping[0].risk.irreversible);
  EXPECT_EQ(mapping[0].risk.asil, Asil::kB);
}

TEST(Traceability, HasOneRowPerUcaHazardLossTriple) {
  const auto sc = example();
  std::size_t expected = 0;
  for (const auto& u : sc.ucas)
    for (const auto& h : u.hazards) expected += sc.find_hazard(h.id)->losses.size();
  const auto rows = traceability_matrix(sc);
  EXPECT_EQ(rows.size(), expected);
  std::set<std::tuple<std::string, std::string, std::string>> triples;
  for (const auto& r : rows) triples.insert({r.uca, r.hazard, r.loss});
  EXPECT_EQ(triples.size(), rows.size()) << "no triple twice";
}

TEST(Traceability, RowsCarryTheTransitionsAndRegionOfTheirUca) {
  const auto sc = example();
  for (const auto& r : traceability_matrix(sc)) {
    const Uca* u = sc.find_uca(r.uca);
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(r.transitions.size(), u->fsm_transitions.size());
    EXPECT_EQ(r.region, *u->region);
    EXPECT_TRUE(r.scenarios.empty());
    EXPECT_EQ(r.loss_reversible, sc.find_loss(r.loss)->reversible);
  }
}

TEST(Traceability, CsvHasAHeaderAndOneLinePerRowWithQuotedCommas) {
  const auto rows = traceability_matrix(example());
  const std::string csv = traceability_csv(rows);
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), rows.size() + 1);
  EXPECT_EQ(csv.rfind("uca,uca_type,control_action,hazard,asil,smil,loss,loss_name,reversible,fsm_transitions,"
                      "region,scenarios\n",
                      0),
            0u);
}

TEST(Traceability, DanglingReferencesAreLeftOutOfTheMatrix) {
  const auto text = testing::replace_once(testing::example_text(), "hazards: [H5, H7]", "hazards: [H5, H77]");
  const auto sc = parse_safety_case(text, "case.yaml");
  for (const auto& r : traceability_matrix(sc)) EXPECT_NE(r.hazard, "H77");
}

TEST(AnalysisJson, CountsMatchTheCase) {
  const auto sc = example();
  const auto j = analysis_json(sc, check(sc));
  EXPECT_EQ(j["summary"]["hazards"], 8);
  EXPECT_EQ(j["summary"]["errors"], 0);
  EXPECT_EQ(j["asil"].size(), 8u);
  EXPECT_EQ(j["traceability"].size(), traceability_matrix(sc).size());
}

}  // namespace traceability_test
}  // namespace emrm::safety
