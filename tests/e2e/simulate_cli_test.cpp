// End-to-end: `emrm simulate` as a user runs it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace simulate_cli_test {

using ::testing::HasSubstr;

TEST(SimulateCli, PrintsATableWithTheRegionAndEveryStrategy) {
  const auto r = run_emrm("simulate --speed-kph 50 --ttc-s 1.0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Region: G"));
  for (const char* s : {"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident", "emrm"})
    EXPECT_THAT(r.out, HasSubstr(s));
  EXPECT_THAT(r.out, HasSubstr("EMRM FSM trace: S1 hazard_detected S2"));
}

TEST(SimulateCli, JsonHasTheDocumentedShape) {
  const auto r = run_emrm("simulate --speed-kph 60 --ttc-s 0.6 --mu 0.8 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph"})
    EXPECT_TRUE(j["input"].contains(key));
  EXPECT_TRUE(j["feasible"].get<bool>());
  EXPECT_THAT(std::string("G Y O R"), HasSubstr(j["region"].get<std::string>()));
  for (const char* key : {"impact_speed_kph", "delta_v_kph", "p_mais3", "p_fatal", "loss_level"})
    EXPECT_TRUE(j["unmitigated"].contains(key)) << key;
  ASSERT_EQ(j["strategies"].size(), 6u);  // every registered strategy, the oracle included
  for (const auto& [name, s] : j["strategies"].items()) {
    for (const char* key : {"avoided", "impact_speed_kph", "delta_v_kph", "p_mais3", "p_fatal", "loss_level",
                            "delta_loss", "min_ttc_s", "fsm_trace", "planner"})
      EXPECT_TRUE(s.contains(key)) << name << " " << key;
    EXPECT_TRUE(s["planner"].contains("nodes"));
    if (s["avoided"].get<bool>()) {
      EXPECT_EQ(s["impact_speed_kph"].get<double>(), 0.0) << name;
      EXPECT_EQ(s["loss_level"].get<int>(), 0) << name;
    }
    EXPECT_EQ(s["delta_loss"].get<int>(), j["unmitigated"]["loss_level"].get<int>() - s["loss_level"].get<int>());
  }
}

TEST(SimulateCli, SameSeedGivesByteIdenticalJson) {
  const std::string args = "simulate --speed-kph 66 --ttc-s 0.7 --mu 0.9 --passage-m 2.5 --seed 5 --json --paths";
  const auto a = run_emrm(args);
  const auto b = run_emrm(args);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_GT(a.out.size(), 1000u);
}

TEST(SimulateCli, TimingIsOptInBecauseItVaries) {
  const auto r = run_emrm("simulate --speed-kph 66 --ttc-s 0.7 --json --timing");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["strategies"]["dodge"]["planner"].contains("time_ms"));
}

// The shipped scene is the built-in defaults with the production car's actuation; the ideal
// profile takes that back.
TEST(SimulateCli, ShippedSceneFileEqualsTheBuiltInDefaults) {
  const auto builtin = run_emrm("simulate --speed-kph 55 --ttc-s 0.8 --json");
  const auto shipped = run_emrm("simulate --scene " + quoted(example("scene.yaml")) +
                                " --profile ideal --speed-kph 55 --ttc-s 0.8 --json");
  ASSERT_EQ(shipped.exit_code, 0) << shipped.err;
  // The same simulation; only the "scene" key names what each was told (file, profile), and the
  // actuation in effect is the same.
  auto a = nlohmann::json::parse(builtin.out);
  auto b = nlohmann::json::parse(shipped.out);
  EXPECT_EQ(a["scene"]["actuation"], b["scene"]["actuation"]);
  EXPECT_TRUE(a["scene"]["file"].is_null());
  EXPECT_EQ(b["scene"]["profile"], "ideal");
  a.erase("scene");
  b.erase("scene");
  EXPECT_EQ(a, b);
}

