#include "emrm/core/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "emrm/core/trig.hpp"

namespace emrm::core {
namespace geometry_test {

constexpr double kPi = std::numbers::pi;

OrientedBox box(double x, double y, double heading_rad, double length_m, double width_m) {
  return {{x, y}, heading_rad, length_m, width_m};
}

// ---- a brute-force reference: closed polygons intersect when a corner of one lies in (or on)
// the other, or two edges cross or touch ----------------------------------------------------------

double orient(Vec2 a, Vec2 b, Vec2 c) { return (b - a).cross(c - a); }

bool on_segment(Vec2 p, Vec2 q, Vec2 r) {  // r on segment pq, given collinear
  return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
         r.y <= std::max(p.y, q.y);
}

bool segments_intersect(Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2) {
  const double d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2);
  const double d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && on_segment(q1, q2, p1)) || (d2 == 0 && on_segment(q1, q2, p2)) ||
         (d3 == 0 && on_segment(p1, p2, q1)) || (d4 == 0 && on_segment(p1, p2, q2));
}

bool inside_convex(const std::array<Vec2, 4>& poly, Vec2 p) {  // counter-clockwise polygon, closed
  for (std::size_t i = 0; i < 4; ++i)
    if (orient(poly[i], poly[(i + 1) % 4], p) < 0) return false;
  return true;
}

bool reference_overlaps(const OrientedBox& a, const OrientedBox& b) {
  const auto pa = a.corners();
  const auto pb = b.corners();
  for (const auto& p : pa)
    if (inside_convex(pb, p)) return true;
  for (const auto& p : pb)
    if (inside_convex(pa, p)) return true;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      if (segments_intersect(pa[i], pa[(i + 1) % 4], pb[j], pb[(j + 1) % 4])) return true;
  return false;
}

OrientedBox grown(OrientedBox b, double margin_m) {
  b.length_m += 2 * margin_m;
  b.width_m += 2 * margin_m;
  return b;
}

// The reference verdict when it does not hinge on rounding: the same with both boxes grown and
// shrunk by a micrometre. Borderline pairs (a 1e-6 m question) are left out.
std::optional<bool> clear_verdict(const OrientedBox& a, const OrientedBox& b) {
  const bool small = reference_overlaps(grown(a, -1e-6), grown(b, -1e-6));
  const bool large = reference_overlaps(grown(a, 1e-6), grown(b, 1e-6));
  if (small != large) return std::nullopt;
  return small;
}

struct RandomBoxes {
  std::mt19937_64 rng{20240601};
  std::uniform_real_distribution<double> position{-6.0, 6.0};
  std::uniform_real_distribution<double> heading{-kPi, kPi};
  std::uniform_real_distribution<double> size{0.2, 8.0};
  OrientedBox next() { return box(position(rng), position(rng), heading(rng), size(rng), size(rng)); }
};

OrientedBox moved(const OrientedBox& b, double rotation_rad, Vec2 shift) {
  const double c = std::cos(rotation_rad), s = std::sin(rotation_rad);
  return box(c * b.center.x - s * b.center.y + shift.x, s * b.center.x + c * b.center.y + shift.y,
             b.heading_rad + rotation_rad, b.length_m, b.width_m);
}

bool inside_or_on(const OrientedBox& b, Vec2 p, double tolerance_m) {
  const Vec2 u = Vec2::unit(b.heading_rad);
  const Vec2 n{-u.y, u.x};
  const Vec2 d = p - b.center;
  return std::abs(d.dot(u)) <= b.length_m / 2 + tolerance_m && std::abs(d.dot(n)) <= b.width_m / 2 + tolerance_m;
}

// ---- corners -------------------------------------------------------------------------------------

TEST(OrientedBox, CornersAreCounterClockwiseFromFrontRight) {
  const auto c = box(1.0, 2.0, 0.0, 4.0, 2.0).corners();
  EXPECT_EQ(c[0], (Vec2{3.0, 1.0}));  // front-right
  EXPECT_EQ(c[1], (Vec2{3.0, 3.0}));  // front-left
  EXPECT_EQ(c[2], (Vec2{-1.0, 3.0}));
  EXPECT_EQ(c[3], (Vec2{-1.0, 1.0}));
}

