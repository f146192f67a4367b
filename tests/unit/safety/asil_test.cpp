#include "emrm/safety/asil.hpp"

#include <gtest/gtest.h>

namespace emrm::safety {
namespace asil_test {

// ISO 26262-3:2018 Table 4, transcribed row by row (S1..S3 × E1..E4 × C1..C3), independent of
// the sum rule the implementation uses.
constexpr const char* kIsoTable[3][4][3] = {
    {{"QM", "QM", "QM"}, {"QM", "QM", "QM"}, {"QM", "QM", "A"}, {"QM", "A", "B"}},  // S1
    {{"QM", "QM", "QM"}, {"QM", "QM", "A"}, {"QM", "A", "B"}, {"A", "B", "C"}},     // S2
    {{"QM", "QM", "A"}, {"QM", "A", "B"}, {"A", "B", "C"}, {"B", "C", "D"}},        // S3
};

TEST(Asil, MatchesIso26262Table4ForEveryRatedCombination) {
  int checked = 0;
  for (int s = 1; s <= 3; ++s)
    for (int e = 1; e <= 4; ++e)
      for (int c = 1; c <= 3; ++c) {
        const Asil asil =
            determine_asil(static_cast<Severity>(s), static_cast<Exposure>(e), static_cast<Controllability>(c));
        EXPECT_EQ(core::enum_name(asil), kIsoTable[s - 1][e - 1][c - 1]) << "S" << s << " E" << e << " C" << c;
        ++checked;
      }
  EXPECT_EQ(checked, 36);
}

TEST(Asil, AnyRatingOfZeroGivesQm) {
  int checked = 0;
  for (int s = 0; s <= 3; ++s)
    for (int e = 0; e <= 4; ++e)
      for (int c = 0; c <= 3; ++c) {
        if (s != 0 && e != 0 && c != 0) continue;
        EXPECT_EQ(determine_asil(static_cast<Severity>(s), static_cast<Exposure>(e), static_cast<Controllability>(c)),
                  Asil::kQM);
        ++checked;
      }
  EXPECT_EQ(checked, 4 * 5 * 4 - 36);
}

TEST(Asil, RaisingAnyRatingNeverLowersTheAsil) {
  for (int s = 0; s <= 3; ++s)
    for (int e = 0; e <= 4; ++e)
      for (int c = 0; c <= 3; ++c) {
        const Asil base =
            determine_asil(static_cast<Severity>(s), static_cast<Exposure>(e), static_cast<Controllability>(c));
        if (s < 3) {
          EXPECT_GE(
              determine_asil(static_cast<Severity>(s + 1), static_cast<Exposure>(e), static_cast<Controllability>(c)),
              base);
        }
        if (e < 4) {
          EXPECT_GE(
              determine_asil(static_cast<Severity>(s), static_cast<Exposure>(e + 1), static_cast<Controllability>(c)),
              base);
        }
        if (c < 3) {
          EXPECT_GE(
              determine_asil(static_cast<Severity>(s), static_cast<Exposure>(e), static_cast<Controllability>(c + 1)),
              base);
        }
      }
}

TEST(SmilTable, FirstMatchingRuleWinsAndUnstatedRatingsDoNotMatch) {
  SmilTable table;
  table.levels = {"B", "D"};
  SmilRule specific;
  specific.maneuverability = Maneuverability::kM3;
  specific.severity = Severity::kS3;
  specific.smil = "D";
  SmilRule general;
  general.maneuverability = Maneuverability::kM3;
  general.smil = "B";
  table.rules = {specific, general};

  Hazard h;
  h.severity = Severity::kS3;
  h.maneuverability = Maneuverability::kM3;
  ASSERT_NE(find_smil_rule(table, h), nullptr);
  EXPECT_EQ(find_smil_rule(table, h)->smil, "D");
  h.severity = Severity::kS2;
  EXPECT_EQ(find_smil_rule(table, h)->smil, "B");
  h.maneuverability.reset();
  EXPECT_EQ(find_smil_rule(table, h), nullptr);
}

TEST(SmilTable, RuleOnAsilUsesTheComputedAsil) {
  SmilTable table;
  SmilRule rule;
  rule.asil = Asil::kD;
  rule.smil = "X";
  table.rules = {rule};
  Hazard h;
  h.severity = Severity::kS3;
  h.exposure = Exposure::kE4;
  h.controllability = Controllability::kC3;
  h.asil = Asil::kA;  // stated wrongly; the computed D is what the table sees
  EXPECT_NE(find_smil_rule(table, h), nullptr);
  h.controllability = Controllability::kC2;
  EXPECT_EQ(find_smil_rule(table, h), nullptr);
}

}  // namespace asil_test
}  // namespace emrm::safety
