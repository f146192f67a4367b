// The reference line's segments against closed forms (ASAM OpenDRIVE 1.7 §7), each read from a
// small OpenDRIVE text: arc length, heading and curvature, and the clothoid against the Fresnel
// integrals' tabulated values and an independent integration.

#include "emrm/opendrive/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emrm/opendrive/road_network.hpp"
#include "opendrive/xodr_text.hpp"

namespace emrm::opendrive {
namespace {

using testing::geometry;
using testing::num;
using testing::road;
using testing::xodr;

constexpr double kPi = std::numbers::pi;

/// The reference line of a one-road file with these geometries.
ReferenceLine line_of(const std::string& geometries, double length) {
  const RoadNetwork network = parse_opendrive(xodr(road("1", length, geometries)), "g.xodr");
  return network.roads().front().plan_view;
}

double angle_difference(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

TEST(OpenDriveGeometry, LineIsStraightAtItsHeading) {
  const double h = 0.7;
  const ReferenceLine line = line_of(geometry(0, 10, -5, h, 50, "<line/>"), 50);
  EXPECT_DOUBLE_EQ(line.length(), 50.0);
  for (const double s : {0.0, 12.5, 50.0}) {
    const Pose p = line.at(s);
    EXPECT_NEAR(p.x, 10 + s * std::cos(h), 1e-12);
    EXPECT_NEAR(p.y, -5 + s * std::sin(h), 1e-12);
    EXPECT_NEAR(angle_difference(p.heading, h), 0.0, 1e-15);
    EXPECT_EQ(line.curvature(s), 0.0);
  }
}

TEST(OpenDriveGeometry, ArcLiesOnItsCircle) {
  for (const double radius : {25.0, -40.0}) {  // left and right turns
    const double h = -0.3;
    const double length = 60.0;
    const ReferenceLine arc =
        line_of(geometry(0, 3, 4, h, length, "<arc curvature=\"" + num(1 / radius) + "\"/>"), length);
    const double cx = 3 - radius * std::sin(h);
    const double cy = 4 + radius * std::cos(h);
    for (const double s : {0.0, 1e-7, 7.0, 33.3, length}) {
      const Pose p = arc.at(s);
      const double angle = h + s / radius;
      EXPECT_NEAR(angle_difference(p.heading, angle), 0.0, 1e-14);
      EXPECT_NEAR(p.x, cx + radius * std::sin(angle), 1e-11);
      EXPECT_NEAR(p.y, cy - radius * std::cos(angle), 1e-11);
      EXPECT_NEAR(std::hypot(p.x - cx, p.y - cy), std::abs(radius), 1e-11);
      EXPECT_DOUBLE_EQ(arc.curvature(s), 1 / radius);
    }
  }
}

/// (cos, sin) of the heading integrated by composite Simpson, independently of the library.
Pose simpson_clothoid(const Pose& start, double k, double rate, double s, int steps) {
  const double h = s / steps;
  double x = 0;
  double y = 0;
  for (int i = 0; i <= steps; ++i) {
    const double sigma = i * h;
    const double w = (i == 0 || i == steps) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double theta = start.heading + k * sigma + 0.5 * rate * sigma * sigma;
    x += w * std::cos(theta);
    y += w * std::sin(theta);
  }
  return {start.x + x * h / 3, start.y + y * h / 3, start.heading + k * s + 0.5 * rate * s * s};
}

TEST(OpenDriveGeometry, ClothoidMatchesTheFresnelIntegrals) {
  // x = C(z), y = S(z) for heading pi s²/2 (Abramowitz and Stegun, Table 7.7: C(1), S(1)).
  const Pose one = clothoid({}, 0.0, kPi, 1.0);
  EXPECT_NEAR(one.x, 0.7798934003768228, 1e-14);
  EXPECT_NEAR(one.y, 0.4382591473903548, 1e-14);
  // Far along, the asymptotic forms (A&S 7.3.9-10, 7.3.27-28): at z = 30, sin(pi z²/2) = 0 and
  // cos = 1, so C = 1/2 - g(z), S = 1/2 - f(z), with f ~ 1/(pi z) - 3/(pi³ z⁵), g ~ 1/(pi² z³) - 15/(pi⁴ z⁷)
  // (the next terms are below 1e-13).
  const double z = 30.0;
  const Pose far = clothoid({}, 0.0, kPi, z);
  const double f = 1 / (kPi * z) - 3 / (std::pow(kPi, 3) * std::pow(z, 5));
  const double g = 1 / (kPi * kPi * std::pow(z, 3)) - 15 / (std::pow(kPi, 4) * std::pow(z, 7));
  EXPECT_NEAR(far.x, 0.5 - g, 1e-12);
  EXPECT_NEAR(far.y, 0.5 - f, 1e-12);
}

TEST(OpenDriveGeometry, ClothoidComposesAndReverses) {
  const Pose start{1, 2, 0.4};
  const double k = 0.02;
  const double rate = -0.0013;
  const Pose whole = clothoid(start, k, rate, 90.0);
  const Pose half = clothoid(start, k, rate, 35.0);
  const Pose rest = clothoid(half, k + rate * 35.0, rate, 55.0);
  EXPECT_NEAR(rest.x, whole.x, 1e-11);
  EXPECT_NEAR(rest.y, whole.y, 1e-11);
  EXPECT_NEAR(rest.heading, whole.heading, 1e-13);
  const Pose back = clothoid(whole, k + rate * 90.0, rate, -90.0);
  EXPECT_NEAR(back.x, start.x, 1e-11);
  EXPECT_NEAR(back.y, start.y, 1e-11);
  EXPECT_NEAR(back.heading, start.heading, 1e-13);
}

TEST(OpenDriveGeometry, SpiralCurvatureIsLinearHeadingQuadratic) {
  const double k0 = -0.01;
  const double k1 = 0.05;
  const double length = 80.0;
  const double h = 1.1;
  const ReferenceLine spiral = line_of(
      geometry(0, -7, 2, h, length, "<spiral curvStart=\"" + num(k0) + "\" curvEnd=\"" + num(k1) + "\"/>"), length);
  const double rate = (k1 - k0) / length;
  for (const double s : {0.0, 10.0, 40.0, 79.0, 80.0}) {
    EXPECT_NEAR(spiral.curvature(s), k0 + rate * s, 1e-15);
    const Pose p = spiral.at(s);
    EXPECT_NEAR(angle_difference(p.heading, h + k0 * s + 0.5 * rate * s * s), 0.0, 1e-13);
    const Pose q = simpson_clothoid({-7, 2, h}, k0, rate, s, 20000);
    EXPECT_NEAR(p.x, q.x, 1e-9);
    EXPECT_NEAR(p.y, q.y, 1e-9);
  }
}

TEST(OpenDriveGeometry, StraightPoly3IsALine) {
  const double slope = 0.25;  // v = 0.5 + u/4: a line at atan(1/4) from the start, offset 0.5 to the left
  const double h = -0.6;
  const ReferenceLine poly =
      line_of(geometry(0, 2, 3, h, 40, "<poly3 a=\"0.5\" b=\"" + num(slope) + "\" c=\"0\" d=\"0\"/>"), 40);
  const double direction = h + std::atan(slope);
  const double x0 = 2 - 0.5 * std::sin(h);
  const double y0 = 3 + 0.5 * std::cos(h);
  for (const double s : {0.0, 5.0, 23.7, 40.0}) {
    const Pose p = poly.at(s);
    EXPECT_NEAR(p.x, x0 + s * std::cos(direction), 1e-10);
    EXPECT_NEAR(p.y, y0 + s * std::sin(direction), 1e-10);
    EXPECT_NEAR(angle_difference(p.heading, direction), 0.0, 1e-13);
    EXPECT_NEAR(poly.curvature(s), 0.0, 1e-15);
  }
}

/// The arc length of v = k u² from 0 to u.
double parabola_length(double k, double u) {
  const double q = 2 * k * u;
  return 0.5 * u * std::sqrt(1 + q * q) + std::asinh(q) / (4 * k);
}

TEST(OpenDriveGeometry, Poly3ParabolaIsParametrisedByArcLength) {
  const double k = 0.01;
  const double end_u = 60.0;
  const double length = parabola_length(k, end_u);
  const ReferenceLine poly =
      line_of(geometry(0, 0, 0, 0, length, "<poly3 a=\"0\" b=\"0\" c=\"" + num(k) + "\" d=\"0\"/>"), length);
  for (const double u : {0.0, 1.0, 17.0, 42.5, end_u}) {
    const Pose p = poly.at(parabola_length(k, u));
    EXPECT_NEAR(p.x, u, 1e-9);
    EXPECT_NEAR(p.y, k * u * u, 1e-9);
    EXPECT_NEAR(p.heading, std::atan(2 * k * u), 1e-12);
    EXPECT_NEAR(poly.curvature(parabola_length(k, u)), 2 * k / std::pow(1 + 4 * k * k * u * u, 1.5), 1e-12);
  }
}

TEST(OpenDriveGeometry, ParamPoly3ReproducesAParabolaInBothRanges) {
  const double k = 0.02;
  const double end_u = 45.0;
  const double length = parabola_length(k, end_u);
  const double h = 0.3;
  const double c = std::cos(h);
  const double s = std::sin(h);
  // u = X p / P, v = k u² for p in [0, P], P the range's end.
  for (const bool arc_length : {true, false}) {
    const double range_end = arc_length ? length : 1.0;
    const double bu = end_u / range_end;
    const std::string shape = "<paramPoly3 aU=\"0\" bU=\"" + num(bu) + "\" cU=\"0\" dU=\"0\" aV=\"0\" bV=\"0\" cV=\"" +
                              num(k * bu * bu) + "\" dV=\"0\" pRange=\"" + (arc_length ? "arcLength" : "normalized") +
                              "\"/>";
    const ReferenceLine line = line_of(geometry(0, 5, 6, h, length, shape), length);
    for (const double u : {0.0, 3.0, 22.0, end_u}) {
      const Pose p = line.at(parabola_length(k, u));
      const double v = k * u * u;
      EXPECT_NEAR(p.x, 5 + c * u - s * v, 1e-9) << arc_length;
      EXPECT_NEAR(p.y, 6 + s * u + c * v, 1e-9) << arc_length;
      EXPECT_NEAR(p.heading, h + std::atan(2 * k * u), 1e-12) << arc_length;
    }
  }
}

TEST(OpenDriveGeometry, SegmentsJoinInOneLine) {
  // line, spiral into an arc, arc, spiral out, line: each starts where the previous ends.
  const double r = 50;
  const Pose a{0, 0, 0};
  const Pose b = clothoid(a, 0, 0, 20);
  const Pose c = clothoid(b, 0, 1 / (r * 30), 30);
  const Pose d = clothoid(c, 1 / r, 0, 40);
  const Pose e = clothoid(d, 1 / r, -1 / (r * 30), 30);
  const std::string text =
      geometry(0, a.x, a.y, a.heading, 20, "<line/>") +
      geometry(20, b.x, b.y, b.heading, 30, "<spiral curvStart=\"0\" curvEnd=\"" + num(1 / r) + "\"/>") +
      geometry(50, c.x, c.y, c.heading, 40, "<arc curvature=\"" + num(1 / r) + "\"/>") +
      geometry(90, d.x, d.y, d.heading, 30, "<spiral curvStart=\"" + num(1 / r) + "\" curvEnd=\"0\"/>") +
      geometry(120, e.x, e.y, e.heading, 10, "<line/>");
  const ReferenceLine line = line_of(text, 130);
  for (const double joint : {20.0, 50.0, 90.0, 120.0}) {
    const Pose before = line.at(joint - 1e-9);
    const Pose at = line.at(joint);
    EXPECT_NEAR(before.x, at.x, 1e-8);
    EXPECT_NEAR(before.y, at.y, 1e-8);
    EXPECT_NEAR(before.heading, at.heading, 1e-9);
  }
  EXPECT_EQ(line.segment_index(50.0), 2U);
  EXPECT_EQ(line.segment_index(49.9), 1U);
}

}  // namespace
}  // namespace emrm::opendrive
