// Atomic outputs end to end (docs/outputs.md, "Atomic outputs"): a command that fails leaves no
// partial output file and no temporary; a multi-file command that fails on bad input, or on one
// target it cannot write, writes none of its files; a command that succeeds leaves no temporary.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace atomic_outputs_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;
using Names = std::vector<std::string>;

// The regular files under `dir` (recursively, relative to it, sorted); none when it is absent.
Names files_under(const fs::path& dir) {
  Names names;
  if (!fs::exists(dir)) return names;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) names.push_back(fs::relative(entry.path(), dir).generic_string());
  std::sort(names.begin(), names.end());
  return names;
}

// What is under `dir` and looks like a temporary of an atomic write (NAME.tmp.PID.N), files or folders.
Names temporaries_under(const fs::path& dir) {
  Names names;
  if (!fs::exists(dir)) return names;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos)
      names.push_back(fs::relative(entry.path(), dir).generic_string());
  return names;
}

class AtomicOutputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { example_ = new fs::path(small_example("atomic")); }
  static void TearDownTestSuite() { delete example_; }
  static fs::path scratch(const std::string& name) { return example_->parent_path() / name; }
  static fs::path* example_;
};
fs::path* AtomicOutputs::example_ = nullptr;

// One of the five targets is a folder: the plan writes none of the five (it used to write the
// first four and leave coverage.md.tmp), and when it can, all five and no temporary.
TEST_F(AtomicOutputs, PlanWritesAllFiveFilesOrNone) {
  const auto blocked = scratch("plan-blocked");
  fs::create_directories(blocked / "coverage.md" / "inside");
  auto r = run_emrm("plan " + quoted(*example_ / "odd.yaml") + " -o " + quoted(blocked));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("coverage.md"));
  EXPECT_EQ(files_under(blocked), Names{});
  EXPECT_EQ(temporaries_under(blocked), Names{});

  const auto plan = scratch("plan");
  r = run_emrm("plan " + quoted(*example_ / "odd.yaml") + " -o " + quoted(plan));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(files_under(plan),
            (Names{"coverage.csv", "coverage.json", "coverage.md", "scenarios.csv", "scenarios.json"}));
}

TEST_F(AtomicOutputs, AnalyzeWritesAllFourFilesOrNone) {
  const auto blocked = scratch("analysis-blocked");
  fs::create_directories(blocked / "asil.csv" / "inside");
  auto r = run_emrm("analyze " + quoted(*example_ / "safety.yaml") + " -o " + quoted(blocked));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(files_under(blocked), Names{});
  EXPECT_EQ(temporaries_under(blocked), Names{});

  const auto analysis = scratch("analysis");
  r = run_emrm("analyze " + quoted(*example_ / "safety.yaml") + " -o " + quoted(analysis));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(files_under(analysis), (Names{"asil.csv", "findings.json", "traceability.csv", "traceability.md"}));
}

// --dot and --svg: both or neither (the DOT file used to be written before the SVG failed).
TEST_F(AtomicOutputs, FsmWritesItsDiagramsBothOrNeither) {
  const auto out = scratch("fsm");
  fs::create_directories(out / "g.svg" / "inside");
  const auto r = run_emrm("fsm " + quoted(*example_ / "emrm_fsm.yaml") + " --dot " + quoted(out / "g.dot") + " --svg " +
                          quoted(out / "g.svg"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(files_under(out), Names{});
  EXPECT_EQ(temporaries_under(out), Names{});
}

// A safety case `emrm run` cannot read fails the run before the store is opened: nothing written
// (the store, the exports, outcomes.csv and estimates.csv used to be written first). The run that
// succeeds, and the report on it, leave no temporary; a malformed table in the folder fails the
// report before the first figure is drawn.
TEST_F(AtomicOutputs, RunAndReportReadEveryInputBeforeWriting) {
  const auto plan = scratch("run-plan");
  auto r = run_emrm("plan " + quoted(*example_ / "odd.yaml") + " -o " + quoted(plan));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  write_text(scratch("broken") / "safety.yaml", "name: [unclosed\n");

  const auto failed = scratch("run-failed");
  r = run_emrm("run " + quoted(plan / "scenarios.csv") + " --safety " + quoted(scratch("broken") / "safety.yaml") +
               " -o " + quoted(failed) + " --threads 2");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_FALSE(fs::exists(failed)) << "written: " << testing::PrintToString(files_under(failed));

  const auto out = scratch("run");
  r = run_emrm("run " + quoted(plan / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(temporaries_under(out), Names{});
  const Names files = files_under(out);
  for (const std::string name : {"outcomes.csv", "estimates.csv", "estimates.json", "traceability.csv",
                                 "traceability.md", "regions.csv", "cells.csv", "cells.json", "results.sqlite"})
    EXPECT_NE(std::find(files.begin(), files.end(), name), files.end()) << name;

  write_text(out / "tables" / "broken.csv", "a,\"never closed\n");
  r = run_emrm("report " + quoted(out));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("broken.csv"));
  EXPECT_FALSE(fs::exists(out / "figures"));
  EXPECT_FALSE(fs::exists(out / "report.html"));

  fs::remove(out / "tables" / "broken.csv");
  r = run_emrm("report " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(fs::is_regular_file(out / "report.html"));
  EXPECT_TRUE(fs::is_regular_file(out / "figures" / "emrm_fsm.png"));
  EXPECT_EQ(temporaries_under(out), Names{});
}

// The sweep's three exports are renamed into place only once all three are complete; a
// --progress-log that cannot be written is bad input found before the store is created.
TEST_F(AtomicOutputs, SweepExportsAllThreeOrNone) {
  const auto log_blocked = scratch("sweep-log-blocked");
  fs::create_directories(log_blocked / "log");
  auto r = run_emrm("sweep " + quoted(*example_ / "campaign.yaml") + " -o " + quoted(log_blocked) +
                    " --threads 2 --progress-log " + quoted(log_blocked / "log"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(files_under(log_blocked), Names{});

  const auto sweep = scratch("sweep");
  r = run_emrm("sweep " + quoted(*example_ / "campaign.yaml") + " -o " + quoted(sweep) + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(temporaries_under(sweep), Names{});

  const auto merged = scratch("merged");
  fs::create_directories(merged / "cells.json" / "inside");
  r = run_emrm("merge " + quoted(sweep) + " -o " + quoted(merged));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("cells.json"));
  EXPECT_FALSE(fs::exists(merged / "regions.csv"));
  EXPECT_FALSE(fs::exists(merged / "cells.csv"));
  EXPECT_EQ(temporaries_under(merged), Names{});
}

}  // namespace atomic_outputs_cli_test
}  // namespace emrm::e2e
