// The plan view's segments (ASAM OpenDRIVE 1.7 §7.4 line, §7.5 spiral, §7.6 arc, §7.7.1 poly3,
// §7.7.2 paramPoly3) and the clothoid they and OpenSCENARIO trajectories share (docs/import.md).

#include "emrm/opendrive/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace emrm::opendrive {
namespace {

/// The n-point Gauss-Legendre rule on [-1, 1], its nodes found by Newton's method on P_n.
constexpr int kGaussPoints = 12;
struct GaussRule {
  std::array<double, kGaussPoints> node{};
  std::array<double, kGaussPoints> weight{};
};

GaussRule make_gauss_rule() {
  GaussRule rule;
  constexpr int n = kGaussPoints;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0;
      double p1 = x;
      for (int k = 2; k <= n; ++k) {  // (k) P_k = (2k - 1) x P_{k-1} - (k - 1) P_{k-2}
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-17) break;
    }
    rule.node[static_cast<std::size_t>(i)] = x;
    rule.weight[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
  return rule;
}

const GaussRule& gauss_rule() {
  static const GaussRule rule = make_gauss_rule();
  return rule;
}

/// The integral of f over [a, b] by one Gauss-Legendre panel.
template <class F>
double gauss(const F& f, double a, double b) {
  const GaussRule& rule = gauss_rule();
  const double half = 0.5 * (b - a);
  const double mid = 0.5 * (a + b);
  double sum = 0.0;
  for (std::size_t i = 0; i < rule.node.size(); ++i) sum += rule.weight[i] * f(mid + half * rule.node[i]);
  return half * sum;
}

/// sin(x)/x, without cancellation near 0.
double sinc(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * x / 6.0;  // next term x⁴/120 < 1e-18
  return std::sin(x) / x;
}

Pose rotated_into(const Segment& segment, double u, double v, double local_heading) {
  const double c = std::cos(segment.heading);
  const double s = std::sin(segment.heading);
  return {segment.x + c * u - s * v, segment.y + s * u + c * v, segment.heading + local_heading};
}

/// A cubic curve in the segment's local frame, by a parameter w: poly3 (u = w, v = v(w)) or
/// paramPoly3 (u(w), v(w)).
struct LocalCurve {
  std::array<double, 4> u{};
  std::array<double, 4> v{};

  static double value(const std::array<double, 4>& k, double w) { return k[0] + w * (k[1] + w * (k[2] + w * k[3])); }
  static double slope(const std::array<double, 4>& k, double w) { return k[1] + w * (2.0 * k[2] + w * 3.0 * k[3]); }
  static double bend(const std::array<double, 4>& k, double w) { return 2.0 * k[2] + 6.0 * k[3] * w; }

  [[nodiscard]] double speed(double w) const { return std::hypot(slope(u, w), slope(v, w)); }
  [[nodiscard]] double arc_length(double from, double to) const {
    return gauss([this](double w) { return speed(w); }, from, to);
  }
  [[nodiscard]] double curvature(double w) const {
    const double du = slope(u, w);
    const double dv = slope(v, w);
    const double speed_cubed = std::pow(du * du + dv * dv, 1.5);
    return speed_cubed > 0.0 ? (du * bend(v, w) - dv * bend(u, w)) / speed_cubed : 0.0;
  }
  [[nodiscard]] Pose pose(const Segment& segment, double w) const {
    return rotated_into(segment, value(u, w), value(v, w), std::atan2(slope(v, w), slope(u, w)));
  }

  /// The parameter in [lo, hi] where the arc length from `lo` is `target` (the arc length grows
  /// with the parameter): Newton's method, falling back on bisection where a step leaves the bracket.
  [[nodiscard]] double parameter_at(double lo, double hi, double target) const {
    const double start = lo;
    double w = lo + (hi - lo) * 0.5;
    if (const double speed_lo = speed(lo); speed_lo > 0.0) w = std::min(hi, lo + target / speed_lo);
    for (int iteration = 0; iteration < 60; ++iteration) {
      const double error = arc_length(start, w) - target;
      if (error > 0.0)
        hi = w;
      else
        lo = w;
      const double rate = speed(w);
      double next = rate > 0.0 ? w - error / rate : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - w) <= 1e-14 * (1.0 + std::abs(w))) return next;
      w = next;
    }
    return w;
  }
};

LocalCurve local_curve(const Poly3& p) { return {{0.0, 1.0, 0.0, 0.0}, {p.a, p.b, p.c, p.d}}; }
LocalCurve local_curve(const ParamPoly3& p) { return {{p.a_u, p.b_u, p.c_u, p.d_u}, {p.a_v, p.b_v, p.c_v, p.d_v}}; }

/// The table's steps: about one a metre, at least 16, at most 4096 (Newton does the rest).
std::size_t table_steps(double length) { return static_cast<std::size_t>(std::clamp(std::ceil(length), 16.0, 4096.0)); }

/// The parameter at `steps` + 1 equal steps of arc length up to `own_length`, from 0 to `end`.
std::vector<double> parameter_table(const LocalCurve& curve, double own_length, double end) {
  const std::size_t steps = table_steps(own_length);
  std::vector<double> table(steps + 1, 0.0);
  const double step = own_length / static_cast<double>(steps);
  for (std::size_t k = 1; k < steps; ++k) table[k] = curve.parameter_at(table[k - 1], end, step);
  table[steps] = end;
  return table;
}

