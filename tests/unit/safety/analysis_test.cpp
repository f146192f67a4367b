#include "emrm/safety/analysis.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "emrm/safety/load.hpp"
#include "example_case.hpp"

namespace emrm::safety {
namespace analysis_test {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Edge {
  std::string from, event, to;
};

TEST(Analysis, FsmFileIsTheCasesEntryBesideTheCaseFile) {
  const auto sc = parse_safety_case(testing::example_text(), "cases/tjunction/safety.yaml");
  ASSERT_TRUE(fsm_file(sc).has_value());
  EXPECT_EQ(*fsm_file(sc), fs::path("cases/tjunction/emrm_fsm.yaml"));
  const auto without =
      parse_safety_case(testing::replace_once(testing::example_text(), "fsm: emrm_fsm.yaml\n", ""), "safety.yaml");
  EXPECT_FALSE(fsm_file(without).has_value());
}

TEST(Analysis, FsmTransitionsTakeAnyRangeOfFromEventTo) {
  const std::vector<Edge> edges{{"S1", "hazard_detected", "S2"}, {"S2", "no_risk", "S1"}};
  const auto known = fsm_transitions("g.yaml", edges);
  EXPECT_EQ(known.file, "g.yaml");
  EXPECT_EQ(known.transitions.size(), 2U);
  EXPECT_TRUE(known.transitions.contains({"S2", "no_risk", "S1"}));
}

TEST(Analysis, MissingFsmTransitionIsAnErrorAndJsonNamesTheFsmOnlyWhenChecked) {
  // Only one of the transitions the UCAs name: SAF011 errors.
  const std::vector<Edge> edges{{"S1", "hazard_detected", "S2"}};
  const auto checked =
      analyze(parse_safety_case(testing::example_text(), "safety.yaml"), fsm_transitions("emrm_fsm.yaml", edges));
  EXPECT_GT(checked.errors(), 0U);
  EXPECT_EQ(to_json(checked)["fsm"], "emrm_fsm.yaml");
  EXPECT_NE(to_text(checked).find("FSM transitions checked against emrm_fsm.yaml (1 transitions)"), std::string::npos);

  const auto unchecked = analyze(parse_safety_case(testing::example_text(), "safety.yaml"));
  EXPECT_EQ(unchecked.errors(), 0U);
  EXPECT_FALSE(to_json(unchecked).contains("fsm"));
  EXPECT_EQ(unchecked.matrix.size(), traceability_matrix(unchecked.safety_case).size());
}

TEST(Analysis, WritesTheFourFilesFromTheOneProducerOfEach) {
  const auto dir = fs::temp_directory_path() / ("emrm-analysis-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto analysis = analyze(parse_safety_case(testing::example_text(), "safety.yaml"));
  const auto files = write_analysis(dir, analysis);
  ASSERT_EQ(files.size(), 4U);
  for (const auto& f : files) EXPECT_TRUE(fs::is_regular_file(f)) << f;
  EXPECT_EQ(read(dir / "traceability.csv"), traceability_csv(analysis.matrix));
  EXPECT_EQ(read(dir / "traceability.md"),
            "# Traceability matrix: " + analysis.safety_case.name + "\n\n" + traceability_markdown(analysis.matrix));
  EXPECT_EQ(read(dir / "findings.json"), findings_json(analysis.findings).dump(2) + "\n");
  EXPECT_EQ(read(dir / "asil.csv"), core::csv_table(asil_header(), asil_rows(analysis.safety_case)));
  fs::remove_all(dir);
}

}  // namespace analysis_test
}  // namespace emrm::safety
