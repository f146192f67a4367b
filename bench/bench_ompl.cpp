// emrm_ompl_bench: emrm's kinodynamic RRT ("rrt") against OMPL's control planners (RRT, SST,
// KPIECE1) on the same cells, with emrm's own vehicle model, validity checks and goal
// (docs/benchmarks.md, "The planner against OMPL"). Prints a Markdown table of success rate and
// time to the first avoidance per planner and cell set, and writes one CSV row per cell and planner.
//
//   emrm_ompl_bench [--csv PATH] [--time-limit S] [--y-cells N] [--random-cells N]
//                   [--limits drift_to_avoid|dodge]
//
// The formulation, and why each choice was made, is in the comments below and in the doc.

#include <fmt/format.h>
#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/config.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "emrm/sim/planner.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"

namespace {

namespace ob = ompl::base;
namespace oc = ompl::control;
using namespace emrm::sim;

// ---------------------------------------------------------------------------------------------
// The OMPL formulation.

// What a propagated state is, as emrm's Roller decided it: still open, an avoidance (the goal), or
// ended otherwise (contact, road departure, the strategy's constraint, the horizon, a failed
// recovery). The verdict travels with the state because emrm's checks are continuous: contact and
// departure are found between integration steps, which a check of the end state alone would miss.
enum class Verdict : unsigned char { kOpen, kAvoided, kFailed };

// The state: emrm's VehicleState (x, y, yaw, vx, vy, yaw rate, wheel angle) and the time, since the
// truck moves; the actuators are instant (the bench's scene), so nothing else carries over.
constexpr unsigned kX = 0, kY = 1, kYaw = 2, kVx = 3, kVy = 4, kYawRate = 5, kSteer = 6, kTime = 7, kDims = 8;

class EgoSpace final : public ob::RealVectorStateSpace {
 public:
  class StateType final : public ob::RealVectorStateSpace::StateType {
   public:
    Verdict verdict = Verdict::kOpen;
  };

  EgoSpace() : ob::RealVectorStateSpace(kDims) { setName("emrm_ego"); }

  ob::State* allocState() const override {
    auto* s = new StateType;
    s->values = new double[dimension_];
    return s;
  }
  void freeState(ob::State* state) const override {
    auto* s = static_cast<StateType*>(state);
    delete[] s->values;
    delete s;
  }
  void copyState(ob::State* to, const ob::State* from) const override {
    ob::RealVectorStateSpace::copyState(to, from);
    static_cast<StateType*>(to)->verdict = static_cast<const StateType*>(from)->verdict;
  }
  // KPIECE1's grid: the plane, in cells of 1 m along the road and 0.5 m across it (the passage is
  // 1-3 m wide, the ego 1.6 m).
  void registerProjections() override;
};

class PlaneProjection final : public ob::ProjectionEvaluator {
 public:
  explicit PlaneProjection(const ob::StateSpace* space) : ob::ProjectionEvaluator(space) {}
  unsigned int getDimension() const override { return 2; }
  void defaultCellSizes() override { cellSizes_ = {1.0, 0.5}; }
  void project(const ob::State* state, Eigen::Ref<Eigen::VectorXd> projection) const override {
    const double* v = state->as<EgoSpace::StateType>()->values;
    projection[0] = v[kX];
    projection[1] = v[kY];
  }
};

void EgoSpace::registerProjections() { registerDefaultProjection(std::make_shared<PlaneProjection>(this)); }

VehicleState vehicle_of(const double* v) { return {v[kX], v[kY], v[kYaw], v[kVx], v[kVy], v[kYawRate], v[kSteer]}; }

void write_state(const VehicleState& s, double t_s, Verdict verdict, ob::State* to) {
  auto* e = to->as<EgoSpace::StateType>();
  double* v = e->values;
  v[kX] = s.x_m, v[kY] = s.y_m, v[kYaw] = s.yaw_rad, v[kVx] = s.vx_mps, v[kVy] = s.vy_mps;
  v[kYawRate] = s.yaw_rate_radps, v[kSteer] = s.steer_rad, v[kTime] = t_s;
  e->verdict = verdict;
}

// The control: emrm's Control. The brake is sampled on [-0.5, 1.5] and clamped, so that no braking
// and full braking (the ABS at the friction limit, which emrm's closed-form stop needs) each have a
// quarter of the mass rather than none; the rear lock is on above 0.75 (a quarter of the samples,
// emrm's share), and ignored under limits that forbid it.
Control control_of(const oc::Control* c) {
  const double* u = c->as<oc::RealVectorControlSpace::ControlType>()->values;
  return {u[0], std::clamp(u[1], 0.0, 1.0), u[2] > 0.75};
}

// Propagation: emrm's Roller driving one held segment of `duration` from the state, with the
// strategy's limits and emrm's built-in validity checks and termination tests. Passing the truck
// hands the car to emrm's recovery controller inside the same call, so a state that passed is
// already judged: an avoidance (stable with room to stop) or not. A state that is no longer open
// stays as it is.
class RollerPropagator final : public oc::StatePropagator {
 public:
  RollerPropagator(oc::SpaceInformation* si, const Roller& roller) : oc::StatePropagator(si), roller_(roller) {}
  void propagate(const ob::State* from, const oc::Control* control, double duration, ob::State* to) const override {
    const auto* s = from->as<EgoSpace::StateType>();
    if (s->verdict != Verdict::kOpen) {
      si_->copyState(to, from);
      return;
    }
    ++calls_;
    const std::vector<ControlSegment> plan{hold(control_of(control), duration)};
    const RolloutResult r = roller_.roll(vehicle_of(s->values), s->values[kTime], plan, std::nullopt, 1 << 30);
    const Verdict verdict = r.termination == Termination::kOpen ? Verdict::kOpen
                            : r.avoided()                       ? Verdict::kAvoided
                                                                : Verdict::kFailed;
    write_state(r.end_state, r.end_time_s, verdict, to);
  }
  [[nodiscard]] long calls() const noexcept { return calls_; }