/// The curve's arc length from 0 to `end` by composite Gauss-Legendre (64 panels).
double own_length(const LocalCurve& curve, double end) {
  constexpr int kPanels = 64;
  double sum = 0.0;
  for (int i = 0; i < kPanels; ++i) sum += curve.arc_length(end * i / kPanels, end * (i + 1) / kPanels);
  return sum;
}

}  // namespace

Pose clothoid(const Pose& start, double curvature, double curvature_rate, double s) {
  if (curvature_rate == 0.0) {  // a line or an arc: the chord s sinc(k s / 2) at the mean heading
    const double half_turn = 0.5 * curvature * s;
    const double chord = s * sinc(half_turn);
    const double mean = start.heading + half_turn;
    return {start.x + chord * std::cos(mean), start.y + chord * std::sin(mean), start.heading + 2.0 * half_turn};
  }
  const auto heading = [&](double sigma) { return start.heading + sigma * (curvature + 0.5 * curvature_rate * sigma); };
  // Panels short enough that the heading turns by at most about one radian in each: 12 points
  // then integrate cos and sin to rounding (the error term is below (1)^24 / 24!).
  const double turn_bound = std::abs(s) * (std::abs(curvature) + std::abs(curvature_rate * s));
  const auto panels = static_cast<int>(std::min(1e6, std::ceil(turn_bound) + 1.0));
  double x = 0.0;
  double y = 0.0;
  for (int i = 0; i < panels; ++i) {
    const double a = s * i / panels;
    const double b = s * (i + 1) / panels;
    x += gauss([&](double sigma) { return std::cos(heading(sigma)); }, a, b);
    y += gauss([&](double sigma) { return std::sin(heading(sigma)); }, a, b);
  }
  return {start.x + x, start.y + y, heading(s)};
}

ReferenceLine::ReferenceLine(std::vector<Segment> segments) : segments_(std::move(segments)) {
  tables_.resize(segments_.size());
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const Segment& segment = segments_[i];
    if (const auto* poly = std::get_if<Poly3>(&segment.shape)) {
      // u runs until the arc length is the segment's; it is at most that length (the speed is >= 1).
      const LocalCurve curve = local_curve(*poly);
      const double end = curve.parameter_at(0.0, segment.length, segment.length);
      tables_[i] = {segment.length, parameter_table(curve, segment.length, end)};
    } else if (const auto* param = std::get_if<ParamPoly3>(&segment.shape)) {
      const LocalCurve curve = local_curve(*param);
      const double end = param->range == ParamRange::kArcLength ? segment.length : 1.0;
      const double length = own_length(curve, end);
      tables_[i] = {length, parameter_table(curve, length, end)};
    }
  }
}

double ReferenceLine::length() const { return segments_.empty() ? 0.0 : segments_.back().s + segments_.back().length; }

std::size_t ReferenceLine::segment_index(double s) const {
  const auto after = std::upper_bound(segments_.begin(), segments_.end(), s,
                                      [](double value, const Segment& segment) { return value < segment.s; });
  return after == segments_.begin() ? 0 : static_cast<std::size_t>(after - segments_.begin()) - 1;
}

namespace {

/// The curve parameter at arc length ds into a poly3/paramPoly3 segment (stretched to its table).
double table_parameter(const LocalCurve& curve, const std::vector<double>& table, double own, double length,
                       double ds) {
  const double sigma = std::clamp(ds, 0.0, length) * own / length;
  const std::size_t steps = table.size() - 1;
  const double step = own / static_cast<double>(steps);
  const auto k = std::min(steps - 1, static_cast<std::size_t>(sigma / step));
  return curve.parameter_at(table[k], table[k + 1], sigma - static_cast<double>(k) * step);
}

}  // namespace

Pose ReferenceLine::at(double s) const {
  s = std::clamp(s, 0.0, length());
  const std::size_t i = segment_index(s);
  const Segment& segment = segments_[i];
  const double ds = s - segment.s;
  const Pose start{segment.x, segment.y, segment.heading};
  return std::visit(
      [&](const auto& shape) -> Pose {
        using T = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<T, Line>) {
          return clothoid(start, 0.0, 0.0, ds);
        } else if constexpr (std::is_same_v<T, Arc>) {
          return clothoid(start, shape.curvature, 0.0, ds);
        } else if constexpr (std::is_same_v<T, Spiral>) {
          return clothoid(start, shape.curvature_start, (shape.curvature_end - shape.curvature_start) / segment.length,
                          ds);
        } else {
          const LocalCurve curve = local_curve(shape);
          const auto& table = tables_[i];
          return curve.pose(segment, table_parameter(curve, table.parameter, table.own_length, segment.length, ds));
        }
      },
      segment.shape);
}

double ReferenceLine::curvature(double s) const {
  s = std::clamp(s, 0.0, length());
  const std::size_t i = segment_index(s);
  const Segment& segment = segments_[i];
  const double ds = s - segment.s;
  return std::visit(
      [&](const auto& shape) -> double {
        using T = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<T, Line>) {
          return 0.0;
        } else if constexpr (std::is_same_v<T, Arc>) {
          return shape.curvature;
        } else if constexpr (std::is_same_v<T, Spiral>) {
          return shape.curvature_start + (shape.curvature_end - shape.curvature_start) * ds / segment.length;
        } else {
          const LocalCurve curve = local_curve(shape);
          const auto& table = tables_[i];
          // The curve's own (geometric) curvature, also where a paramPoly3 is stretched to its length.
          return curve.curvature(table_parameter(curve, table.parameter, table.own_length, segment.length, ds));
        }
      },
      segment.shape);
}

}  // namespace emrm::opendrive
