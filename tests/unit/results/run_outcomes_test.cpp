// outcomes.csv's writer and typed reader (results/run_outcomes.hpp): what is written reads back,
// the columns are the documented ones, and a file that is not as `emrm run` writes it is refused
// at its line and column.

#include "emrm/results/run_outcomes.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "emrm/core/error.hpp"
#include "scratch.hpp"

namespace emrm::results {
namespace run_outcomes_test {

namespace fs = std::filesystem;

RunOutcomes two_scenarios() {
  RunOutcomes r;
  r.factors = {"speed_kph", "mu"};
  r.scenarios = {{.id = "S001",
                  .cell = "c1.0",
                  .malfunctions = {"brake_loss", "sensor_lag"},
                  .weight = 0.625,
                  .feasible = true,
                  .region = "Y",
                  .success = 1,
                  .chosen_strategy = "dodge",
                  .impact_speed_kph = 12.5,
                  .loss_level = 3,
                  .factor_values = {50.0, 0.35}},
                 {.id = "S002",
                  .cell = "c0.1",
                  .malfunctions = {},
                  .weight = 2.0,
                  .feasible = false,
                  .region = "infeasible",
                  .success = 0,
                  .chosen_strategy = "",
                  .impact_speed_kph = 0.0,
                  .loss_level = 0,
                  .factor_values = {90.0, 1.0}}};
  return r;
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path dir = test::scratch_dir("run-outcomes-test", name);
  fs::create_directories(dir);
  std::ofstream(dir / "outcomes.csv") << text;
  return dir / "outcomes.csv";
}

TEST(RunOutcomes, WhatIsWrittenReadsBack) {
  const RunOutcomes r = two_scenarios();
  const std::string text = run_outcomes_csv(r);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "id,cell,speed_kph,mu,malfunctions,weight,feasible,region,success,chosen_strategy,impact_speed_kph,"
            "loss_level");
  EXPECT_NE(text.find("\nS002,c0.1,90,1,,2,no,infeasible,,,,\n"), std::string::npos) << text;
  const RunOutcomes back = read_run_outcomes(write("round-trip", text));
  EXPECT_EQ(back.factors, r.factors);
  ASSERT_EQ(back.scenarios.size(), 2U);
  EXPECT_EQ(back.scenarios[0].malfunctions, r.scenarios[0].malfunctions);
  EXPECT_EQ(back.scenarios[0].factor_values, r.scenarios[0].factor_values);
  EXPECT_EQ(back.scenarios[0].success, 1);
  EXPECT_DOUBLE_EQ(back.scenarios[0].impact_speed_kph, 12.5);
  EXPECT_FALSE(back.scenarios[1].feasible);
  EXPECT_EQ(back.lines, (std::vector<int>{2, 3}));
  EXPECT_EQ(run_outcomes_csv(back), text);
}

TEST(RunOutcomes, AFileNotAsEmrmRunWritesItIsRefusedWhereItIsWrong) {
  const std::string text = run_outcomes_csv(two_scenarios());
  const auto refusal = [](const std::string& name, const std::string& bad) -> std::string {
    try {
      (void)read_run_outcomes(write(name, bad));
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << name;
    return {};
  };
  std::string bad = text;
  bad.replace(bad.find(",yes,"), 5, ",perhaps,");
  const int column = static_cast<int>(bad.find("perhaps") - bad.find("S001")) + 1;
  EXPECT_NE(refusal("flag", bad).find(fmt::format("outcomes.csv:2:{}: error: feasible: expected yes or no", column)),
            std::string::npos)
      << refusal("flag", bad);
  bad = text;
  bad.replace(bad.find("0.625"), 5, "heavy");
  EXPECT_NE(refusal("number", bad).find("weight: expected a finite number, got 'heavy'"), std::string::npos);
  bad = text;
  bad.replace(bad.find("50,"), 3, "nan,");
  EXPECT_NE(refusal("nan", bad).find("speed_kph: expected a finite number"), std::string::npos);
  EXPECT_NE(refusal("header", "id,cell,weight\nS1,c0,1\n").find("expected the header of an outcomes.csv"),
            std::string::npos);
  // Refused at the short row's last field.
  EXPECT_NE(refusal("short", text + "S3,c0\n").find("outcomes.csv:4:4: error: expected"), std::string::npos);
  EXPECT_NE(refusal("short", text + "S3,c0\n").find("fields as in the header, got 2"), std::string::npos);
}

}  // namespace run_outcomes_test
}  // namespace emrm::results
