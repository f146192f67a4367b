#include "emrm/core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "emrm/core/trig.hpp"

namespace emrm::core {
namespace {

// Both headings at once: two independent dependency chains that the processor overlaps.
[[gnu::always_inline]] inline std::array<CosSin, 2> cos_sin_pair(double x0, double x1) noexcept {
  if (!(std::abs(x0) < kFastAngleLimit && std::abs(x1) < kFastAngleLimit)) return {cos_sin(x0), cos_sin(x1)};
  return {cos_sin_kernel(x0), cos_sin_kernel(x1)};
}

// A box with its axes worked out once: one sin/cos per box per call.
struct Frame {
  Vec2 center;
  Vec2 axis;    // unit vector along the heading (length direction)
  Vec2 normal;  // unit vector to the left of the heading (width direction)
  double half_length = 0.0;
  double half_width = 0.0;
};

Frame frame_of(const OrientedBox& b) noexcept {
  const auto [c, s] = cos_sin(b.heading_rad);
  return {b.center, {c, s}, {-s, c}, 0.5 * b.length_m, 0.5 * b.width_m};
}

// Half-extent of box `f` projected on the unit direction `dir`.
double radius_along(const Frame& f, Vec2 dir) noexcept {
  return f.half_length * std::abs(f.axis.dot(dir)) + f.half_width * std::abs(f.normal.dot(dir));
}

std::array<Vec2, 4> corners_of(const Frame& f) noexcept {
  const Vec2 along = f.axis * f.half_length;
  const Vec2 across = f.normal * f.half_width;
  return {f.center + along - across, f.center + along + across, f.center - along + across, f.center - along - across};
}

// The four outward face normals of a box, in the order of corners_of's edges:
// front (FR→FL), left (FL→RL), rear (RL→RR), right (RR→FR).
std::array<Vec2, 4> face_normals_of(const Frame& f) noexcept { return {f.axis, f.normal, -f.axis, -f.normal}; }

// A convex polygon of at most 8 vertices: a quadrilateral clipped by four half-planes.
struct Polygon {
  std::array<Vec2, 8> vertices{};
  std::size_t count = 0;
};

// b's rectangle clipped to a's (Sutherland–Hodgman).
Polygon overlap_polygon(const Frame& a, const Frame& b) noexcept {
  Polygon current;
  for (const Vec2& c : corners_of(b)) current.vertices[current.count++] = c;
  for (const Vec2& n : face_normals_of(a)) {
    const double limit = a.center.dot(n) + radius_along(a, n);
    Polygon next;
    for (std::size_t i = 0; i < current.count; ++i) {
      const Vec2 p = current.vertices[i];
      const Vec2 q = current.vertices[(i + 1) % current.count];
      const double sp = p.dot(n) - limit;
      const double sq = q.dot(n) - limit;
      // A convex polygon gains at most one vertex per clip; the bound only guards against
      // rounding making a degenerate sliver look non-convex.
      if (sp <= 0.0 && next.count < next.vertices.size()) next.vertices[next.count++] = p;
      if (((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0)) && next.count < next.vertices.size())
        next.vertices[next.count++] = p + (q - p) * (sp / (sp - sq));
    }
    current = next;
    if (current.count == 0) break;
  }
  return current;
}

// The box with every side moved out by `margin_m`.
Frame grown(Frame f, double margin_m) noexcept {
  f.half_length += margin_m;
  f.half_width += margin_m;
  return f;
}

// Area centroid, or the mean of the vertices when the region has no area.
Vec2 centroid(const Polygon& poly) noexcept {
  Vec2 mean;
  for (std::size_t i = 0; i < poly.count; ++i) mean = mean + poly.vertices[i];
  mean = mean * (1.0 / static_cast<double>(poly.count));
  double twice_area = 0.0;
  Vec2 weighted;
  for (std::size_t i = 0; i < poly.count; ++i) {
    // Relative to the mean, for accuracy far from the origin.
    const Vec2 p = poly.vertices[i] - mean;
    const Vec2 q = poly.vertices[(i + 1) % poly.count] - mean;
    const double w = p.cross(q);
    twice_area += w;
    weighted = weighted + (p + q) * w;
  }
  if (std::abs(twice_area) <= 1e-12) return mean;
  return mean + weighted * (1.0 / (3.0 * twice_area));
}

// Only reached if rounding lost a region a millimetre thick: b's corner furthest into a.
Vec2 deepest_corner(const Frame& b, Vec2 normal) noexcept {
  const auto corners = corners_of(b);
  std::size_t deepest = 0;
  for (std::size_t i = 1; i < 4; ++i)
    if (corners[i].dot(normal) < corners[deepest].dot(normal)) deepest = i;
  return corners[deepest];
}

}  // namespace

std::array<Vec2, 4> OrientedBox::corners() const { return corners_of(frame_of(*this)); }

bool overlaps(const OrientedBox& a, const OrientedBox& b) noexcept {
  const double ahl = 0.5 * a.length_m;
  const double ahw = 0.5 * a.width_m;
  const double bhl = 0.5 * b.length_m;
  const double bhw = 0.5 * b.width_m;
  const Vec2 d = b.center - a.center;
  const double dist2 = d.dot(d);

  // Far apart: no trigonometry needed, and this is the common case in a simulation (the ego is
  // far from the truck for most of its steps). With circumradii r_a, r_b the boxes are apart when
  // |d| > r_a + r_b, and (r_a + r_b)² ≤ 2 (r_a² + r_b²) gives a test without square roots. The
  // hair of slack keeps rounding from ever rejecting boxes that touch.
  const double reach2 = 2.0 * (ahl * ahl + ahw * ahw + bhl * bhl + bhw * bhw);
  if (dist2 > reach2 * (1.0 + 1e-12)) return false;

  const auto [cs_a, cs_b] = cos_sin_pair(a.heading_rad, b.heading_rad);
  const double ca = cs_a.cos, sa = cs_a.sin, cb = cs_b.cos, sb = cs_b.sin;
  // In 2-D, a's axes against b's axes are just cos and sin of the relative heading.
  const double cos_rel = std::abs(ca * cb + sa * sb);
  const double sin_rel = std::abs(ca * sb - sa * cb);

  // Separated only when the gap is strictly positive: touching boxes overlap.
  if (std::abs(d.x * ca + d.y * sa) > ahl + bhl * cos_rel + bhw * sin_rel) return false;
  if (std::abs(-d.x * sa + d.y * ca) > ahw + bhl * sin_rel + bhw * cos_rel) return false;
  if (std::abs(d.x * cb + d.y * sb) > bhl + ahl * cos_rel + ahw * sin_rel) return false;
  return std::abs(-d.x * sb + d.y * cb) <= bhw + ahl * sin_rel + ahw * cos_rel;
}

double separation_lower_bound(const OrientedBox& a, const OrientedBox& b) noexcept {
  const double ahl = 0.5 * a.length_m;
  const double ahw = 0.5 * a.width_m;
  const double bhl = 0.5 * b.length_m;
  const double bhw = 0.5 * b.width_m;
  const Vec2 d = b.center - a.center;
  const auto [cs_a, cs_b] = cos_sin_pair(a.heading_rad, b.heading_rad);
  const double ca = cs_a.cos, sa = cs_a.sin, cb = cs_b.cos, sb = cs_b.sin;
  const double cos_rel = std::abs(ca * cb + sa * sb);
  const double sin_rel = std::abs(ca * sb - sa * cb);
  return std::max({std::abs(d.x * ca + d.y * sa) - (ahl + bhl * cos_rel + bhw * sin_rel),
                   std::abs(-d.x * sa + d.y * ca) - (ahw + bhl * sin_rel + bhw * cos_rel),
                   std::abs(d.x * cb + d.y * sb) - (bhl + ahl * cos_rel + ahw * sin_rel),
                   std::abs(-d.x * sb + d.y * cb) - (bhw + ahl * sin_rel + ahw * cos_rel)});
}

Contact contact(const OrientedBox& a, const OrientedBox& b) noexcept {
  // The verdict is overlaps()'s own, so that a caller who found a collision with overlaps() always
  // gets a contact for it, whatever the rounding below.
  if (!overlaps(a, b)) return {};
  const Frame fa = frame_of(a);
  const Frame fb = frame_of(b);
  const Vec2 d = fb.center - fa.center;

  // Penetration along each of the four candidate axes; the smallest one is the contact normal.
  const std::array<Vec2, 4> axes{fa.axis, fa.normal, fb.axis, fb.normal};
  double best_depth = std::numeric_limits<double>::infinity();
  int best = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec2 axis = axes[static_cast<std::size_t>(i)];
    const double depth = std::max(radius_along(fa, axis) + radius_along(fb, axis) - std::abs(d.dot(axis)), 0.0);
    // a's axes win ties (strictly smaller needed to switch), so the normal of a face-to-face
    // contact of parallel boxes does not depend on rounding.
    if (depth < best_depth - 1e-12) {
      best_depth = depth;
      best = i;
    }
  }