TEST(OrientedBox, CornersFollowTheHeading) {
  // Heading -y (the truck): its front is its lowest y edge, its right side faces -x.
  const auto c = box(0.0, 0.0, -kPi / 2, 10.0, 2.5).corners();
  EXPECT_NEAR(c[0].x, -1.25, 1e-12);
  EXPECT_NEAR(c[0].y, -5.0, 1e-12);
  EXPECT_NEAR(c[1].x, 1.25, 1e-12);
  EXPECT_NEAR(c[1].y, -5.0, 1e-12);
  EXPECT_NEAR(c[2].y, 5.0, 1e-12);
}

TEST(OrientedBox, CornersAgreeWithTheLibrarysTrigonometryAtAnyHeading) {
  // The box code evaluates sin/cos itself (for speed); it must agree with <cmath> to rounding.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> heading(-60.0, 60.0);
  for (int i = 0; i < 20000; ++i) {
    const double h = i < 10000 ? heading(rng) : heading(rng) * 2e4;  // beyond 8e5 rad: the library
    const auto b = box(3.0, -4.0, h, 4.0, 2.0);
    const Vec2 u{std::cos(h), std::sin(h)};
    const Vec2 n{-u.y, u.x};
    const Vec2 front_right = b.center + u * 2.0 - n * 1.0;
    const auto c = b.corners();
    ASSERT_NEAR(c[0].x, front_right.x, 1e-14) << h;
    ASSERT_NEAR(c[0].y, front_right.y, 1e-14) << h;
  }
  for (const double h : {0.0, kPi / 2, -kPi / 2, kPi, -kPi, kPi / 4}) {
    const auto c = box(0, 0, h, 2, 0).corners();
    EXPECT_NEAR(c[0].x, std::cos(h), 2e-16) << h;
    EXPECT_NEAR(c[0].y, std::sin(h), 2e-16) << h;
  }
}

// ---- overlaps: hand cases ------------------------------------------------------------------------

TEST(Overlaps, AxisAlignedBoxesOverlapOnlyWhenTheirExtentsDo) {
  const auto a = box(0, 0, 0, 4, 2);
  EXPECT_TRUE(overlaps(a, box(3.9, 0, 0, 4, 2)));
  EXPECT_FALSE(overlaps(a, box(4.1, 0, 0, 4, 2)));
  EXPECT_TRUE(overlaps(a, box(0, 1.9, 0, 4, 2)));
  EXPECT_FALSE(overlaps(a, box(0, 2.1, 0, 4, 2)));
  EXPECT_FALSE(overlaps(a, box(4.1, 2.1, 0, 4, 2)));
  EXPECT_TRUE(overlaps(a, box(3.9, -1.9, 0, 4, 2)));
}

TEST(Overlaps, TouchingEdgesAndCornersCountAsOverlap) {
  const auto a = box(0, 0, 0, 4, 2);
  EXPECT_TRUE(overlaps(a, box(4.0, 0, 0, 4, 2)));        // edge to edge
  EXPECT_TRUE(overlaps(a, box(0, -2.0, 0, 4, 2)));       // side to side
  EXPECT_TRUE(overlaps(a, box(4.0, 2.0, 0, 4, 2)));      // corner to corner
  EXPECT_TRUE(overlaps(a, box(3.0, 0, kPi / 2, 2, 2)));  // turned square, edge to edge
}

TEST(Overlaps, DiamondAgainstSquareSeparatesAtItsCorner) {
  // A 2 m square and a 2 m square turned 45°: its corner reaches √2 from its centre.
  const auto square = box(0, 0, 0, 2, 2);
  const double contact_x = 1.0 + std::sqrt(2.0);
  EXPECT_TRUE(overlaps(square, box(contact_x - 1e-6, 0, kPi / 4, 2, 2)));
  EXPECT_FALSE(overlaps(square, box(contact_x + 1e-6, 0, kPi / 4, 2, 2)));
  EXPECT_TRUE(overlaps(square, box(0, -contact_x + 1e-6, -kPi / 4, 2, 2)));
  EXPECT_FALSE(overlaps(square, box(0, -contact_x - 1e-6, -kPi / 4, 2, 2)));
}

