// Judging a recorded trajectory (assess.hpp): contact and road departure between samples, the safe
// state at the end, and the outcome as JSON and text.

#include "emrm/exchange/assess.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "emrm/core/error.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"
#include "slopes.hpp"

namespace emrm::exchange {
namespace {

using detail::slope;
using detail::stencil;

using sim::kKphPerMps;
// A sample within this of the truck or of the road's edge touches it: the tolerance of the
// simulator's own continuous collision check (docs/physics.md), so that a trajectory emrm executed
// up to the moment of contact is judged a contact.
constexpr double kTouch_m = 0.5e-3;
// A recording that ends moving within this of the truck (or the road's edge) ended at a contact
// (a departure): the reach of sim::actor_impact's nudge, within which the simulator itself assesses
// the state it integrated to the first touch as a contact.
constexpr double kEndTouch_m = 0.01;

class Judge {
 public:
  Judge(const sim::Scene& scene, const RecordedTrajectory& trajectory)
      : scene_(scene), samples_(trajectory.samples), has_truck_(trajectory.has_truck) {
    const auto& cfg = scene.config();
    for (const sim::Actor& actor : scene.actors()) {
      const sim::ActorBody& body = actor.body();
      actor_reach_m_.push_back(0.5 * std::hypot(body.length_m, body.width_m));
      circumradii_m_.push_back(0.5 * std::hypot(cfg.ego.length_m, cfg.ego.width_m) + actor_reach_m_.back());
    }
    reach_m_ = std::hypot(std::max(cfg.ego.cg_to_front_m(), cfg.ego.cg_to_rear_m()), 0.5 * cfg.ego.width_m);
  }

  // The pose at time t in segment [i, i+1]: position and heading interpolated linearly.
  [[nodiscard]] sim::VehicleState pose(std::size_t i, double t) const {
    const auto& a = samples_[i];
    const auto& b = samples_[i + 1];
    const double u = (t - a.t_s) / (b.t_s - a.t_s);
    sim::VehicleState s;
    s.x_m = a.x_m + u * (b.x_m - a.x_m);
    s.y_m = a.y_m + u * (b.y_m - a.y_m);
    s.yaw_rad = a.yaw_rad + u * (b.yaw_rad - a.yaw_rad);
    return s;
  }

  // The full state at time t in segment [i, i+1]: the pose, the speed interpolated, the direction
  // of motion and the yaw rate from the parabola through three neighbouring samples.
  [[nodiscard]] sim::VehicleState state(std::size_t i, double t) const {
    sim::VehicleState s = pose(i, t);
    const auto& a = samples_[i];
    const auto& b = samples_[i + 1];
    const double u = (t - a.t_s) / (b.t_s - a.t_s);
    const double speed = a.speed_mps + u * (b.speed_mps - a.speed_mps);
    s.steer_rad = a.steer_rad + u * (b.steer_rad - a.steer_rad);
    const auto [first, points] = stencil(i, samples_.size());
    double ts[3], xs[3], ys[3], yaws[3];
    for (int k = 0; k < points; ++k) {
      const auto& p = samples_[first + k];
      ts[k] = p.t_s;
      xs[k] = p.x_m;
      ys[k] = p.y_m;
      yaws[k] = p.yaw_rad;
    }
    const double vx = slope(ts, xs, points, t);
    const double vy = slope(ts, ys, points, t);
    const double direction = std::hypot(vx, vy) > 1e-9 ? std::atan2(vy, vx) : s.yaw_rad;
    const auto [c, sn] = core::cos_sin(direction - s.yaw_rad);
    s.vx_mps = speed * c;
    s.vy_mps = speed * sn;
    s.yaw_rate_radps = slope(ts, yaws, points, t);
    return s;
  }

