#include "emrm/core/expression.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

namespace emrm::core {
namespace expression_test {

using ::testing::HasSubstr;

const std::vector<std::string> kFactors{"speed_kph", "ttc_s", "mu"};

TEST(Expression, EvaluatesComparisonsAndLogic) {
  Expression e("ttc_s < 0.7 && mu < 0.3", kFactors, {"f", 1, 1});
  EXPECT_TRUE(e.holds(std::vector<double>{50, 0.5, 0.2}));
  EXPECT_FALSE(e.holds(std::vector<double>{50, 0.5, 0.4}));
  EXPECT_FALSE(e.holds(std::vector<double>{50, 0.7, 0.2}));
  Expression n("!(ttc_s < 0.7) || speed_kph >= 72", kFactors, {"f", 1, 1});
  EXPECT_TRUE(n.holds(std::vector<double>{30, 1.0, 1.0}));
  EXPECT_TRUE(n.holds(std::vector<double>{72, 0.1, 1.0}));
  EXPECT_FALSE(n.holds(std::vector<double>{71, 0.1, 1.0}));
}

TEST(Expression, ComputesArithmeticLikeTheClosedForm) {
  Expression stop("(speed_kph / 3.6)^2 / (2 * mu * 9.81)", kFactors, {"f", 1, 1});
  const double v = 50.0 / 3.6;
  EXPECT_NEAR(stop.evaluate(std::vector<double>{50, 0, 0.8}), v * v / (2 * 0.8 * 9.81), 1e-12);
}

TEST(Expression, ReportsOnlyTheVariablesItReads) {
  Expression e("mu * 2 > speed_kph", kFactors, {"f", 1, 1});
  EXPECT_EQ(e.used_variables(), (std::vector<std::string>{"speed_kph", "mu"}));
}

TEST(Expression, UnknownNameIsAnInputErrorAtItsColumn) {
  try {
    Expression e("ttc_s < 1 && rain > 2", kFactors, {"f.yaml", 4, 11});
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().line, 4);
    EXPECT_EQ(err.where().column, 11 + 13);  // the r of rain
    EXPECT_THAT(err.message(), HasSubstr("unknown name 'rain'"));
    EXPECT_THAT(err.message(), HasSubstr("speed_kph, ttc_s, mu"));
  }
}

TEST(Expression, SyntaxErrorsAndEmptyTextAreInputErrors) {
  EXPECT_THROW(Expression("ttc_s < ", kFactors, {"f", 1, 1}), InputError);
  EXPECT_THROW(Expression("(mu", kFactors, {"f", 1, 1}), InputError);
  EXPECT_THROW(Expression("  ", kFactors, {"f", 1, 1}), InputError);
}

TEST(Expression, QuotedYamlScalarErrorsPointInsideTheQuotes) {
  const auto node = YamlNode::parse("region: \"mu < x\"\n", "r.yaml");
  try {
    Expression e(node.at("region"), kFactors);
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().line, 1);
    EXPECT_EQ(err.where().column, 15);  // the x
  }
}

TEST(Expression, CopiesEvaluateIndependently) {
  Expression a("mu * 10", kFactors, {"f", 1, 1});
  Expression b = a;
  EXPECT_DOUBLE_EQ(a.evaluate(std::vector<double>{0, 0, 0.5}), 5.0);
  EXPECT_DOUBLE_EQ(b.evaluate(std::vector<double>{0, 0, 0.1}), 1.0);
  EXPECT_DOUBLE_EQ(a.evaluate(std::vector<double>{0, 0, 0.2}), 2.0);
}

}  // namespace expression_test
}  // namespace emrm::core
