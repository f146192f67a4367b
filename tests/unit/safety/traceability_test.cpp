#include "emrm/safety/traceability.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/safety/load.hpp"
#include "example_case.hpp"
#include "scratch.hpp"

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

std::filesystem::path written(const std::string& name, const std::string& text) {
  const auto dir = emrm::test::scratch_dir("traceability-test", name);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "traceability.csv") << text;
  return dir / "traceability.csv";
}

TEST(Traceability, TheCsvReadsBackAsItsRows) {
  auto rows = traceability_matrix(example());
  ASSERT_GE(rows.size(), 2U);
  rows[0].scenarios = {"S001", "S017", "S203"};
  rows[1].loss_name = "a name, with a comma and \"quotes\"";
  rows[1].loss_reversible = !rows[1].loss_reversible;
  const auto back = read_traceability_csv(written("round-trip", traceability_csv(rows)));
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(to_row(back[i]), to_row(rows[i])) << i;
  EXPECT_EQ(back[0].scenarios, rows[0].scenarios);
  EXPECT_EQ(back[0].transitions, rows[0].transitions);
  EXPECT_FALSE(back[0].transitions.empty());
}

TEST(Traceability, AMalformedCsvIsRefusedWhereItIsWrong) {
  const auto rows = traceability_matrix(example());
  std::string csv = traceability_csv(rows);
  const auto refusal = [](const std::string& name, const std::string& text) -> std::string {
    try {
      (void)read_traceability_csv(written(name, text));
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << name;
    return {};
  };
  // `reversible` on the third line (the second row) made "perhaps": its line and column.
  const std::size_t line3 = csv.find('\n', csv.find('\n') + 1) + 1;
  const std::string row = csv.substr(line3, csv.find('\n', line3) - line3);
  const std::string value = to_row(rows[1])[8];
  const std::size_t column = row.find("," + value + ",") + 2;  // 1-based, after the comma
  std::string bad = csv;
  bad.replace(line3 + column - 1, value.size(), "perhaps");
  EXPECT_NE(refusal("reversible", bad)
                .find(fmt::format("traceability.csv:3:{}: error: reversible: expected yes or no", column)),
            std::string::npos)
      << refusal("reversible", bad);
  EXPECT_NE(refusal("header", "uca,hazard\n").find("expected a traceability matrix with the header"),
            std::string::npos);
  EXPECT_NE(refusal("short", csv + "UCA1,x\n").find("fields as in the header, got 2"), std::string::npos);
}

TEST(Findings, TheJsonReadsBackAsTheFindings) {
  const std::vector<Finding> findings{
      {"SAF001", FindingSeverity::kError, "UCA9", "a \"dangling\" reference", {"case.yaml", 12, 7}},
      {"SAF014", FindingSeverity::kWarning, "H2", "no loss", {"", 0, 0}}};
  const auto file = written("findings", findings_json(findings).dump(2) + "\n");
  const auto back = read_findings_json(file);
  ASSERT_EQ(back.size(), findings.size());
  for (std::size_t i = 0; i < findings.size(); ++i) {
    EXPECT_EQ(back[i].code, findings[i].code);
    EXPECT_EQ(back[i].severity, findings[i].severity);
    EXPECT_EQ(back[i].subject, findings[i].subject);
    EXPECT_EQ(back[i].message, findings[i].message);
    EXPECT_EQ(back[i].where.str(), findings[i].where.str());
  }
  EXPECT_EQ(findings_json(back), findings_json(findings));
  // The members are sorted by name, as the file has always been written.
  EXPECT_EQ(findings_json(findings).dump().rfind("[{\"code\":\"SAF001\",\"column\":7,\"file\":", 0), 0U);
  try {
    (void)read_findings_json(written("bad-severity", "[\n  {\"code\": \"X\", \"severity\": \"fatal\"}\n]\n"));
    ADD_FAILURE() << "read an unknown severity";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("traceability.csv:2:"), std::string::npos) << e.what();
  }
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