TEST(SimulateCli, OneStrategyCanBeAskedFor) {
  const auto r = run_emrm("simulate --speed-kph 40 --ttc-s 0.5 --strategy emergency_stop --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["strategies"].size(), 1u);
  EXPECT_FALSE(j["strategies"]["emergency_stop"]["avoided"].get<bool>());
}

// Issue 40, 9: a straight stop short of the truck is finished in closed form; its JSON trajectory
// held three samples, and re-checking it by interpolation was off by metres at mid-stop. Every
// integration step is there now, each on the closed form x0 + v0 t - a t^2 / 2 at the deceleration
// the first step shows, ending where v0^2 / (2a) puts it.
TEST(SimulateCli, AStraightStopCarriesEveryIntegrationStep) {
  const auto r = run_emrm("simulate --speed-kph 40 --ttc-s 2 --mu 0.7 --strategy emergency_stop --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& path = j["strategies"]["emergency_stop"]["trajectory"];
  ASSERT_TRUE(j["strategies"]["emergency_stop"]["avoided"].get<bool>());
  const double dt = 0.01;
  const double x0 = path[0]["x"], v0 = path[0]["v"];
  const double a = (v0 - path[1]["v"].get<double>()) / dt;
  ASSERT_GT(a, 0.0);
  const double stop_s = v0 / a;
  EXPECT_GE(path.size(), static_cast<std::size_t>(stop_s / dt));
  for (std::size_t k = 1; k < path.size(); ++k) {
    const double t = path[k]["t"];
    EXPECT_LE(t - path[k - 1]["t"].get<double>(), dt + 1e-9) << "at sample " << k;
    const double tau = std::min(t, stop_s);
    EXPECT_NEAR(path[k]["x"].get<double>(), x0 + v0 * tau - 0.5 * a * tau * tau, 1e-6) << "at t = " << t;
    EXPECT_NEAR(path[k]["v"].get<double>(), v0 - a * tau, 1e-6) << "at t = " << t;
  }
  EXPECT_NEAR(path.back()["x"].get<double>() - x0, v0 * v0 / (2.0 * a), 1e-6);
}
TEST(SimulateCli, InfeasibleCellsAreReportedNotSimulated) {
  const auto r = run_emrm("simulate --speed-kph 72 --ttc-s 2.9 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["feasible"].get<bool>());
  EXPECT_EQ(j["region"], "infeasible");
}

TEST(SimulateCli, FiguresAreWrittenAsSvgAndPng) {
  const auto dir = scratch_dir("simulate-figure");
  const auto svg = dir / "cell.svg";
  const auto png = dir / "cell.png";
  ASSERT_EQ(run_emrm("simulate --speed-kph 60 --ttc-s 0.8 --figure " + quoted(svg)).exit_code, 0);
  ASSERT_EQ(run_emrm("simulate --speed-kph 60 --ttc-s 0.8 --figure " + quoted(png)).exit_code, 0);
  EXPECT_THAT(read_text(svg), HasSubstr("<svg"));
  const std::string header = read_text(png).substr(0, 8);
  EXPECT_EQ(header, std::string("\x89PNG\r\n\x1a\n", 8));
  expect_bad_input(run_emrm("simulate --speed-kph 60 --ttc-s 0.8 --figure " + quoted(dir / "cell.gif")),
                   ".png or .svg");
}

TEST(SimulateCli, BadCellsExitTwoWithOneMessage) {
  expect_bad_input(run_emrm("simulate --speed-kph -5 --ttc-s 1"), "speed");
  expect_bad_input(run_emrm("simulate --speed-kph nan --ttc-s 1"), "speed");
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1 --mu 0"), "mu");
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1 --mu 2.5"), "mu");
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1 --passage-m 12"), "passage");
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1 --strategy teleport"), "unknown strategy 'teleport'");
  EXPECT_EQ(run_emrm("simulate --ttc-s 1").exit_code, 2);
  // The slip named, and "error:" as every other message has it (a file's errors after its place).
  const auto percent = run_emrm("simulate --speed-kph 50 --ttc-s 1 --mu 50");
  expect_bad_input(percent, "error: mu must be a finite friction coefficient with 0 < mu <= 2, got 50; a percentage?");
  EXPECT_EQ(percent.err.rfind("error: ", 0), 0u) << percent.err;
}

// A 2 kg car (the mass in tonnes) was accepted: every vehicle parameter has the range of road
// vehicles, and a value outside it names the unit slip behind it.
TEST(SimulateCli, AnImplausibleVehicleNamesTheUnitSlip) {
  const auto dir = scratch_dir("simulate-vehicle");
  const auto refused = [&](const std::string& field, const std::string& value, const std::string& words) {
    write_text(dir / "scene.yaml", "ego:\n  " + field + ": " + value + "\n");
    const auto r = run_emrm("simulate --scene " + quoted(dir / "scene.yaml") + " --speed-kph 50 --ttc-s 1");
    expect_bad_input(r, (dir / "scene.yaml").string() + ":2:");
    EXPECT_THAT(r.err, HasSubstr(words)) << field;
  };
  refused("mass_kg", "2", "ego.mass_kg: expected a mass in [50, 60000] kg for a road vehicle, got 2 (in tonnes?)");
  refused("length_m", "4508", "(in millimetres?)");
  refused("front_cornering_stiffness_n_per_rad", "70", "(in kN/rad?)");
  refused("max_steer_rate_radps", "45", "(in degrees per second?)");
  refused("width_m", "0", "expected a width in [0.4, 3] m for a road vehicle, got 0");
  write_text(dir / "scene.yaml", "ego:\n  mass_kg: 2000\n");  // a large car is one
  EXPECT_EQ(run_emrm("simulate --scene " + quoted(dir / "scene.yaml") + " --speed-kph 50 --ttc-s 1").exit_code, 0);
}

TEST(SimulateCli, MalformedSceneFileExitsTwoNamingLineAndColumn) {
  const auto dir = scratch_dir("simulate-scene");
  write_text(dir / "scene.yaml", "truck:\n  mass_kg: heavy\n");
  const auto r = run_emrm("simulate --scene " + quoted(dir / "scene.yaml") + " --speed-kph 50 --ttc-s 1");
  expect_bad_input(r, "scene.yaml:2:");
  write_text(dir / "scene2.yaml", "road: [1, 2\n");
  expect_bad_input(run_emrm("simulate --scene " + quoted(dir / "scene2.yaml") + " --speed-kph 50 --ttc-s 1"),
                   "malformed YAML");
}

}  // namespace simulate_cli_test
}  // namespace emrm::e2e

namespace emrm::e2e {
namespace simulate_cli_test {

// Profiles (docs/actuation.md): a NAME from the scene's profiles/ folder, or a FILE.
TEST(SimulateCli, ProductionProfileMovesTheStopBoundary) {
  // 50 km/h on a dry road: instant braking stops within TTC 0.71 s; the production profile's
  // latency, dead time and ramp add about 0.48 s, so at TTC 1.0 s the stop no longer avoids.
  const std::string cell = " --speed-kph 50 --ttc-s 1.0 --strategy emergency_stop --json";
  const auto ideal = run_emrm("simulate --scene " + quoted(example("scene.yaml")) + " --profile ideal" + cell);
  const auto production =
      run_emrm("simulate --scene " + quoted(example("scene.yaml")) + " --profile production" + cell);
  const auto file = run_emrm("simulate --profile " + quoted(example("profiles/production.yaml")) + cell);
  ASSERT_EQ(ideal.exit_code, 0) << ideal.err;
  ASSERT_EQ(production.exit_code, 0) << production.err;
  ASSERT_EQ(file.exit_code, 0) << file.err;
  EXPECT_TRUE(nlohmann::json::parse(ideal.out)["strategies"]["emergency_stop"]["avoided"].get<bool>());
  EXPECT_FALSE(nlohmann::json::parse(production.out)["strategies"]["emergency_stop"]["avoided"].get<bool>());
  // Apart from the "scene" key, which names what each was told, the same simulation.
  const auto without_scene = [](const std::string& out) {
    auto j = nlohmann::json::parse(out);
    j.erase("scene");
    return j;
  };
  EXPECT_EQ(without_scene(production.out), without_scene(file.out));
  EXPECT_EQ(nlohmann::json::parse(production.out)["scene"]["profile"], "production");
  // The shipped scene is the production car: the profile changes nothing in it.
  const auto shipped = run_emrm("simulate --scene " + quoted(example("scene.yaml")) + cell);
  ASSERT_EQ(shipped.exit_code, 0) << shipped.err;
  EXPECT_EQ(without_scene(shipped.out), without_scene(production.out));
  EXPECT_EQ(nlohmann::json::parse(shipped.out)["scene"]["actuation"],
            nlohmann::json::parse(production.out)["scene"]["actuation"]);
  // And the text says which actuation it used, and the stop boundary through it, the closed form of
  // full braking after the latency and dead time along a linear ramp t_r (v > a·t_r/2):
  // TTC = L + t_d + v/(2a) + t_r/2 − a·t_r²/(24 v), a = μg; 0.708 s would be v/(2μg) alone.
  const auto text = run_emrm("simulate --scene " + quoted(example("scene.yaml")) +
                             " --speed-kph 50 --ttc-s 1.0 --strategy emergency_stop");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("actuation: perception latency 0.25 s"));
  const nlohmann::json act = nlohmann::json::parse(shipped.out)["scene"]["actuation"];
  const double wait_s = act["perception_latency_s"].get<double>() + act["brake_dead_time_s"].get<double>();
  const double ramp_s = act["brake_ramp_s"].get<double>();
  ASSERT_GT(wait_s, 0.0);
  const double v = 50.0 / 3.6, a = 9.81;
  const double expected_s = wait_s + v / (2.0 * a) + ramp_s / 2.0 - a * ramp_s * ramp_s / (24.0 * v);
  const std::string said = "braking alone needs TTC >= ";
  const auto at = text.out.find(said);
  ASSERT_NE(at, std::string::npos) << text.out;
  EXPECT_NEAR(std::stod(text.out.substr(at + said.size())), expected_s, 0.0006) << text.out;  // printed to 1 ms
  EXPECT_THAT(text.out, HasSubstr("stopping through the actuation"));
}

TEST(SimulateCli, BadProfilesAreBadInput) {
  const std::string scene = " --scene " + quoted(example("scene.yaml")) + " --speed-kph 50 --ttc-s 1.0";
  const auto unknown = run_emrm("simulate" + scene + " --profile racing");
  expect_bad_input(unknown, "no profile 'racing'");
  EXPECT_THAT(unknown.err, HasSubstr("production"));  // the known names are listed
  expect_bad_input(run_emrm("simulate" + scene + " --profile /nonexistent/p.yaml"), "does not exist");

  const std::string dir = ::testing::TempDir() + "/emrm-profile-test";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const auto negative = run_emrm("simulate --speed-kph 50 --ttc-s 1.0 --profile " +
                                 quoted(write("negative.yaml", "actuation:\n  brake_ramp_s: -0.2\n")));
  expect_bad_input(negative, "negative.yaml:2:17");
  EXPECT_THAT(negative.err, HasSubstr("expected a value >= 0"));
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1.0 --profile " +
                            quoted(write("typo.yaml", "actuation:\n  brake_lag_s: 0.2\n"))),
                   "unknown field 'brake_lag_s'");
  expect_bad_input(run_emrm("simulate --speed-kph 50 --ttc-s 1.0 --profile " +
                            quoted(write("empty.yaml", "description: nothing\n"))),
                   "actuation");
}

}  // namespace simulate_cli_test
}  // namespace emrm::e2e