  // Actor `k` at time t in segment i: the hazard (actor 0) as recorded when the recording has it,
  // every other actor (and an unrecorded hazard) as the scene moves it.
  [[nodiscard]] sim::ActorState actor(std::size_t k, std::size_t i, double t) const {
    if (k != 0 || !has_truck_) return scene_.actors()[k].at(t);
    const auto& a = samples_[i];
    const auto& b = samples_[i + 1];
    const double dt = b.t_s - a.t_s;
    const double u = (t - a.t_s) / dt;
    const sim::ActorBody& body = scene_.hazard().body();
    sim::ActorState out;
    out.box.center = {a.truck_x_m + u * (b.truck_x_m - a.truck_x_m), a.truck_y_m + u * (b.truck_y_m - a.truck_y_m)};
    out.box.heading_rad = a.truck_yaw_rad + u * (b.truck_yaw_rad - a.truck_yaw_rad);
    out.box.length_m = body.length_m;
    out.box.width_m = body.width_m;
    out.velocity_mps = {(b.truck_x_m - a.truck_x_m) / dt, (b.truck_y_m - a.truck_y_m) / dt};
    return out;
  }

  [[nodiscard]] double actor_gap(std::size_t k, std::size_t i, double t) const {
    return core::separation_lower_bound(scene_.ego_box(pose(i, t)), actor(k, i, t).box);
  }
  [[nodiscard]] double edge_gap(std::size_t i, double t) const { return scene_.edge_gap_m(scene_.ego_box(pose(i, t))); }

  struct Touch {
    std::size_t segment = 0;
    double t_s = 0.0;
    double gap_m = 0.0;  // <= 0: an overlap
  };

  // The first time in segment i at which `gap` closes, or nothing, by conservative advancement as
  // the simulator's own check does it: between samples every point of the ego moves (relative to
  // the actor `with`, or to the road's edge without one) at most `motion` (translation, the car's reach
  // swept by its turn, the actor's travel and turn) spread evenly over the segment, so the gap cannot close faster than
  // motion/Δt; steps of (gap + kTouch_m) at that rate miss no touch deeper than kTouch_m. The first overlap is timed by
  // bisection; a probe within kTouch_m without an overlap (a run recorded up to its moment of contact) counts at the
  // segment's closest approach.
  template <class Gap>
  [[nodiscard]] std::optional<Touch> first_touch(std::size_t i, double gap_at_start, std::optional<std::size_t> with,
                                                 Gap&& gap) const {
    const auto& a = samples_[i];
    const auto& b = samples_[i + 1];
    double motion = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) + std::abs(b.yaw_rad - a.yaw_rad) * reach_m_;
    if (with) {
      const auto ta = actor(*with, i, a.t_s).box;
      const auto tb = actor(*with, i, b.t_s).box;
      motion += (tb.center - ta.center).norm() + std::abs(tb.heading_rad - ta.heading_rad) * actor_reach_m_[*with];
    }
    if (gap_at_start - kTouch_m > motion) return std::nullopt;
    const double rate_mps = motion / (b.t_s - a.t_s);
    const auto first_overlap = [&](double lo, double hi) {
      while (hi - lo > 1e-7) {  // as the simulator times a touch: depths of micrometres
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;  // times so large that no double lies between
        (gap(mid) <= 0.0 ? hi : lo) = mid;
      }
      return hi;
    };
    std::optional<double> closest;
    double closest_gap = kTouch_m;
    double previous = a.t_s;
    double t = a.t_s;
    double g = gap_at_start;
    // At most 4096 probes a segment (numbers out of any range make no progress otherwise).
    for (int k = 0; k < 4096; ++k) {
      const double step_s = (std::max(g, 0.0) + kTouch_m) / rate_mps;
      previous = t;
      t = std::isfinite(step_s) && step_s > 0.0 ? std::min(b.t_s, t + step_s) : b.t_s;
      g = gap(t);
      if (g <= 0.0) return Touch{i, first_overlap(previous, t), 0.0};
      if (g <= closest_gap) {
        closest = t;
        closest_gap = g;
      }
      if (!(t < b.t_s)) break;
    }
    if (!closest) return std::nullopt;
    return Touch{i, *closest, closest_gap};
  }