 private:
  const Roller& roller_;
  mutable long calls_ = 0;
};

// Validity: the verdict emrm's ValidityChecker (and the recovery) gave the state when it was
// propagated; the start state is valid (a feasible cell).
class VerdictChecker final : public ob::StateValidityChecker {
 public:
  explicit VerdictChecker(ob::SpaceInformation* si) : ob::StateValidityChecker(si) {}
  bool isValid(const ob::State* state) const override {
    return state->as<EgoSpace::StateType>()->verdict != Verdict::kFailed;
  }
};

// Where emrm's RRT aims its goal-biased samples (src/sim/rrt.cpp): the free bands beside the truck,
// from a car length before where it stands when the car would reach it to two car lengths beyond
// where the car has passed it.
struct Passage {
  double near_x_m = 0.0, far_x_m = 0.0;
  std::vector<std::pair<double, double>> bands;  // y ranges of the ego's CG
  explicit Passage(const Scene& scene) {
    const auto& ego = scene.config().ego;
    near_x_m = scene.initial_distance_m() + (scene.passed_x_m(scene.ttc_s()) - scene.passed_x_m()) - ego.length_m;
    far_x_m = scene.passed_x_m(scene.ttc_s()) + 2.0 * ego.length_m;
    const FreeBands free = scene.free_bands(scene.config().simulation.horizon_s);
    for (std::size_t i = 0; i < free.count; ++i) {
      const double lo = free.band[i].low_m + ego.width_m / 2.0;
      bands.emplace_back(lo, std::max(lo, free.band[i].high_m - ego.width_m / 2.0));
    }
  }
};

// The goal is emrm's avoidance: a state the Roller judged avoided (stopped short of the truck, or
// passed it and stable with room to stop after the recovery). Its distance, for the planners'
// approximate solutions, is the distance in the plane to the passage; its samples (goal bias) lie
// in the passage, as emrm's RRT's do, with the heading straight and the speed and time at random.
class AvoidanceGoal final : public ob::GoalSampleableRegion {
 public:
  AvoidanceGoal(const ob::SpaceInformationPtr& si, const Scene& scene) : ob::GoalSampleableRegion(si), scene_(scene) {
    setThreshold(0.0);
  }
  bool isSatisfied(const ob::State* st) const override {
    return st->as<EgoSpace::StateType>()->verdict == Verdict::kAvoided;
  }
  bool isSatisfied(const ob::State* st, double* distance) const override {
    if (distance != nullptr) *distance = distanceGoal(st);
    return isSatisfied(st);
  }
  double distanceGoal(const ob::State* st) const override {
    const auto* s = st->as<EgoSpace::StateType>();
    if (s->verdict == Verdict::kAvoided) return 0.0;
    const double x = s->values[kX], y = s->values[kY];
    const double dx = std::max({passage_.near_x_m - x, x - passage_.far_x_m, 0.0});
    double dy = passage_.bands.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    for (const auto& [lo, hi] : passage_.bands) dy = std::min(dy, std::max({lo - y, y - hi, 0.0}));
    return std::hypot(dx, dy);
  }
  void sampleGoal(ob::State* st) const override {
    const Road& road = scene_.road();
    double y = rng_.uniformReal(road.min_y_m, road.max_y_m);
    if (!passage_.bands.empty()) {
      const auto& [lo, hi] = passage_.bands[passage_.bands.size() == 1 ? 0 : rng_.uniformInt(0, 1)];
      y = rng_.uniformReal(lo, hi);
    }
    VehicleState s;
    s.x_m = rng_.uniformReal(passage_.near_x_m, passage_.far_x_m);
    s.y_m = y;
    s.vx_mps = rng_.uniformReal(0.0, scene_.initial_speed_mps());
    write_state(s, rng_.uniformReal(0.0, scene_.config().simulation.horizon_s), Verdict::kOpen, st);
  }
  unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned int>::max(); }

