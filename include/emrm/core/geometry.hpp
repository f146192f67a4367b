#pragma once

// Small 2-D geometry: vectors, oriented rectangles and their separating-axis test.
// Everything is in metres and radians, in the road frame (x along the main road, y to the left).

#include <array>
#include <cmath>
#include <optional>

namespace emrm::core {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;

  constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator*(double k) const { return {x * k, y * k}; }
  constexpr Vec2 operator-() const { return {-x, -y}; }
  constexpr bool operator==(const Vec2&) const = default;
  [[nodiscard]] constexpr double dot(Vec2 o) const { return x * o.x + y * o.y; }
  /// z-component of the 3-D cross product.
  [[nodiscard]] constexpr double cross(Vec2 o) const { return x * o.y - y * o.x; }
  [[nodiscard]] double norm() const { return std::hypot(x, y); }
  /// Unit vector at `angle_rad` from +x.
  [[nodiscard]] static Vec2 unit(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }
};

/// A rectangle of `length` along its heading and `width` across it, centred at `center`.
struct OrientedBox {
  Vec2 center;
  double heading_rad = 0.0;
  double length_m = 0.0;
  double width_m = 0.0;

  /// Corners counter-clockwise: front-right, front-left, rear-left, rear-right.
  [[nodiscard]] std::array<Vec2, 4> corners() const;
};

/// True when the two rectangles overlap or touch (separating-axis test on the four edge normals).
[[nodiscard]] bool overlaps(const OrientedBox& a, const OrientedBox& b) noexcept;

/// A lower bound on the distance between two rectangles: the largest gap between their
/// projections on the four edge normals (the separating-axis test's axes). Positive only when
/// they are apart, and never more than their true distance (a projection never lengthens a
/// segment), so a body that moves less than this cannot reach the other: what conservative
/// advancement needs. Zero or negative when they overlap or touch.
[[nodiscard]] double separation_lower_bound(const OrientedBox& a, const OrientedBox& b) noexcept;

/// Two boxes' parts within this of each other count as the contact's region: the contact point is
/// the centroid of their overlap with each grown by it (docs/physics.md, "Impacts and losses").
inline constexpr double kContactSlop_m = 1e-3;

/// Contact between two rectangles found by the separating-axis test.
struct Contact {
  bool touching = false;
  Vec2 normal;         ///< unit, pointing from a towards b, along the axis of least penetration
  double depth_m = 0;  ///< penetration along `normal` (0 when not touching)
  /// A representative contact point: the centroid of the overlap of the two boxes each grown by
  /// kContactSlop_m (inside both to the slop). Continuous in the boxes' poses at any depth: faces
  /// that touch give the middle of their common stretch (exactly the overlap's centroid when they are
  /// parallel), and a tilt between them moves it by at most width²/(12·slop) per radian, where the
  /// bare overlap's centroid jumped to a corner at a tilt of depth/width.
  Vec2 point;
};

/// The contact of a with b; `touching` is exactly overlaps(a, b), and the rest is zero when false.
[[nodiscard]] Contact contact(const OrientedBox& a, const OrientedBox& b) noexcept;

/// Time to collision of two boxes moving at constant velocities: the first τ in [0, horizon] at
/// which they overlap (0 if they already do), or nothing. Exact (swept separating-axis test).
[[nodiscard]] std::optional<double> time_to_overlap(const OrientedBox& a, Vec2 velocity_a, const OrientedBox& b,
                                                    Vec2 velocity_b, double horizon_s) noexcept;

}  // namespace emrm::core