  // A near touch (within kTouch_m, no overlap) followed on while the approach continues into the
  // next segments: their first overlap, else the closest approach.
  template <class GapIn>
  [[nodiscard]] Touch follow(Touch touch, std::optional<std::size_t> with, GapIn&& gap_in) const {
    for (std::size_t j = touch.segment + 1; touch.gap_m > 0.0 && j + 1 < samples_.size(); ++j) {
      const auto next = first_touch(j, gap_in(j, samples_[j].t_s), with, [&](double t) { return gap_in(j, t); });
      if (!next || next->gap_m >= touch.gap_m) break;
      touch = *next;
    }
    return touch;
  }

  // Far apart by the centres alone: actor `k` cannot be reached within the segment.
  [[nodiscard]] bool far_from(std::size_t k, std::size_t i) const {
    const auto& a = samples_[i];
    const auto& b = samples_[i + 1];
    const core::Vec2 ego_a{a.x_m, a.y_m};
    const core::Vec2 actor_a = actor(k, i, a.t_s).box.center;
    const core::Vec2 actor_b = actor(k, i, b.t_s).box.center;
    const double move = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) + (actor_b - actor_a).norm();
    const core::Vec2 d = ego_a - actor_a;
    const double reach = circumradii_m_[k] + move + 1.0;
    return d.dot(d) > reach * reach;
  }

  // The first contact in segment i with any actor (followed on through the next segments), the
  // earliest of them, and with which actor.
  [[nodiscard]] std::optional<std::pair<Touch, std::size_t>> first_contact(std::size_t i) const {
    std::optional<std::pair<Touch, std::size_t>> out;
    const double ta = samples_[i].t_s;
    for (std::size_t k = 0; k < scene_.actors().size(); ++k) {
      if (far_from(k, i)) continue;
      auto touch = first_touch(i, actor_gap(k, i, ta), k, [&](double t) { return actor_gap(k, i, t); });
      if (!touch) continue;
      const Touch followed = follow(*touch, k, [&](std::size_t j, double t) { return actor_gap(k, j, t); });
      if (!out || followed.t_s < out->first.t_s) out = std::pair{followed, k};
    }
    return out;
  }