namespace emrm::e2e {
namespace simulate_cli_test {

// Messages a new user met (issue "your own case"): a misspelt option or key names the one meant,
// an infeasible cell says why with its units.
TEST(SimulateCli, MisspellingsNameWhatWasMeant) {
  const auto option = run_emrm("simulate --speed 50 --ttc-s 1");
  EXPECT_EQ(option.exit_code, 2);
  EXPECT_THAT(option.err, HasSubstr("unknown option '--speed' (did you mean '--speed-kph'?)"));
  const std::string dir = ::testing::TempDir() + "/emrm-misspelt";
  std::filesystem::create_directories(dir);
  std::string scene = read_text(example("scene.yaml"));
  scene.replace(scene.find("\nseverity:"), 10, "\nseverty:");
  std::ofstream(dir + "/scene.yaml") << scene;
  const auto key = run_emrm("simulate --scene " + quoted(dir + "/scene.yaml") + " --speed-kph 50 --ttc-s 1");
  EXPECT_EQ(key.exit_code, 2);
  EXPECT_THAT(key.err, HasSubstr("unknown field 'severty' (did you mean 'severity'?)"));
  const auto far = run_emrm("simulate --speed-kph 50 --ttc-s 800");
  EXPECT_EQ(far.exit_code, 0);
  EXPECT_THAT(
      far.out,
      HasSubstr("the truck would appear 11111.11 m ahead (v·TTC), beyond the scene's max_initial_distance_m = 24.5 m"));
  EXPECT_THAT(far.out, HasSubstr("TTC in seconds"));
}

}  // namespace simulate_cli_test
}  // namespace emrm::e2e