TEST(Overlaps, ThinDiagonalBoxIsSeparatedAlongItsOwnNormal) {
  // A 4 × 0.2 m box along y = x, and a unit square whose nearest corner (c − ½, ½ − c) is
  // |2c − 1|/√2 from that line: they touch at c = ½ + 0.05·√2, though their bounding boxes overlap.
  const auto diagonal = box(0, 0, kPi / 4, 4.0, 0.2);
  const double c = 0.5 + 0.05 * std::sqrt(2.0);
  EXPECT_TRUE(overlaps(diagonal, box(c - 1e-6, -(c - 1e-6), 0, 1, 1)));
  EXPECT_FALSE(overlaps(diagonal, box(c + 1e-6, -(c + 1e-6), 0, 1, 1)));
  EXPECT_FALSE(overlaps(diagonal, box(1.2, -1.2, 0, 1, 1)));
}

TEST(Overlaps, BoxInsideAnotherOverlapsBothWays) {
  const auto big = box(0, 0, 0.2, 10, 10);
  const auto small = box(1, 2, 0.3, 1, 0.5);
  EXPECT_TRUE(overlaps(big, small));
  EXPECT_TRUE(overlaps(small, big));
  EXPECT_TRUE(overlaps(small, small));
}

TEST(Overlaps, CarFrontAgainstTruckSide) {
  // The scene's layout: ego heading +x, truck heading −y with its near side at x = d.
  const double d = 5.0;
  const auto truck = box(d + 1.25, 0.0, -kPi / 2, 10.0, 2.5);
  EXPECT_FALSE(overlaps(box(d - 2.254 - 0.01, -1.75, 0, 4.508, 1.61), truck));
  EXPECT_TRUE(overlaps(box(d - 2.254 + 0.01, -1.75, 0, 4.508, 1.61), truck));
  EXPECT_FALSE(overlaps(box(d + 1.0, -5.0 - 0.805 - 0.01, 0, 4.508, 1.61), truck));  // passes below its front
}

// ---- overlaps: properties ------------------------------------------------------------------------

TEST(Overlaps, AgreesWithBruteForcePolygonIntersection) {
  RandomBoxes random;
  int compared = 0, overlapping = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto a = random.next();
    const auto b = random.next();
    const auto expected = clear_verdict(a, b);
    if (!expected) continue;
    ++compared;
    overlapping += *expected;
    ASSERT_EQ(overlaps(a, b), *expected) << "case " << i;
  }
  // Both verdicts must be well represented for the comparison to mean something.
  EXPECT_GT(compared, 19900);
  EXPECT_GT(overlapping, 3000);
  EXPECT_GT(compared - overlapping, 3000);
}

TEST(Overlaps, IsSymmetric) {
  RandomBoxes random;
  for (int i = 0; i < 20000; ++i) {
    const auto a = random.next();
    const auto b = random.next();
    ASSERT_EQ(overlaps(a, b), overlaps(b, a)) << "case " << i;
  }
}

TEST(Overlaps, IsInvariantUnderACommonRigidMotion) {
  RandomBoxes random;
  std::uniform_real_distribution<double> angle(-kPi, kPi), shift(-100.0, 100.0);
  for (int i = 0; i < 20000; ++i) {
    const auto a = random.next();
    const auto b = random.next();
    if (!clear_verdict(a, b)) continue;
    const double rotation = angle(random.rng);
    const Vec2 offset{shift(random.rng), shift(random.rng)};
    ASSERT_EQ(overlaps(a, b), overlaps(moved(a, rotation, offset), moved(b, rotation, offset))) << "case " << i;
  }
}

// ---- contact -------------------------------------------------------------------------------------

TEST(Contact, ApartBoxesDoNotTouch) {
  const auto c = contact(box(0, 0, 0, 4, 2), box(5, 0, 0, 4, 2));
  EXPECT_FALSE(c.touching);
  EXPECT_EQ(c.depth_m, 0.0);
}