  [[nodiscard]] Assessment run() const {
    Assessment out;
    const std::size_t n = samples_.size();
    const std::size_t actors = scene_.actors().size();
    // The first sample itself.
    {
      const double t0 = samples_[0].t_s;
      for (std::size_t k = 0; k < actors; ++k)
        if (actor_gap(k, 0, t0) <= kTouch_m) return at_contact(out, k, 0, t0);
      if (edge_gap(0, t0) <= kTouch_m) return at_departure(out, 0, t0);
    }
    const auto edge_gap_in = [&](std::size_t j, double t) { return edge_gap(j, t); };
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double ta = samples_[i].t_s;
      const auto contact = first_contact(i);
      std::optional<Touch> departure =
          first_touch(i, edge_gap(i, ta), std::nullopt, [&](double t) { return edge_gap(i, t); });
      if (departure) departure = follow(*departure, std::nullopt, edge_gap_in);
      if (contact && (!departure || contact->first.t_s <= departure->t_s))
        return at_contact(out, contact->second, contact->first.segment, contact->first.t_s);
      if (departure) return at_departure(out, departure->segment, departure->t_s);
    }
    const std::size_t last = n - 2;
    const double t_end = samples_.back().t_s;
    if (samples_.back().speed_mps >= sim::kStoppedSpeed_mps) {
      for (std::size_t k = 0; k < actors; ++k)
        if (actor_gap(k, last, t_end) <= kEndTouch_m) return at_contact(out, k, last, t_end);
      if (edge_gap(last, t_end) <= kEndTouch_m) return at_departure(out, last, t_end);
    }
    // No event: a safe state at the end?
    const sim::VehicleState end = state(last, t_end);
    out.end_time_s = t_end;
    out.samples_judged = n;
    if (samples_.back().speed_mps < sim::kStoppedSpeed_mps) {
      // At rest, unless an actor that moves on (as the scene moves it) meets the standing car.
      if (const auto touch = sim::touch_at_rest(scene_, end, t_end))
        return contact(out, touch->actor, end, scene_.actors()[touch->actor].at(touch->t_s), touch->t_s);
      out.safe_state = SafeState::kStopped;
    } else {
      const double ego_min_x = sim::extent_of(scene_.ego_box(end)).min_x;
      const double truck_far_x =
          has_truck_ ? sim::extent_of(actor(0, last, t_end).box).max_x : scene_.passed_x_m(t_end);
      if (ego_min_x > truck_far_x && sim::stable_with_room_to_stop(scene_, end))
        out.safe_state = SafeState::kStabilised;
    }
    out.avoided = out.safe_state != SafeState::kNone;
    return out;
  }

 private:
  Assessment at_contact(Assessment out, std::size_t k, std::size_t segment, double t) const {
    const std::size_t i = std::min(segment, samples_.size() - 2);
    out.samples_judged = i + 2;
    return contact(std::move(out), k, state(i, t), actor(k, i, t), t);
  }
  // The ego at `s` meets actor k, there at `at`, at time t.
  Assessment contact(Assessment out, std::size_t k, const sim::VehicleState& s, const sim::ActorState& at,
                     double t) const {
    core::Contact c;
    out.contact = true;
    out.contact_with = scene_.actors()[k].body().name;
    out.impact = sim::actor_impact(scene_, scene_.actors()[k].body(), s, at, &c);
    out.event_time_s = t;
    out.event_point_m = c.point;
    out.end_time_s = t;
    return out;
  }
  Assessment at_departure(Assessment out, std::size_t segment, double t) const {
    const std::size_t i = std::min(segment, samples_.size() - 2);
    const sim::VehicleState s = state(i, t);
    out.road_departure = true;
    out.impact = sim::roadside_impact(scene_, s, &out.event_point_m);
    out.event_time_s = t;
    out.end_time_s = t;
    out.samples_judged = i + 2;
    return out;
  }

  const sim::Scene& scene_;
  const std::vector<TrajectorySample>& samples_;
  bool has_truck_;
  std::vector<double> circumradii_m_;  // the ego's and each actor's, by actor
  double reach_m_ = 0.0;
  std::vector<double> actor_reach_m_;  // each actor's half diagonal
};

nlohmann::ordered_json impact_json(const sim::ImpactAssessment& a) {
  nlohmann::ordered_json j;
  const nlohmann::json impact = sim::to_json(a);
  for (const auto& [k, v] : impact.items()) j[k] = v;
  return j;
}

}  // namespace

std::string_view safe_state_name(SafeState s) noexcept {
  switch (s) {
    case SafeState::kStopped:
      return "stopped";
    case SafeState::kStabilised:
      return "stabilised";
    case SafeState::kNone:
      break;
  }
  return "none";
}

Assessment assess(const sim::SceneConfig& config, const sim::CellInput& cell, const RecordedTrajectory& trajectory) {
  sim::validate(config);
  sim::validate_cell(config, cell);
  const sim::Scene scene(config, cell);
  if (!scene.feasible()) throw UsageError("the cell is infeasible: " + scene.infeasible_reason());
  Assessment out = Judge(scene, trajectory).run();
  out.hazard = scene.hazard().body().name;
  if (out.avoided) out.impact = {};
  const auto model = sim::make_vehicle_model(config.simulation.vehicle_model, config.ego);
  out.unmitigated = sim::no_action_rollout(scene, *model).impact;
  out.delta_loss = out.unmitigated.loss_level - out.impact.loss_level;
  if (out.contact) {
    out.min_ttc_s = 0.0;
  } else if (!trajectory.has_truck) {
    std::vector<sim::PathPoint> path;
    path.reserve(trajectory.samples.size());
    const Judge judge(scene, trajectory);
    for (std::size_t k = 0; k + 1 < trajectory.samples.size(); ++k)
      path.push_back({trajectory.samples[k].t_s, judge.state(k, trajectory.samples[k].t_s), {}});
    out.min_ttc_s = sim::min_ttc_along(scene, path);
  }
  return out;
}