 private:
  const Scene& scene_;
  Passage passage_{scene_};
  mutable ompl::RNG rng_;
};

// ---------------------------------------------------------------------------------------------
// One planner on one cell.

struct Run {
  bool success = false;   // an avoidance within the time limit
  bool verified = false;  // its controls, replayed from t = 0 by emrm::sim::replay, avoid too
  double ms = 0.0;        // wall time of the search (to the first avoidance when it succeeds)
  long work = 0;          // emrm: rollouts; OMPL: propagation calls (5 integration steps each)
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// emrm's planner as shipped (its budget of planner.max_nodes extension attempts, 2 000, and the wall
// clock), then with the wall clock alone, the budget OMPL's planners have; then OMPL's.
constexpr const char* kPlanners[] = {"emrm rrt", "emrm rrt (wall clock only)", "OMPL RRT", "OMPL SST", "OMPL KPIECE1"};
constexpr int kOmplRrt = 2, kOmplSst = 3;
constexpr double kPropagationStep_s = 0.05;

Run run_emrm(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, std::uint64_t seed) {
  Run run;
  const auto started = std::chrono::steady_clock::now();
  const PlanResult r = find_planner("rrt")->plan({scene, model, limits, seed, false});
  run.ms = elapsed_ms(started);
  run.work = r.stats.rollouts;
  run.success = r.avoidance.has_value();
  run.verified = run.success && replay(scene, model, limits, r.avoidance->maneuver).avoided();
  return run;
}

template <std::size_t N>
ob::RealVectorBounds bounds_of(const std::pair<double, double> (&ranges)[N]) {
  ob::RealVectorBounds bounds(N);
  for (std::size_t i = 0; i < N; ++i) {
    bounds.setLow(static_cast<unsigned>(i), ranges[i].first);
    bounds.setHigh(static_cast<unsigned>(i), ranges[i].second);
  }
  return bounds;
}

Run run_ompl(int which, const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
             double time_limit_s) {
  const SceneConfig& config = scene.config();
  const VehicleState start = scene.ego_initial();
  const Passage passage(scene);
  auto space = std::make_shared<EgoSpace>();
  // Where the uniform samples fall: the drivable area from the start to past the passage, headings
  // within ±90°, every speed from rest to the start's, and the search's horizon.
  const std::pair<double, double> ranges[kDims] = {{start.x_m - 1.0, passage.far_x_m + 2.0},
                                                   {scene.road().min_y_m, scene.road().max_y_m},
                                                   {-std::numbers::pi / 2.0, std::numbers::pi / 2.0},
                                                   {0.0, start.vx_mps + 0.5},
                                                   {-3.0, 3.0},
                                                   {-2.0, 2.0},
                                                   {-config.ego.max_steer_rad, config.ego.max_steer_rad},
                                                   {0.0, config.simulation.horizon_s}};
  space->setBounds(bounds_of(ranges));
  // Steering rate, brake and rear lock, as control_of reads them.
  const std::pair<double, double> control_ranges[] = {
      {-config.ego.max_steer_rate_radps, config.ego.max_steer_rate_radps}, {-0.5, 1.5}, {0.0, 1.0}};
  auto controls = std::make_shared<oc::RealVectorControlSpace>(space, 3);
  controls->setBounds(bounds_of(control_ranges));

  const Roller roller(scene, model, limits);
  auto si = std::make_shared<oc::SpaceInformation>(space, controls);
  auto propagator = std::make_shared<RollerPropagator>(si.get(), roller);
  si->setStatePropagator(propagator);
  si->setStateValidityChecker(std::make_shared<VerdictChecker>(si.get()));
  // Controls are held for emrm's own range of durations (planner.min/max_duration_s: 0.1-0.4 s).
  si->setPropagationStepSize(kPropagationStep_s);
  si->setMinMaxControlDuration(static_cast<unsigned>(std::lround(config.planner.min_duration_s / kPropagationStep_s)),
                               static_cast<unsigned>(std::lround(config.planner.max_duration_s / kPropagationStep_s)));
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<EgoSpace> start_state(space);
  write_state(start, 0.0, Verdict::kOpen, start_state.get());
  pdef->addStartState(start_state);
  pdef->setGoal(std::make_shared<AvoidanceGoal>(si, scene));
  // SST goes on improving its solution until the time runs out: any cost satisfies this objective,
  // so it stops at its first avoidance like the others.
  auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
  objective->setCostThreshold(ob::Cost(std::numeric_limits<double>::infinity()));
  pdef->setOptimizationObjective(objective);

  ob::PlannerPtr planner;
  const double goal_bias = config.planner.goal_bias;  // emrm's share of samples in the passage
  if (which == kOmplRrt) {
    auto rrt = std::make_shared<oc::RRT>(si);
    rrt->setGoalBias(goal_bias);
    planner = rrt;
  } else if (which == kOmplSst) {
    auto sst = std::make_shared<oc::SST>(si);
    sst->setGoalBias(goal_bias);
    // The defaults (0.2, 0.1) are for unit-scaled spaces; here one control moves the state by
    // metres and m/s, and radii that small would make SST plain RRT.
    sst->setSelectionRadius(1.0);
    sst->setPruningRadius(0.5);
    planner = sst;
  } else {
    planner = std::make_shared<oc::KPIECE1>(si);
  }
  planner->setProblemDefinition(pdef);

  Run run;
  const auto started = std::chrono::steady_clock::now();
  planner->setup();
  const ob::PlannerStatus status = planner->solve(ob::timedPlannerTerminationCondition(time_limit_s));
  run.ms = elapsed_ms(started);
  run.work = propagator->calls();
  run.success = status == ob::PlannerStatus::EXACT_SOLUTION;
  if (run.success) {
    auto& path = *pdef->getSolutionPath()->as<oc::PathControl>();
    Maneuver maneuver;
    for (std::size_t i = 0; i < path.getControlCount(); ++i)
      maneuver.plan.push_back(hold(control_of(path.getControls()[i]), path.getControlDurations()[i]));
    run.verified = replay(scene, model, limits, maneuver).avoided();
  }
  return run;
}

// ---------------------------------------------------------------------------------------------
// The cells.

struct Cell {
  CellInput input;
  std::string set;    // "Y band" or "random"
  std::string group;  // random cells: "braking avoids" or "evasive only"
};

// Every feasible cell of the fine grid (examples/tjunction/campaign.yaml) whose region, simulated by
// emrm with every strategy (its strengthened search included), is Y; then `count` of them spread
// evenly over the band in grid order.
std::vector<Cell> y_band(const SceneConfig& config, std::size_t count) {
  std::vector<CellInput> band;
  for (int speed = 30; speed <= 72; ++speed)
    for (int k = 0; k < 46; ++k) {
      const CellInput cell{double(speed), 0.25 + 0.06 * k, 1.0, 3.0, config.truck.speed_kph};
      if (!Scene(config, cell).feasible()) continue;
      if (simulate_cell(config, cell, {}).region == Region::kY) band.push_back(cell);
    }
  std::fprintf(stderr, "fine grid: %zu Y cells\n", band.size());
  std::vector<Cell> cells;
  count = std::min(count, band.size());
  for (std::size_t i = 0; i < count; ++i) cells.push_back({band[i * band.size() / count], "Y band", ""});
  return cells;
}

bool braking_avoids(const SceneConfig& config, const CellInput& cell) {
  const Scene scene(config, cell);
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  return Roller(scene, *model, {}).roll(scene.ego_initial(), 0.0, {}, Tail::full_stop(), 1).avoided();
}

// `count` feasible cells drawn uniformly over speed 30-72 km/h, TTC 0.25-2.95 s, mu 0.1-1 and
// passage 1-3 m (the scene's truck speed), from a fixed seed, rounded so that the CSV names them
// exactly. The doubles come from the generator's bits, not from std::uniform_real_distribution,
// whose output the standard leaves to the library.
std::vector<Cell> random_cells(const SceneConfig& config, std::size_t count) {
  std::mt19937_64 rng(2041);
  const auto draw = [&](double lo, double hi, double step) {
    const double u = static_cast<double>(rng() >> 11) * 0x1p-53;
    return std::round((lo + u * (hi - lo)) / step) * step;
  };
  std::vector<Cell> cells;
  while (cells.size() < count) {
    const double speed = draw(30.0, 72.0, 0.1), ttc = draw(0.25, 2.95, 0.01);
    const double mu = draw(0.1, 1.0, 0.01), passage = draw(1.0, 3.0, 0.01);
    const CellInput cell{speed, ttc, mu, passage, config.truck.speed_kph};
    if (!Scene(config, cell).feasible()) continue;
    cells.push_back({cell, "random", braking_avoids(config, cell) ? "braking avoids" : "evasive only"});
  }
  return cells;
}

// ---------------------------------------------------------------------------------------------
// The table.

double quantile(std::vector<double> v, double q) {  // nearest rank; NaN when empty
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string ms_text(double ms) {
  if (std::isnan(ms)) return "–";
  return ms < 10.0 ? fmt::format("{:.2f}", ms) : fmt::format("{:.0f}", ms);
}

// One row per planner for the cells `in` selects: successes, the median and p90 time over them,
// the median against emrm's, the median of the per-cell ratio over the cells both solved, and the
// cells it solved that emrm's did not.
void print_rows(const std::string& label, const std::vector<Cell>& cells, const std::vector<std::vector<Run>>& runs,
                const std::function<bool(const Cell&)>& in) {
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (in(cells[i])) chosen.push_back(i);
  if (chosen.empty()) return;
  double emrm_median = 0.0;
  for (std::size_t p = 0; p < std::size(kPlanners); ++p) {
    std::vector<double> times, paired;
    int successes = 0, verified = 0, beyond_emrm = 0;
    for (const std::size_t i : chosen) {
      const Run& r = runs[i][p];
      const Run& e = runs[i][0];
      if (!r.success) continue;
      ++successes;
      verified += r.verified ? 1 : 0;
      times.push_back(r.ms);
      if (e.success) paired.push_back(r.ms / e.ms);
      if (!e.success) ++beyond_emrm;
    }
    const double m = median(times);
    if (p == 0) emrm_median = m;
    const bool emrm = p == 0;
    fmt::print("| {} | {} | {} | {}/{} ({:.0f} %) | {} | {} | {} | {} | {} |\n", label, kPlanners[p], chosen.size(),
               successes, chosen.size(), 100.0 * successes / static_cast<double>(chosen.size()), ms_text(m),
               ms_text(quantile(times, 0.9)),
               emrm || times.empty() || !(emrm_median > 0.0) ? "–" : fmt::format("{:.1f}×", m / emrm_median),
               emrm || paired.empty() ? "–" : fmt::format("{:.1f}× ({})", median(paired), paired.size()),
               emrm ? fmt::format("{} verified", verified) : fmt::format("{}; {} verified", beyond_emrm, verified));
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Before anything else creates an OMPL generator: every planner's seed follows from this one.
  ompl::RNG::setSeed(41);
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);

  std::string csv_path = "ompl_bench.csv";
  double time_limit_s = 1.0;
  std::size_t y_count = 60, random_count = 200;
  std::string strategy = "drift_to_avoid";
  for (int i = 1; i < argc; i += 2) {
    const std::string key = argv[i];
    if (i + 1 == argc) {
      std::fprintf(stderr,
                   "usage: %s [--csv PATH] [--time-limit S] [--y-cells N] [--random-cells N] "
                   "[--limits drift_to_avoid|dodge]\n",
                   argv[0]);
      return 2;
    }
    const std::string value = argv[i + 1];
    if (key == "--csv")
      csv_path = value;
    else if (key == "--time-limit")
      time_limit_s = std::stod(value);
    else if (key == "--y-cells")
      y_count = std::stoul(value);
    else if (key == "--random-cells")
      random_count = std::stoul(value);
    else if (key == "--limits" && (value == "drift_to_avoid" || value == "dodge"))
      strategy = value;
    else {
      std::fprintf(stderr, "unknown option or value: %s %s\n", key.c_str(), value.c_str());
      return 2;
    }
  }
  // drift_to_avoid's limits admit every avoidance of the evasive strategies (rear lock allowed, no
  // sliding constraint, no contact), so every Y cell can be solved under them; dodge forbids a
  // sliding rear axle, which exercises the strategy-constraint check.
  const ControlLimits limits =
      strategy == "dodge" ? ControlLimits{.forbid_rear_sliding = true} : ControlLimits{.allow_rear_lock = true};

  // The shipped scene with instant actuation (the `ideal` profile): the OMPL state then needs no
  // actuator memory. emrm's planner runs on the same scene, with the same wall-clock limit.
  SceneConfig config = load_scene_config(EMRM_SOURCE_DIR "/examples/tjunction/scene.yaml");
  config.actuation = ActuationConfig{};
  config.planner.max_time_ms = 1000.0 * time_limit_s;
  // The same search with no node budget (3·max_nodes must stay an int): the same seed draws the same
  // tree, so it differs from the shipped one only where that one ran out of nodes.
  SceneConfig unbounded = config;
  unbounded.planner.max_nodes = std::numeric_limits<int>::max() / 3;

  const auto began = std::chrono::steady_clock::now();
  std::vector<Cell> cells = y_band(config, y_count);
  std::fprintf(stderr, "Y band chosen in %.1f s\n", elapsed_ms(began) / 1000.0);
  for (Cell& c : random_cells(config, random_count)) cells.push_back(std::move(c));

  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  std::vector<std::vector<Run>> runs;
  std::FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
    return 1;
  }
  std::fprintf(csv, "set,group,speed_kph,ttc_s,mu,passage_m,planner,success,verified,time_ms,work\n");
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    const Scene scene(config, c.input);
    std::vector<Run> row;
    const std::uint64_t seed = cell_key(c.input, 41);
    row.push_back(run_emrm(scene, *model, limits, seed));
    row.push_back(run_emrm(Scene(unbounded, c.input), *model, limits, seed));
    for (int p = kOmplRrt; p < static_cast<int>(std::size(kPlanners)); ++p)
      row.push_back(run_ompl(p, scene, *model, limits, time_limit_s));
    for (std::size_t p = 0; p < row.size(); ++p)
      std::fprintf(csv, "%s,%s,%.1f,%.2f,%.2f,%.2f,%s,%d,%d,%.3f,%ld\n", c.set.c_str(), c.group.c_str(), c.input[0],
                   c.input[1], c.input[2], c.input[3], kPlanners[p], row[p].success, row[p].verified, row[p].ms,
                   row[p].work);
    std::fprintf(stderr, "[%zu/%zu] %s %.1f km/h TTC %.2f mu %.2f passage %.2f: %.1f %.1f %.1f %.1f %.1f ms\n", i + 1,
                 cells.size(), c.set.c_str(), c.input[0], c.input[1], c.input[2], c.input[3], row[0].ms, row[1].ms,
                 row[2].ms, row[3].ms, row[4].ms);
    runs.push_back(std::move(row));
  }
  std::fclose(csv);

  // Debian's ompl/config.h leaves OMPL_VERSION empty; the numbers are there.
  fmt::print("OMPL {}.{}.{}, limits {}, time limit {} s per planner and cell; times in ms over successes\n\n",
             OMPL_MAJOR_VERSION, OMPL_MINOR_VERSION, OMPL_PATCH_VERSION, strategy, time_limit_s);
  fmt::print(
      "| cells | planner | n | success | median | p90 | median vs emrm | paired ratio (cells) | "
      "solved where emrm did not; verified |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n");
  print_rows("Y band of the fine grid", cells, runs, [](const Cell& c) { return c.set == "Y band"; });
  print_rows("random", cells, runs, [](const Cell& c) { return c.set == "random"; });
  print_rows("random, braking avoids", cells, runs, [](const Cell& c) { return c.group == "braking avoids"; });
  print_rows("random, evasive only", cells, runs, [](const Cell& c) { return c.group == "evasive only"; });
  fmt::print("\ntotal {:.0f} s\n", elapsed_ms(began) / 1000.0);
  return 0;
}