TEST(Contact, AxisAlignedPenetrationGivesNormalFromAToBAndDepth) {
  const auto a = box(0, 0, 0, 4, 2);
  auto c = contact(a, box(3.5, 0, 0, 4, 2));
  ASSERT_TRUE(c.touching);
  EXPECT_NEAR(c.normal.x, 1.0, 1e-12);
  EXPECT_NEAR(c.normal.y, 0.0, 1e-12);
  EXPECT_NEAR(c.depth_m, 0.5, 1e-12);
  EXPECT_NEAR(c.point.x, 1.75, 1e-12);  // the middle of the overlap x ∈ [1.5, 2], y ∈ [−1, 1]
  EXPECT_NEAR(c.point.y, 0.0, 1e-12);

  c = contact(a, box(-3.5, 0.5, 0, 4, 2));
  EXPECT_NEAR(c.normal.x, -1.0, 1e-12);
  EXPECT_NEAR(c.depth_m, 0.5, 1e-12);
  EXPECT_NEAR(c.point.y, 0.25, 1e-12);  // the overlapping stretch is y ∈ [−0.5, 1]

  c = contact(a, box(0.3, 1.8, 0, 4, 2));
  EXPECT_NEAR(c.normal.y, 1.0, 1e-12);
  EXPECT_NEAR(c.depth_m, 0.2, 1e-12);
}

TEST(Contact, CornerOfADiamondIsTheContactPoint) {
  const auto square = box(0, 0, 0, 2, 2);
  const auto diamond = box(1.0 + std::sqrt(2.0) - 0.1, 0.0, kPi / 4, 2, 2);
  const auto c = contact(square, diamond);
  ASSERT_TRUE(c.touching);
  EXPECT_NEAR(c.depth_m, 0.1, 1e-12);
  EXPECT_NEAR(c.normal.x, 1.0, 1e-12);
  // The overlap is the diamond's tip, a triangle (0.9, 0), (1, ±0.1): the point is its centroid (to
  // the slop, by which both boxes grow for it).
  EXPECT_NEAR(c.point.x, 1.0 - 0.1 / 3.0, kContactSlop_m);
  EXPECT_NEAR(c.point.y, 0.0, 1e-12);

  // The other way round the normal flips and the point stays.
  const auto r = contact(diamond, square);
  EXPECT_NEAR(r.normal.x, -1.0, 1e-12);
  EXPECT_NEAR(r.depth_m, 0.1, 1e-12);
  EXPECT_NEAR(r.point.x, c.point.x, 1e-12);
}

TEST(Contact, CarFrontIntoTruckSideIsCentralOnTheBumper) {
  const auto ego = box(-2.254 + 0.3, -1.75, 0, 4.508, 1.61);  // front bumper 0.3 m into the truck
  const auto truck = box(1.25, 0.0, -kPi / 2, 10.0, 2.5);     // near side at x = 0
  const auto c = contact(ego, truck);
  ASSERT_TRUE(c.touching);
  EXPECT_NEAR(c.normal.x, 1.0, 1e-12);
  EXPECT_NEAR(c.depth_m, 0.3, 1e-12);
  EXPECT_NEAR(c.point.x, 0.15, 1e-12);   // the middle of the 0.3 m deep overlap
  EXPECT_NEAR(c.point.y, -1.75, 1e-12);  // on the line of the ego's CG: r × n = 0
}

// A car's front against a truck's side, the car turned by `tilt` and placed so that its deepest
// corner is `depth` into the truck (the moment a contact is timed, by bisection, to micrometres).
OrientedBox car_into_side(double tilt_rad, double depth_m) {
  const double length = 4.508, width = 1.61;
  const double reach = length / 2 * std::cos(tilt_rad) + width / 2 * std::abs(std::sin(tilt_rad));
  return box(depth_m - reach, -1.75, tilt_rad, length, width);
}
const OrientedBox kTruckSide = box(1.25, 0.0, -kPi / 2, 10.0, 2.5);  // near side at x = 0