nlohmann::ordered_json to_json(const Assessment& a, const RecordedTrajectory& trajectory, TrajectoryFormat format,
                               const sim::FactorTable& factors, const sim::CellInput& cell,
                               const std::string& strategy) {
  nlohmann::ordered_json j;
  j["file"] = trajectory.file;
  j["format"] = std::string(format_name(format));
  j["input"] = nlohmann::ordered_json::object();
  for (std::size_t f = 0; f < factors.size() && f < cell.size(); ++f) j["input"][factors[f].key] = cell[f];
  j["truck"] = trajectory.has_truck ? "recorded" : "scene";
  j["samples"] = trajectory.samples.size();
  if (!strategy.empty()) j["strategy"] = strategy;
  j["unmitigated"] = impact_json(a.unmitigated);
  nlohmann::ordered_json o = impact_json(a.impact);
  o["avoided"] = a.avoided;
  o["contact"] = a.contact;
  o["road_departure"] = a.road_departure;
  o["departure_speed_kph"] = a.road_departure ? a.impact.impact_speed_mps * kKphPerMps : 0.0;
  o["delta_loss"] = a.delta_loss;
  o["min_ttc_s"] = a.min_ttc_s && std::isfinite(*a.min_ttc_s) ? nlohmann::ordered_json(*a.min_ttc_s)
                                                              : nlohmann::ordered_json(nullptr);
  o["event_time_s"] = a.event_time_s ? nlohmann::ordered_json(*a.event_time_s) : nlohmann::ordered_json(nullptr);
  o["event_point"] = a.event_time_s ? nlohmann::ordered_json::array({a.event_point_m.x, a.event_point_m.y})
                                    : nlohmann::ordered_json(nullptr);
  o["safe_state"] = std::string(safe_state_name(a.safe_state));
  o["end_time_s"] = a.end_time_s;
  o["samples_judged"] = a.samples_judged;
  j["outcome"] = std::move(o);
  return j;
}

std::string to_text(const Assessment& a, const RecordedTrajectory& trajectory, const std::string& strategy) {
  std::string out = fmt::format("{}: {} samples from {:.3f} s to {:.3f} s{}; {}: {}\n", trajectory.file,
                                trajectory.samples.size(), trajectory.samples.front().t_s,
                                trajectory.samples.back().t_s, strategy.empty() ? "" : " (" + strategy + ")", a.hazard,
                                trajectory.has_truck ? "recorded" : "the scene's nominal motion");
  if (a.avoided) {
    out += fmt::format("Avoided: no contact, no road departure; safe state: {} at {:.3f} s\n",
                       safe_state_name(a.safe_state), a.end_time_s);
  } else if (a.contact || a.road_departure) {
    out += fmt::format(
        "{} at {:.4f} s at ({:.3f}, {:.3f}) m: impact speed {:.2f} km/h, Δv {:.2f} km/h, "
        "P(MAIS3+) {:.4f}, P(fatal) {:.4f}, loss level L{}\n",
        a.contact ? "Contact with the " + a.contact_with : std::string("Road departure"), *a.event_time_s,
        a.event_point_m.x, a.event_point_m.y, a.impact.impact_speed_mps * kKphPerMps, a.impact.delta_v_mps * kKphPerMps,
        a.impact.p_mais3, a.impact.p_fatal, a.impact.loss_level);
  } else {
    out += fmt::format("Not avoided: no contact or departure, but no safe state at the last sample ({:.3f} s)\n",
                       a.end_time_s);
  }
  out += fmt::format("Unmitigated reference: loss level L{} (Δv {:.2f} km/h); Δloss {}\n", a.unmitigated.loss_level,
                     a.unmitigated.delta_v_mps * kKphPerMps, a.delta_loss);
  return out;
}

}  // namespace emrm::exchange
