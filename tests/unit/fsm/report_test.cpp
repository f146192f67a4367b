#include "emrm/fsm/report.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "emrm/fsm/dot.hpp"

namespace emrm::fsm {
namespace report_test {

using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

std::string example(const std::string& name) { return std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/" + name; }

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// S0 --a--> S1 and S0 --a--> S2: one non-deterministic choice; S2 is a dead end, S1 marked.
Generator nondeterministic() {
  Generator g("nd");
  for (const char* s : {"S0", "S1", "S2"}) g.add_state(s);
  g.add_event("a");
  g.add_transition("S0", "a", "S1");
  g.add_transition("S0", "a", "S2");
  g.set_initial("S0");
  g.mark("S1");
  return g;
}

std::vector<std::string> keys(const nlohmann::ordered_json& j) {
  std::vector<std::string> out;
  for (const auto& [key, value] : j.items()) out.push_back(key);
  return out;
}

TEST(FsmReport, WithoutOperationsTheTextIsTheSummaryAndTheJsonHasOnlyTheMachine) {
  const auto report = make_report(nondeterministic(), "nd.yaml", {});
  EXPECT_FALSE(report.has_operations());
  EXPECT_TRUE(report.ok());
  EXPECT_THAT(to_text(report), HasSubstr("nd (nd.yaml): 3 states, 1 event, 2 transitions, non-deterministic"));
  EXPECT_EQ(keys(to_json(report)), (std::vector<std::string>{"fsm", "written"}));
}

TEST(FsmReport, JsonHasTheAskedPartsInOrderAndListsEveryChoice) {
  ReportRequest request;
  request.check = true;
  request.words_max_length = 2;
  request.word_queries = {"a", "b"};
  request.traces = TraceFile{"t.txt", {{{"a"}, {}}}};
  auto report = make_report(nondeterministic(), "nd.yaml", request);
  report.written.push_back("nd.dot");
  EXPECT_FALSE(report.ok());  // not deterministic, and S2 blocks
  const auto j = to_json(report);
  EXPECT_EQ(keys(j), (std::vector<std::string>{"fsm", "check", "words", "word_queries", "coverage", "written"}));
  const auto& choices = j["check"]["deterministic"]["choices"];
  ASSERT_TRUE(choices.is_array());
  ASSERT_EQ(choices.size(), 1U);
  EXPECT_EQ(choices[0]["state"], "S0");
  EXPECT_EQ(choices[0]["transitions"].size(), 2U);
  EXPECT_EQ(j["word_queries"][1]["generated"], false);
  EXPECT_EQ(j["written"][0], "nd.dot");

  const auto text = to_text(report);
  EXPECT_THAT(text, Not(HasSubstr("states:")));  // operations asked: no summary
  EXPECT_THAT(text, HasSubstr("deterministic:  FAILED: S0 on 'a' goes to S1 or S2"));
  EXPECT_THAT(text, HasSubstr("word \"b\": not in L(G): 'b' (event 1) is not an event of the machine"));
  EXPECT_THAT(text, HasSubstr("transition coverage of 1 trace from t.txt"));
  EXPECT_THAT(text, HasSubstr("wrote nd.dot\n"));
  EXPECT_THAT(diagram_dot(report), HasSubstr("a (1)"));  // coloured by the coverage
}

TEST(FsmReport, CheckFilesHoldTheJsonOfACheckReportAndThePlainDiagram) {
  const auto dir = fs::temp_directory_path() / ("emrm-fsm-report-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path file = example("emrm_fsm.yaml");
  const auto written = write_check_files(file, dir);
  ASSERT_TRUE(written.check.has_value());
  EXPECT_TRUE(written.ok());

  ReportRequest request;
  request.check = true;
  const auto report = make_report(load_generator(file), file.string(), request);
  EXPECT_EQ(read(dir / "emrm_fsm_check.json"), to_json(report).dump(2) + "\n");
  EXPECT_EQ(read(dir / "emrm_fsm_plain.dot"), to_dot(report.machine));
  fs::remove_all(dir);
}

}  // namespace report_test
}  // namespace emrm::fsm