// The point is well-conditioned in the heading: faces parallel to rounding (a recorded heading is
// never exact) give the point exactly parallel faces give, the middle of the bumper, and a larger
// tilt moves it towards the leading corner at a bounded rate whatever the depth. (The overlap's own
// centroid moved W²/(12·depth) per radian of tilt: without bound at the moment of first touch,
// where the depth is micrometres and a tilt of 1e-7 rad put it at the corner.)
TEST(Contact, PointIsContinuousAsTheFacesTurnParallel) {
  for (const double depth : {1e-9, 1e-6, 1e-4}) {
    const Contact parallel = contact(car_into_side(0.0, depth), kTruckSide);
    ASSERT_TRUE(parallel.touching);
    EXPECT_NEAR(parallel.point.x, depth / 2, 1e-12);
    EXPECT_NEAR(parallel.point.y, -1.75, 1e-12);  // the middle of the bumper
    for (const double sign : {1.0, -1.0}) {
      for (double tilt = 1e-12; tilt <= 1e-7; tilt *= 10) {
        const Contact c = contact(car_into_side(sign * tilt, depth), kTruckSide);
        ASSERT_TRUE(c.touching);
        EXPECT_LT((c.point - parallel.point).norm(), 2e-5) << "tilt " << sign * tilt << " depth " << depth;
      }
      Vec2 previous = parallel.point;
      const double step = 1e-7;
      for (int k = 1; k * step <= 0.01; ++k) {
        const Contact c = contact(car_into_side(sign * k * step, depth), kTruckSide);
        ASSERT_TRUE(c.touching);
        ASSERT_LT((c.point - previous).norm(), 1000.0 * step) << "tilt " << sign * k * step << " depth " << depth;
        previous = c.point;
      }
      // At 0.1 rad, by the leading corner.
      const OrientedBox car = car_into_side(sign * 0.1, depth);
      Vec2 corner = car.corners()[0];
      for (const Vec2& k : car.corners())
        if (k.x > corner.x) corner = k;
      EXPECT_LT((contact(car, kTruckSide).point - corner).norm(), 0.02) << depth;
    }
  }
}

TEST(Contact, TouchingBoxesHaveZeroDepth) {
  const auto c = contact(box(0, 0, 0, 4, 2), box(4, 0, 0, 4, 2));
  EXPECT_TRUE(c.touching);
  EXPECT_NEAR(c.depth_m, 0.0, 1e-12);
  EXPECT_NEAR(c.point.x, 2.0, 1e-12);
}

TEST(Contact, AgreesWithOverlapsAndIsTheMinimumTranslation) {
  RandomBoxes random;
  int touching = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto a = random.next();
    const auto b = random.next();
    const auto c = contact(a, b);
    ASSERT_EQ(c.touching, overlaps(a, b)) << "case " << i;  // exactly, borderline cases included
    if (!c.touching || !clear_verdict(a, b)) continue;
    ++touching;
    ASSERT_NEAR(c.normal.norm(), 1.0, 1e-12);
    ASSERT_GE(c.normal.dot(b.center - a.center), -1e-12) << "normal points from a to b";
    ASSERT_GE(c.depth_m, 0.0);
    // Pushing b out along the normal by the depth separates them; by less it cannot.
    auto pushed = b;
    pushed.center = b.center + c.normal * (c.depth_m + 1e-6);
    ASSERT_FALSE(overlaps(a, pushed)) << "case " << i;
    if (c.depth_m > 1e-5) {
      pushed.center = b.center + c.normal * (c.depth_m - 1e-5);
      ASSERT_TRUE(overlaps(a, pushed)) << "case " << i;
    }
    // The point lies in both boxes (to the slop), and swapping them flips the normal only.
    ASSERT_TRUE(inside_or_on(a, c.point, kContactSlop_m + 1e-9)) << "case " << i;
    ASSERT_TRUE(inside_or_on(b, c.point, kContactSlop_m + 1e-9)) << "case " << i;
    const auto swapped = contact(b, a);
    ASSERT_TRUE(swapped.touching);
    ASSERT_NEAR(swapped.depth_m, c.depth_m, 1e-9) << "case " << i;
    ASSERT_NEAR(swapped.point.x, c.point.x, 1e-9) << "case " << i;
    ASSERT_NEAR(swapped.point.y, c.point.y, 1e-9) << "case " << i;
  }
  EXPECT_GT(touching, 3000);
}

}  // namespace geometry_test
}  // namespace emrm::core

