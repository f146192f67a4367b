// Vehicle models are an extension point: a model registered from outside the library (here a toy
// one, the kinematic bicycle that counts its derivative calls) is picked by name from a scene, runs
// every rollout of simulate_cell and of `emrm simulate`, and says that no certificate backs it
// instead of leaving O and R cells undecided without a word; it disappears when its registration ends.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli.hpp"
#include "emrm/core/error.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm {
namespace toy_vehicle_model_test {

using ::testing::HasSubstr;

std::atomic<long> derivative_calls{0};

class CountingBicycle final : public sim::VehicleModel {
 public:
  explicit CountingBicycle(const sim::VehicleParams& p) : VehicleModel(p), inner_(p) {}
  [[nodiscard]] std::string_view name() const override { return "toy_bicycle"; }
  [[nodiscard]] sim::VehicleState derivative(const sim::VehicleState& s, const sim::Control& u,
                                             double mu) const override {
    derivative_calls.fetch_add(1, std::memory_order_relaxed);
    return inner_.derivative(s, u, mu);
  }
  [[nodiscard]] sim::TireForces tire_forces(const sim::VehicleState& s, const sim::Control& u,
                                            double mu) const override {
    return inner_.tire_forces(s, u, mu);
  }

 private:
  sim::KinematicBicycle inner_;
};

sim::VehicleModelInfo toy_info() {
  return {.name = "toy_bicycle",
          .description = "a kinematic bicycle that counts its calls",
          .make = [](const sim::VehicleParams& p) -> std::unique_ptr<sim::VehicleModel> {
            return std::make_unique<CountingBicycle>(p);
          },
          .certificate_bound = false};
}

sim::SceneConfig toy_scene() {
  sim::SceneConfig config;
  config.simulation.vehicle_model = "toy_bicycle";
  config.planner.max_nodes = 200;
  return config;
}

TEST(ToyVehicleModel, IsKnownByNameOnlyWhileRegistered) {
  {
    const sim::VehicleModelRegistration registration(toy_info());
    EXPECT_THAT(sim::vehicle_model_names(), ::testing::Contains("toy_bicycle"));
    EXPECT_NO_THROW(sim::validate(toy_scene()));
    ASSERT_TRUE(sim::find_vehicle_model("toy_bicycle").has_value());
    EXPECT_FALSE(sim::find_vehicle_model("toy_bicycle")->certificate_bound);
    EXPECT_THROW(sim::VehicleModelRegistration again(toy_info()), UsageError);
  }
  EXPECT_THAT(sim::vehicle_model_names(), ::testing::Not(::testing::Contains("toy_bicycle")));
  EXPECT_FALSE(sim::find_vehicle_model("toy_bicycle").has_value());
  try {
    sim::validate(toy_scene());
    FAIL() << "a scene naming an unregistered model validated";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("vehicle_model"));
    EXPECT_THAT(e.what(), HasSubstr("single_track_fiala"));
  }
}

TEST(ToyVehicleModel, RunsTheRolloutsAndSaysNoCertificateBacksIt) {
  const sim::VehicleModelRegistration registration(toy_info());
  // A cell nothing avoids, even without a friction limit on cornering: at 70 km/h the truck is
  // 1.9 m ahead.
  const sim::CellInput unavoidable{70.0, 0.1, 0.8, 3.0, 0.0};
  const long before = derivative_calls.load();
  const sim::CellResult r = sim::simulate_cell(toy_scene(), unavoidable, sim::CellOptions{});
  EXPECT_GT(derivative_calls.load(), before);
  ASSERT_TRUE(r.feasible);
  EXPECT_TRUE(r.region == sim::Region::kO || r.region == sim::Region::kR) << sim::region_name(r.region);
  EXPECT_FALSE(r.certificate.has_value());
  EXPECT_EQ(r.evidence, sim::Evidence::kUndecided);
  EXPECT_THAT(r.no_certificate, HasSubstr("toy_bicycle"));
  EXPECT_THAT(sim::to_json(r, sim::Scene(toy_scene(), unavoidable), 1).dump(), HasSubstr("no_certificate"));

  // The shipped model certifies the same cell, and says nothing of a missing bound.
  sim::SceneConfig shipped = toy_scene();
  shipped.simulation.vehicle_model = "single_track_fiala";
  const sim::CellResult s = sim::simulate_cell(shipped, unavoidable, sim::CellOptions{});
  EXPECT_TRUE(s.certificate.has_value());
  EXPECT_TRUE(s.no_certificate.empty());
}

TEST(ToyVehicleModel, IsUsedByEmrmSimulate) {
  const sim::VehicleModelRegistration registration(toy_info());
  const auto dir = std::filesystem::temp_directory_path() / "emrm_toy_vehicle_model";
  std::filesystem::create_directories(dir);
  const auto scene = dir / "scene.yaml";
  std::ofstream(scene) << "simulation:\n  vehicle_model: toy_bicycle\nplanner:\n  max_nodes: 200\n";
  const long before = derivative_calls.load();
  std::vector<std::string> args{"emrm", "simulate", "--scene", scene.string(), "--speed-kph", "70", "--ttc-s", "0.1"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  const int code = cli::run_cli(static_cast<int>(argv.size()), argv.data());
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(code, 0) << out;
  EXPECT_GT(derivative_calls.load(), before);
  EXPECT_THAT(out, HasSubstr("vehicle model 'toy_bicycle' has no certificate bound"));
}

}  // namespace toy_vehicle_model_test
}  // namespace emrm
