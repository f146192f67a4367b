#pragma once

// The plan view of an OpenDRIVE road: its reference line as a chain of segments (ASAM OpenDRIVE
// 1.7 §7: line, arc, spiral, poly3, paramPoly3), and the clothoid that OpenSCENARIO trajectories
// reuse. All angles in radians, lengths in metres, curvature positive to the left (1/m).

#include <variant>
#include <vector>

namespace emrm::opendrive {

/// A point and a heading (counter-clockwise from the x axis).
struct Pose {
  double x = 0.0;
  double y = 0.0;
  double heading = 0.0;
};

/// The pose after arc length `s` along the clothoid that leaves `start` with `curvature` (1/m),
/// changing at `curvature_rate` (1/m²): heading(s) = heading + curvature s + curvature_rate s²/2,
/// position the integral of (cos, sin) of it (the Fresnel integrals, evaluated by composite
/// Gauss-Legendre quadrature to about 1e-13 relative). A line when both are 0, an arc when the rate
/// is 0 (both in closed form). `s` may be negative (backwards along the same curve).
/// The one owner of the clothoid: OpenDRIVE spirals and OpenSCENARIO Clothoid trajectories use it.
[[nodiscard]] Pose clothoid(const Pose& start, double curvature, double curvature_rate, double s);

/// The kinds of segment (ASAM OpenDRIVE 1.7 §7.4-§7.7).
struct Line {};
struct Arc {
  double curvature = 0.0;  // 1/m, positive to the left
};
struct Spiral {  // an Euler spiral, curvature linear in s from start to end
  double curvature_start = 0.0;
  double curvature_end = 0.0;
};
struct Poly3 {  // v = a + b u + c u² + d u³ in the local (u along hdg, v to its left) frame
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
};
enum class ParamRange { kArcLength, kNormalized };  // p in [0, length] or [0, 1]
struct ParamPoly3 {                                 // u(p), v(p) cubic in the local frame
  double a_u = 0.0, b_u = 0.0, c_u = 0.0, d_u = 0.0;
  double a_v = 0.0, b_v = 0.0, c_v = 0.0, d_v = 0.0;
  ParamRange range = ParamRange::kNormalized;
};
using Shape = std::variant<Line, Arc, Spiral, Poly3, ParamPoly3>;

/// One <geometry> record: where it starts (s along the road, its pose) and how long it is.
struct Segment {
  double s = 0.0;
  double x = 0.0;
  double y = 0.0;
  double heading = 0.0;
  double length = 0.0;  // > 0
  Shape shape = Line{};
};

/// The reference line: segments in increasing s, the first at s = 0. s is arc length throughout:
/// poly3 and paramPoly3 are evaluated at the curve parameter whose arc length from the segment's
/// start is s - segment.s (inverted numerically; a paramPoly3 whose own length over its p range
/// differs from `length` is stretched to it, so that it ends where its p range ends).
class ReferenceLine {
 public:
  ReferenceLine() = default;
  /// Takes the segments as they are (the reader has checked them: finite, lengths > 0, s in order).
  explicit ReferenceLine(std::vector<Segment> segments);

  [[nodiscard]] const std::vector<Segment>& segments() const { return segments_; }
  /// The last segment's end s (0 without segments).
  [[nodiscard]] double length() const;
  /// The pose at s, s clamped to [0, length()]. Expects at least one segment.
  [[nodiscard]] Pose at(double s) const;
  /// The curvature at s (1/m, positive to the left), s clamped to [0, length()].
  [[nodiscard]] double curvature(double s) const;
  /// The index of the segment that holds s (the later one at a joint).
  [[nodiscard]] std::size_t segment_index(double s) const;

 private:
  // For poly3 and paramPoly3, one per segment (empty for the closed-form kinds): the curve's own
  // arc length over the segment and its parameter at equal steps of it, where Newton's method starts.
  struct ArcLengthTable {
    double own_length = 0.0;
    std::vector<double> parameter;
  };
  std::vector<Segment> segments_;
  std::vector<ArcLengthTable> tables_;
};

}  // namespace emrm::opendrive