namespace emrm::core {
namespace geometry_test {

TEST(TimeToOverlap, HeadOnClosingGivesGapOverClosingSpeed) {
  const OrientedBox a{{0.0, 0.0}, 0.0, 2.0, 1.0};
  const OrientedBox b{{10.0, 0.0}, 0.0, 2.0, 1.0};
  const auto ttc = time_to_overlap(a, {4.0, 0.0}, b, {0.0, 0.0}, 10.0);
  ASSERT_TRUE(ttc.has_value());
  EXPECT_NEAR(*ttc, 8.0 / 4.0, 1e-12);
  EXPECT_NEAR(*time_to_overlap(a, {4.0, 0.0}, b, {-4.0, 0.0}, 10.0), 1.0, 1e-12);
}

TEST(TimeToOverlap, MissesBeyondTheHorizonOrSidewaysAreNothing) {
  const OrientedBox a{{0.0, 0.0}, 0.0, 2.0, 1.0};
  const OrientedBox b{{10.0, 3.0}, 0.0, 2.0, 1.0};
  EXPECT_FALSE(time_to_overlap(a, {4.0, 0.0}, b, {0.0, 0.0}, 10.0).has_value());   // passes beside
  EXPECT_FALSE(time_to_overlap(a, {1.0, 0.3}, b, {0.0, 0.0}, 5.0).has_value());    // too late
  EXPECT_FALSE(time_to_overlap(a, {-4.0, 0.0}, b, {0.0, 0.0}, 10.0).has_value());  // moving away
}

TEST(TimeToOverlap, OverlappingBoxesHaveZero) {
  const OrientedBox a{{0.0, 0.0}, 0.3, 2.0, 1.0};
  EXPECT_EQ(*time_to_overlap(a, {0.0, 0.0}, a, {1.0, 0.0}, 1.0), 0.0);
}

TEST(TimeToOverlap, AgreesWithSampledSeparatingAxisTests) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> pos(-10.0, 10.0), ang(-3.1, 3.1), size(0.5, 5.0), vel(-5.0, 5.0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const OrientedBox a{{pos(rng), pos(rng)}, ang(rng), size(rng), size(rng)};
    const OrientedBox b{{pos(rng), pos(rng)}, ang(rng), size(rng), size(rng)};
    const Vec2 va{vel(rng), vel(rng)};
    const Vec2 vb{vel(rng), vel(rng)};
    const auto ttc = time_to_overlap(a, va, b, vb, 4.0);
    // First sampled overlap, 1 ms resolution.
    std::optional<double> sampled;
    for (int k = 0; k <= 4000 && !sampled; ++k) {
      const double t = k * 1e-3;
      OrientedBox a_t = a, b_t = b;
      a_t.center = a.center + va * t;
      b_t.center = b.center + vb * t;
      if (overlaps(a_t, b_t)) sampled = t;
    }
    ASSERT_EQ(ttc.has_value(), sampled.has_value()) << i;
    if (ttc) {
      ++hits;
      EXPECT_LE(*ttc, *sampled + 1e-9) << i;
      EXPECT_GE(*ttc, *sampled - 1e-3 - 1e-9) << i;
    }
  }
  EXPECT_GT(hits, 100);
}

// wrap_angle skips the library within ±3 rad: it must be remainder(x, 2 pi) bit for bit everywhere.
TEST(WrapAngle, IsTheLibraryRemainderBitForBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-20.0, 20.0);
  std::vector<double> xs{0.0, -0.0, 3.0, -3.0, std::nextafter(3.0, 4.0), kPi, -kPi, 2 * kPi, 1e6};
  for (int i = 0; i < 10000; ++i) xs.push_back(angle(rng));
  for (double x : xs) {
    const double expected = std::remainder(x, 2.0 * kPi);
    const double got = wrap_angle(x);
    EXPECT_EQ(std::signbit(got), std::signbit(expected)) << x;
    EXPECT_EQ(got, expected) << x;
  }
}

}  // namespace geometry_test
}  // namespace emrm::core
