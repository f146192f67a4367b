// End-to-end: `emrm export` and `emrm assess` (docs/openscenario.md). A cell and the shipped plan
// exported (files written together, nothing left behind); the trajectory `emrm simulate --json`
// shows, judged by `emrm assess`, gives the simulated outcome; bad input is exit 2 with one message
// naming file, line and column.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace exchange_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// An argument CLI11 rejects: its message, then "Run with --help for more information."
void expect_usage_error(const RunResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr(what));
}

std::size_t files_in(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
  return n;
}

TEST(ExportCli, WritesTheCellsTwoFiles) {
  const auto dir = scratch_dir("export-cell");
  const auto r = run_emrm("export --format openscenario -o " + quoted(dir / "out") +
                          " --speed-kph 50 --ttc-s 0.8 --mu 0.6 --passage-m 2 --strategy dodge --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("tjunction.xosc"));
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "tjunction.xodr"));
  EXPECT_EQ(files_in(dir / "out"), 2u);  // no temporaries left
  EXPECT_THAT(read_text(dir / "out" / "tjunction.xosc"), HasSubstr("<FollowTrajectoryAction>"));
  EXPECT_THAT(read_text(dir / "out" / "tjunction.xosc"), HasSubstr("<LogicFile filepath=\"tjunction.xodr\"/>"));
  // The count it prints is the file's: the ego's trajectory's vertices, ended on the frame grid.
  const std::string xosc = read_text(dir / "out" / "tjunction.xosc");
  const auto from = xosc.find("<Trajectory name=\"emrm_dodge\"");
  ASSERT_NE(from, std::string::npos);
  const auto to = xosc.find("</Trajectory>", from);
  std::size_t vertices = 0;
  for (auto at = xosc.find("<Vertex ", from); at != std::string::npos && at < to; at = xosc.find("<Vertex ", at + 1))
    ++vertices;
  EXPECT_THAT(r.out, HasSubstr("(the ego follows its dodge trajectory, " + std::to_string(vertices) + " points)"));
}