  Contact out;
  out.touching = true;
  out.depth_m = best_depth;
  const Vec2 axis = axes[static_cast<std::size_t>(best)];
  out.normal = d.dot(axis) >= 0.0 ? axis : -axis;

  // The point is the centroid of the region within kContactSlop_m of both boxes (their overlap,
  // each grown by the slop): inside both to the slop however deep the penetration, the same for
  // contact(a, b) and contact(b, a), in the middle of the overlap for a face-to-face contact and on
  // the struck face for a corner hit. The slop keeps it well-conditioned: the overlap's own centroid
  // jumps from the middle of two faces to a corner at the slightest tilt between them (a shallow
  // overlap of tilted faces is a triangle at one end), and a recorded heading is never exact; the
  // region is never thinner than twice the slop, so its centroid moves continuously with the tilt.
  // Parallel faces give the overlap's own centroid (the region grows equally on every side).
  const Polygon region = overlap_polygon(grown(fa, kContactSlop_m), grown(fb, kContactSlop_m));
  out.point = region.count > 0 ? centroid(region) : deepest_corner(fb, out.normal);
  return out;
}

std::optional<double> time_to_overlap(const OrientedBox& a, Vec2 velocity_a, const OrientedBox& b, Vec2 velocity_b,
                                      double horizon_s) noexcept {
  // In b's frame of motion a moves at v; on every separating axis the projections overlap during
  // one time interval; the boxes overlap during the intersection of the four.
  const Vec2 v = velocity_a - velocity_b;
  const auto ca = a.corners();
  const auto cb = b.corners();
  const std::array<Vec2, 4> axes{Vec2::unit(a.heading_rad), Vec2::unit(a.heading_rad + M_PI / 2),
                                 Vec2::unit(b.heading_rad), Vec2::unit(b.heading_rad + M_PI / 2)};
  double enter = 0.0;
  double leave = horizon_s;
  for (const Vec2& n : axes) {
    double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min, b_min = a_min, b_max = -a_min;
    for (const Vec2& c : ca) {
      a_min = std::min(a_min, c.dot(n));
      a_max = std::max(a_max, c.dot(n));
    }
    for (const Vec2& c : cb) {
      b_min = std::min(b_min, c.dot(n));
      b_max = std::max(b_max, c.dot(n));
    }
    const double speed = v.dot(n);
    if (std::abs(speed) < 1e-12) {
      if (a_max < b_min || a_min > b_max) return std::nullopt;
      continue;
    }
    double t0 = (b_min - a_max) / speed;
    double t1 = (b_max - a_min) / speed;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return std::nullopt;
  }
  return enter;
}

}  // namespace emrm::core
