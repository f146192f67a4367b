// End-to-end: `emrm verify` on a store written by `emrm sweep`, and on copies of it with one claim
// changed: every changed claim is found (exit 1, named), a damaged maneuver is bad input (exit 2).

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <cstdlib>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace verify_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// A green cell, cells where only an evasive strategy avoids, and one where nothing does.
constexpr const char* kCampaign =
    "seed: 5\n"
    "grids:\n"
    "  - name: g\n"
    "    speed_kph: [40, 60]\n"
    "    ttc_s: [0.45, 2.0]\n"
    "  - name: r\n"
    "    speed_kph: 70\n"
    "    ttc_s: 0.25\n";

// Copies the sweep's store and changes it with one SQL statement (through SQLite's own library,
// which emrm links: no shell needed).
fs::path tampered(const fs::path& from, const fs::path& dir, const std::string& sql) {
  fs::create_directories(dir);
  fs::copy_file(from / "results.sqlite", dir / "results.sqlite", fs::copy_options::overwrite_existing);
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open((dir / "results.sqlite").string().c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << sql << ": " << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
  return dir;
}

class VerifyCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(scratch_dir("verify"));
    write_text(*dir_ / "campaign.yaml", kCampaign);
    const auto r = run_emrm("sweep " + quoted(*dir_ / "campaign.yaml") + " -o " + quoted(*dir_ / "out"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path* dir_;
};
fs::path* VerifyCli::dir_ = nullptr;

TEST_F(VerifyCli, AStoreFromASweepHoldsEveryClaim) {
  const auto r = run_emrm("verify " + quoted(*dir_ / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("All claims hold."));
  EXPECT_THAT(r.out, HasSubstr("| G |"));
  const auto j = run_emrm("verify " + quoted(*dir_ / "out" / "results.sqlite") + " --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_THAT(j.out, HasSubstr("\"ok\": true"));
}

// A user's own `verify` keeps its result beside the store, where the report shows it (it was
// written only by reproduce, so the report said "No verification" after a user's verify), and
// takes --threads as every command that works in parallel does, with the same result.
TEST_F(VerifyCli, ItKeepsItsResultForTheReportWhateverTheThreads) {
  const fs::path out = *dir_ / "kept";
  fs::create_directories(out);
  fs::copy_file(*dir_ / "out" / "results.sqlite", out / "results.sqlite", fs::copy_options::overwrite_existing);
  const auto one = run_emrm("verify " + quoted(out) + " --threads 1 --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_TRUE(fs::exists(out / "verify.json"));
  EXPECT_EQ(read_text(out / "verify.json"), one.out);
  const auto two = run_emrm("verify " + quoted(out) + " --threads 2");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_THAT(two.out, HasSubstr("Wrote " + (out / "verify.json").string()));
  EXPECT_EQ(read_text(out / "verify.json"), one.out);
  EXPECT_NE(run_emrm("verify " + quoted(out) + " --threads -1").exit_code, 0);
  const auto report = run_emrm("report " + quoted(out));
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = read_text(out / "report.html");
  EXPECT_THAT(html, HasSubstr("<summary>verify.json</summary>"));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("No verification in this folder")));
}

// A store damaged by hand is bad input with the damage named, for every reader (report, verify,
// diagnose), never a crash: a NULL key in its metadata (was SIGSEGV), a seed that is not a number
// (was an uncaught std::stoull exception), another schema version, a region, method or evidence
// that is none of its names.
TEST_F(VerifyCli, ADamagedStoreIsBadInputNamingTheDamage) {
  const std::vector<std::pair<std::string, std::string>> damages{
      {"UPDATE meta SET key = NULL WHERE key = 'grids'", "no 'grids' in its metadata"},
      {"UPDATE meta SET value = 'abc' WHERE key = 'seed'", "its seed is 'abc', not a whole number"},
      {"UPDATE cells SET seed = 'x1' WHERE cell_index = 0", "is 'x1', not a whole number"},
      {"UPDATE meta SET value = '99' WHERE key = 'schema_version'", "schema version 99"},
      // Regions, evidence and methods are read as their enums (records.hpp): another text is damage.
      {"UPDATE cells SET region = 'X' WHERE cell_index = 0", "is 'X', not G, Y, O, R or infeasible"},
      {"UPDATE cells SET method = 'guessed' WHERE cell_index = 0", "its method of cell "},
      {"UPDATE outcomes SET evidence = 'hearsay' WHERE cell_index = 0",
       "is 'hearsay', not witness, certificate or undecided"}};
  int n = 0;
  for (const auto& [sql, message] : damages) {
    const auto dir = tampered(*dir_ / "out", *dir_ / ("damaged" + std::to_string(n++)), sql);
    for (const std::string command : {"verify ", "report ", "diagnose "}) {
      const auto r = run_emrm(command + quoted(dir));
      EXPECT_EQ(r.exit_code, 2) << command << sql << "\n" << r.err;
      EXPECT_THAT(r.err, HasSubstr(message)) << command << sql;
    }
  }
}

TEST_F(VerifyCli, AChangedRegionIsFound) {
  const auto dir = tampered(*dir_ / "out", *dir_ / "region",
                            "UPDATE cells SET region = 'R', evidence = 'undecided' WHERE region = 'G'");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("region R stored, the outcomes give G"));
}

TEST_F(VerifyCli, AnAvoidanceClaimedWithoutOneIsFound) {
  const auto dir = tampered(*dir_ / "out", *dir_ / "claim",
                            "UPDATE outcomes SET avoided = 1, contact = 0, loss_level = 0 WHERE grid = 'r' AND "
                            "strategy = 'emergency_stop'");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("r#0 emergency_stop: replay does not avoid, unlike what is stored"));
}

TEST_F(VerifyCli, AWitnessThatDoesNotDriveTheClaimIsFound) {
  const auto dir = tampered(*dir_ / "out", *dir_ / "witness",
                            "UPDATE outcomes SET maneuver = '{\"plan\":[],\"tail\":null}' WHERE avoided = 1");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("replay does not avoid"));
}

TEST_F(VerifyCli, ACertificateForAnotherCellIsFound) {
  const auto count = [&](const fs::path& dir) { return run_emrm("verify " + quoted(dir) + " --json"); };
  ASSERT_THAT(count(*dir_ / "out").out, ::testing::Not(HasSubstr("\"certificates\": 0"))) << "no certified cell";
  const auto dir = tampered(*dir_ / "out", *dir_ / "certificate",
                            "UPDATE cells SET certificate = replace(certificate, '\"speed_kph\":70.0', "
                            "'\"speed_kph\":30.0') WHERE certificate != ''");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("the certificate does not hold"));
}

TEST_F(VerifyCli, ADamagedManeuverIsBadInputNamingTheCell) {
  const auto dir =
      tampered(*dir_ / "out", *dir_ / "damaged", "UPDATE outcomes SET maneuver = '{\"plan\": 3}' WHERE grid = 'r'");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("cell r#0"));
  EXPECT_THAT(r.err, HasSubstr("'plan' must be an array"));
}

TEST(VerifyCliInput, ANonStoreIsBadInput) {
  const auto dir = scratch_dir("verify_none");
  const auto r = run_emrm("verify " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("no results store here"));
}

}  // namespace verify_cli_test
}  // namespace emrm::e2e
