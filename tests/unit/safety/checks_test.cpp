#include "emrm/safety/checks.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "emrm/safety/load.hpp"
#include "example_case.hpp"

namespace emrm::safety {
namespace checks_test {

using testing::example_text;
using ::testing::HasSubstr;
using testing::line_of;
using testing::replace_once;

std::vector<Finding> findings_of(const std::string& text, const std::optional<FsmTransitions>& fsm = {}) {
  return check(parse_safety_case(text, "case.yaml"), fsm);
}

std::vector<Finding> with_code(const std::vector<Finding>& findings, const std::string& code) {
  std::vector<Finding> out;
  std::copy_if(findings.begin(), findings.end(), std::back_inserter(out),
               [&](const Finding& f) { return f.code == code; });
  return out;
}

FsmTransitions emrm_fsm_transitions() {
  return {"emrm_fsm.yaml",
          {{"S1", "hazard_detected", "S2"},
           {"S2", "no_risk", "S1"},
           {"S2", "high_risk", "S3"},
           {"S3", "execute_maneuver", "S4"},
           {"S4", "emrm_done", "S1"},
           {"S4", "timeout_error", "S5"},
           {"S5", "post_incident_response", "S6"},
           {"S6", "safe", "S1"}}};
}

TEST(SafetyChecks, ShippedExampleHasNoErrorsAndWarnsAboutTheUnreachedLoss) {
  const auto findings = findings_of(example_text(), emrm_fsm_transitions());
  EXPECT_EQ(count(findings, FindingSeverity::kError), 0u);
  const auto unreached = with_code(findings, "SAF003");
  ASSERT_EQ(unreached.size(), 1u);
  EXPECT_EQ(unreached[0].subject, "L5");
  EXPECT_EQ(unreached[0].severity, FindingSeverity::kWarning);
}

TEST(SafetyChecks, DanglingHazardReferenceOfAUcaNamesTheMissingIdAtItsPlace) {
  const std::string text = replace_once(example_text(), "hazards: [H2, H6]", "hazards: [H2, H66]");
  const auto dangling = with_code(findings_of(text), "SAF001");
  ASSERT_EQ(dangling.size(), 1u);
  EXPECT_EQ(dangling[0].severity, FindingSeverity::kError);
  EXPECT_THAT(dangling[0].message, HasSubstr("'H66'"));
  EXPECT_EQ(dangling[0].where.line, line_of(text, "H66"));
  EXPECT_EQ(dangling[0].where.column, testing::column_of(text, "H66"));
}

TEST(SafetyChecks, DanglingLossAndControlActionReferencesAreFound) {
  std::string text = replace_once(example_text(), "losses: [L6, L7]", "losses: [L6, L8]");
  text = replace_once(text, "control_action: CA1\n    type: provided\n", "control_action: CA9\n    type: provided\n");
  const auto dangling = with_code(findings_of(text), "SAF001");
  ASSERT_EQ(dangling.size(), 2u);
  EXPECT_THAT(dangling[0].message, HasSubstr("loss 'L8'"));
  EXPECT_THAT(dangling[1].message, HasSubstr("control action 'CA9'"));
}

TEST(SafetyChecks, HazardWithoutLossIsAnError) {
  const auto f = with_code(findings_of(replace_once(example_text(), "losses: [L6, L7]", "losses: []")), "SAF002");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].subject, "H1");
}

TEST(SafetyChecks, UcaWithoutHazardIsAnError) {
  const auto f = with_code(findings_of(replace_once(example_text(), "hazards: [H5, H7]", "hazards: []")), "SAF004");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].subject, "UCA4");
}

TEST(SafetyChecks, MissingUcaTypeOfAControlActionIsAWarning) {
  const std::string text = replace_once(example_text(), "type: wrong_timing_or_order", "type: not_provided");
  const auto f = with_code(findings_of(text), "SAF005");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].severity, FindingSeverity::kWarning);
  EXPECT_THAT(f[0].message, HasSubstr("wrong_timing_or_order"));
}

TEST(SafetyChecks, StatedAsilThatDisagreesWithRatingsIsAnError) {
  const std::string text = replace_once(example_text(), "    asil: A\n", "    asil: C\n");
  const auto f = with_code(findings_of(text), "SAF006");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].subject, "H7");
  EXPECT_THAT(f[0].message, HasSubstr("states ASIL C but S3 E2 C2 give ASIL A"));
}

TEST(SafetyChecks, UcaWithoutTransitionOrRegionIsAnError) {
  std::string text = replace_once(example_text(), "    region: \"ttc_s < 0.7\"\n", "");
  text = replace_once(text,
                      "    fsm_transitions:\n      - {from: S2, event: no_risk, to: S1}\n"
                      "      - {from: S2, event: high_risk, to: S3}\n",
                      "");
  const auto findings = findings_of(text);
  ASSERT_EQ(with_code(findings, "SAF007").size(), 1u);
  EXPECT_EQ(with_code(findings, "SAF007")[0].subject, "UCA2");
  ASSERT_EQ(with_code(findings, "SAF008").size(), 1u);
  EXPECT_EQ(with_code(findings, "SAF008")[0].subject, "UCA3");
}

TEST(SafetyChecks, StatedSmilThatDisagreesWithTheTableIsAnError) {
  const std::string text = replace_once(example_text(), "    smil: B\n", "    smil: D\n");
  const auto f = with_code(findings_of(text), "SAF009");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].subject, "H2");
  EXPECT_THAT(f[0].message, HasSubstr("gives B"));
}

TEST(SafetyChecks, SmilWithoutAMatchingRuleIsAWarning) {
  const std::string text =
      replace_once(example_text(), "    - {maneuverability: M2, avoidability: A1, mitigability: MT1, smil: F}\n", "");
  const auto f = with_code(findings_of(text), "SAF010");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].subject, "H6");
}

TEST(SafetyChecks, TransitionUnknownToTheFsmIsAnError) {
  const std::string text =
      replace_once(example_text(), "{from: S4, event: emrm_done, to: S1}", "{from: S4, event: emrm_done, to: S2}");
  const auto f = with_code(findings_of(text, emrm_fsm_transitions()), "SAF011");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_THAT(f[0].message, HasSubstr("S4 -emrm_done-> S2"));
  EXPECT_EQ(f[0].where.line, line_of(text, "{from: S4, event: emrm_done, to: S2}"));
  EXPECT_TRUE(with_code(findings_of(text), "SAF011").empty()) << "without an FSM there is nothing to check against";
}

TEST(SafetyChecks, FindingsComeInFileOrder) {
  std::string text = replace_once(example_text(), "hazards: [H5, H7]", "hazards: [H5, H77]");
  text = replace_once(text, "losses: [L6, L7]", "losses: [L6, L8]");
  const auto findings = findings_of(text);
  ASSERT_GE(findings.size(), 2u);
  for (std::size_t i = 1; i < findings.size(); ++i) EXPECT_LE(findings[i - 1].where.line, findings[i].where.line);
}

}  // namespace checks_test
}  // namespace emrm::safety