TEST(ExportCli, ExportsTheShippedPlan) {
  const auto dir = scratch_dir("export-plan");
  ASSERT_EQ(run_emrm("plan " + quoted(example("odd.yaml")) + " -o " + quoted(dir / "plan")).exit_code, 0);
  const auto r = run_emrm("export --plan " + quoted(dir / "plan") + " -o " + quoted(dir / "osc"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string distribution = read_text(dir / "osc" / "tjunction_distribution.xosc");
  std::size_t sets = 0;
  for (auto at = distribution.find("<ParameterValueSet>"); at != std::string::npos;
       at = distribution.find("<ParameterValueSet>", at + 1))
    ++sets;
  const std::string csv = read_text(dir / "plan" / "scenarios.csv");
  EXPECT_EQ(sets, static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) - 1);
  EXPECT_GE(files_in(dir / "osc" / "roads"), 1u);
}

TEST(ExportCli, BadArgumentsAreExitTwo) {
  const auto dir = scratch_dir("export-bad");
  expect_bad_input(run_emrm("export -o " + quoted(dir / "a")), "give a cell (--speed-kph and --ttc-s) or a plan");
  expect_usage_error(run_emrm("export -o " + quoted(dir / "b") + " --plan " + quoted(dir) + " --speed-kph 50"),
                     "excludes");
  expect_bad_input(run_emrm("export -o " + quoted(dir / "c") + " --plan " + quoted(dir)), "no scenarios.csv");
  expect_bad_input(run_emrm("export -o " + quoted(dir / "d") + " --speed-kph 70 --ttc-s 3"), "infeasible");
  expect_bad_input(run_emrm("export -o " + quoted(dir / "e") + " --speed-kph 50 --ttc-s 1 --strategy nosuch"),
                   "nosuch");
  expect_usage_error(run_emrm("export --format sumo -o " + quoted(dir / "f") + " --speed-kph 50 --ttc-s 1"),
                     "--format");
  for (const char* name : {"a", "b", "c", "d", "e", "f"}) EXPECT_FALSE(fs::exists(dir / name)) << name;
}

// The shipped production car: a recording is judged against the scene it was driven in.
const std::string kScene = " --scene " + quoted(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/scene.yaml");

// The trajectory of every strategy in one cell, from `emrm simulate --json`, judged again.
TEST(AssessCli, SimulatedTrajectoriesGiveTheSimulatedOutcome) {
  const auto dir = scratch_dir("assess-roundtrip");
  const std::string cell = kScene + " --speed-kph 45 --ttc-s 0.7 --mu 0.7 --passage-m 2.5";
  const auto sim = run_emrm("simulate --json --seed 4" + cell);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto json = nlohmann::json::parse(sim.out);
  for (const auto& [name, s] : json["strategies"].items()) {
    std::string csv = "t,x,y,psi,v\n";
    for (const auto& p : s["trajectory"])
      csv += nlohmann::json(p["t"]).dump() + "," + nlohmann::json(p["x"]).dump() + "," + nlohmann::json(p["y"]).dump() +
             "," + nlohmann::json(p["psi"]).dump() + "," + nlohmann::json(p["v"]).dump() + "\n";
    const fs::path file = dir / (name + ".csv");
    write_text(file, csv);
    const auto r = run_emrm("assess " + quoted(file) + cell + " --json --strategy " + name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto a = nlohmann::json::parse(r.out);
    EXPECT_EQ(a["strategy"], name);
    EXPECT_EQ(a["outcome"]["avoided"], s["avoided"]) << name;
    EXPECT_EQ(a["outcome"]["loss_level"], s["loss_level"]) << name;
    EXPECT_NEAR(a["outcome"]["delta_v_kph"].get<double>(), s["delta_v_kph"].get<double>(), 0.1) << name;
    EXPECT_EQ(a["unmitigated"]["loss_level"], json["unmitigated"]["loss_level"]);
  }
}

TEST(AssessCli, BadInputNamesFileLineAndColumn) {
  const auto dir = scratch_dir("assess-bad");
  const std::string cell = kScene + " --speed-kph 50 --ttc-s 1";
  const auto bad = [&](const std::string& name, const std::string& text, const std::string& where,
                       const std::string& what) {
    write_text(dir / name, text);
    const auto r = run_emrm("assess " + quoted(dir / name) + cell);
    expect_bad_input(r, (dir / name).string() + ":" + where + ": error: ");
    EXPECT_THAT(r.err, HasSubstr(what)) << name;
  };
  bad("quote.csv", "t,x,y,psi,v\n0,0,0,0,\"10\n", "2:9", "quote");
  bad("truncated.csv", "t,x,y,psi,v\n0,0,-1.75,0,10\n0.01,0.1,-1.75", "3:10", "expected 5 fields");
  bad("time.csv", "t,x,y,psi,v\n0,0,-1.75,0,10\n0.01,0.1,-1.75,0,10\n0.01,0.2,-1.75,0,10\n", "4:1",
      "expected a time after");
  bad("nan.csv", "t,x,y,psi,v\n0,0,-1.75,0,10\n0.01,0.1,nan,0,10\n", "3:10", "expected a finite number for 'y'");
  bad("columns.csv", "t,x,y,heading,v\n0,0,-1.75,0,10\n0.01,0.1,-1.75,0,10\n", "1:1", "expected a column 'psi'");
  bad("empty.csv", "", "1:1", "empty");
  write_text(dir / "good.csv", "t,x,y,psi,v\n0,-2.12,-1.75,0,10\n0.01,-2.02,-1.75,0,10\n");
  expect_bad_input(run_emrm("assess " + quoted(dir / "good.csv") + cell + " --strategy nosuch"), "nosuch");
  expect_bad_input(run_emrm("assess " + quoted(dir / "good.csv") + kScene + " --speed-kph 90 --ttc-s 3"), "infeasible");
  expect_usage_error(run_emrm("assess " + quoted(dir / "good.csv") + cell + " --format carla"), "--format");
  expect_bad_input(run_emrm("assess " + quoted(dir / "nosuch.csv") + cell), "nosuch.csv");
  EXPECT_EQ(run_emrm("assess " + quoted(dir / "good.csv") + cell).exit_code, 0);
}

// Judged against the built-in car, a recording of the production car read Δv 57.9 instead of
// 49.6 km/h without a word: the scene must be named (a file, or a results folder's stored scene),
// and the output says which scene, actuation and cell it assumed.
TEST(AssessCli, TheSceneIsNamedNeverAssumed) {
  const auto dir = scratch_dir("assess-scene");
  write_text(dir / "good.csv", "t,x,y,psi,v\n0,-2.12,-1.75,0,10\n0.01,-2.02,-1.75,0,10\n");
  const std::string cell = " --speed-kph 50 --ttc-s 1";
  const auto unnamed = run_emrm("assess " + quoted(dir / "good.csv") + cell);
  expect_bad_input(unnamed, "--scene");
  EXPECT_THAT(unnamed.err, HasSubstr("name the scene the trajectory was driven in"));
  EXPECT_TRUE(unnamed.out.empty()) << unnamed.out;

  const auto text = run_emrm("assess " + quoted(dir / "good.csv") + kScene + cell + " --profile ideal");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("Scene: " + std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/scene.yaml"));
  EXPECT_THAT(text.out, HasSubstr("profile ideal"));
  EXPECT_THAT(text.out, HasSubstr("actuation: instant"));
  EXPECT_THAT(text.out, HasSubstr("Cell: 50 km/h, TTC 1 s"));
  const auto json = run_emrm("assess " + quoted(dir / "good.csv") + kScene + cell + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["scene"]["family"], "tjunction");
  EXPECT_TRUE(j["scene"]["profile"].is_null());
  EXPECT_GT(j["scene"]["actuation"]["perception_latency_s"].get<double>(), 0.0);  // the production car's

  // A results folder's stored scene, as its sweep simulated it.
  write_text(dir / "campaign.yaml", "scene: " + std::string(EMRM_SOURCE_DIR) +
                                        "/examples/tjunction/scene.yaml\nstrategies: [emergency_stop]\ngrids:\n"
                                        "  - name: one\n    speed_kph: 50\n    ttc_s: 1.5\n");
  ASSERT_EQ(run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "out")).exit_code, 0);
  const auto stored =
      run_emrm("assess " + quoted(dir / "good.csv") + " --scene " + quoted(dir / "out") + cell + " --json");
  ASSERT_EQ(stored.exit_code, 0) << stored.err;
  EXPECT_EQ(nlohmann::json::parse(stored.out)["scene"]["actuation"], j["scene"]["actuation"]);
  EXPECT_EQ(nlohmann::json::parse(stored.out)["outcome"], j["outcome"]);
  expect_bad_input(run_emrm("assess " + quoted(dir / "good.csv") + " --scene " + quoted(dir) + cell),
                   "no results folder");
}

}  // namespace exchange_cli_test
}  // namespace emrm::e2e
