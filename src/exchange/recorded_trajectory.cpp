// Reading a recorded trajectory (recorded_trajectory.hpp): emrm's CSV and esmini's dat2csv output.

#include "emrm/exchange/recorded_trajectory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

#include "emrm/core/error.hpp"
#include "emrm/core/measured.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/family.hpp"
#include "slopes.hpp"

namespace emrm::exchange {
namespace {

using detail::slope;
using detail::stencil;

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

struct Columns {
  std::map<std::string, std::size_t> index;
  [[nodiscard]] std::optional<std::size_t> find(const std::string& name) const {
    const auto it = index.find(name);
    return it == index.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  }
};

class RowReader {
 public:
  RowReader(const core::CsvRecord& record, const std::string& file) : record_(record), file_(file) {}
  [[nodiscard]] double number(std::size_t column, std::string_view name) const {
    const std::string text = trimmed(record_.fields[column]);
    const auto value = core::parse_finite_number(text);
    if (!value)
      throw InputError(where(column), fmt::format("expected a finite number for '{}', got '{}'", name,
                                                  text.size() > 40 ? text.substr(0, 40) + "…" : text));
    return *value;
  }
  [[nodiscard]] std::string text(std::size_t column) const { return trimmed(record_.fields[column]); }
  [[nodiscard]] SourceLocation where(std::size_t column) const {
    return {file_, record_.lines[column], record_.columns[column]};
  }

 private:
  const core::CsvRecord& record_;
  const std::string& file_;
};

Columns header_of(const core::CsvRecord& header) {
  Columns c;
  for (std::size_t i = 0; i < header.fields.size(); ++i) c.index.emplace(trimmed(header.fields[i]), i);
  return c;
}

std::size_t require_column(const Columns& c, const std::string& name, const core::CsvRecord& header,
                           const std::string& file, std::string_view expected) {
  if (auto i = c.find(name)) return *i;
  throw InputError({file, header.lines.front(), 1},
                   fmt::format("expected a column '{}' in the header (columns: {})", name, expected));
}

void check_time(const RecordedTrajectory& out, double t, const RowReader& r, std::size_t column) {
  if (!out.samples.empty() && !(t > out.samples.back().t_s))
    throw InputError(r.where(column), fmt::format("expected a time after the previous sample's {} s, got {} s",
                                                  out.samples.back().t_s, t));
}

// The speed as read: the dither of a car at rest is 0 (core/measured.hpp); below it, refused.
double checked_speed(double v, const RowReader& r, std::size_t column) {
  const auto speed = core::measured_speed_mps(v);
  if (!speed) throw InputError(r.where(column), core::measured_speed_refusal(v));
  return *speed;
}

// Headings continuous from sample to sample, so that interpolation turns the short way.
void unwrap(RecordedTrajectory& t) {
  for (std::size_t k = 1; k < t.samples.size(); ++k) {
    auto& s = t.samples[k];
    const auto& p = t.samples[k - 1];
    s.yaw_rad = p.yaw_rad + std::remainder(s.yaw_rad - p.yaw_rad, 2.0 * std::numbers::pi);
    s.truck_yaw_rad = p.truck_yaw_rad + std::remainder(s.truck_yaw_rad - p.truck_yaw_rad, 2.0 * std::numbers::pi);
  }
}

// A file in the other format than the one asked for says so, with the flag that reads it: esmini's
// dat2csv output (a "Version:" line, or the columns time, name and h) read as emrm's CSV, or
// emrm's (t, psi and v) read as esmini's.
void refuse_the_other_format(const core::CsvRecord& header, const std::string& file, bool reading_esmini) {
  const Columns c = header_of(header);
  const bool esmini =
      trimmed(header.fields.front()).rfind("Version:", 0) == 0 || (c.find("time") && c.find("name") && c.find("h"));
  const bool emrm = c.find("t") && c.find("psi") && c.find("v");
  if (!reading_esmini && esmini && !emrm)
    throw InputError({file, header.lines.front(), 1},
                     "expected emrm's trajectory CSV (columns t, x, y, psi, v), got esmini's dat2csv output "
                     "(columns time, id, name, x, y, h, …): pass --format esmini to read it");
  if (reading_esmini && emrm && !esmini)
    throw InputError({file, header.lines.front(), 1},
                     "expected esmini's dat2csv output (columns time, id, name, x, y, h, …), got emrm's trajectory "
                     "CSV (columns t, x, y, psi, v): leave out --format esmini to read it");
}

RecordedTrajectory parse_emrm(const std::vector<core::CsvRecord>& records, const std::string& file) {
  constexpr std::string_view kExpected = "t, x, y, psi, v; optional truck_x, truck_y, truck_psi, steer";
  const core::CsvRecord& header = records.front();
  refuse_the_other_format(header, file, false);
  const Columns c = header_of(header);
  const std::size_t t = require_column(c, "t", header, file, kExpected);
  const std::size_t x = require_column(c, "x", header, file, kExpected);
  const std::size_t y = require_column(c, "y", header, file, kExpected);
  const std::size_t psi = require_column(c, "psi", header, file, kExpected);
  const std::size_t v = require_column(c, "v", header, file, kExpected);
  const auto tx = c.find("truck_x");
  const auto ty = c.find("truck_y");
  const auto tpsi = c.find("truck_psi");
  const auto steer = c.find("steer");
  RecordedTrajectory out;
  out.file = file;
  out.has_truck = tx || ty || tpsi;
  if (out.has_truck) {
    for (const char* name : {"truck_x", "truck_y", "truck_psi"})
      (void)require_column(c, name, header, file, "truck_x, truck_y and truck_psi together");
  }
  out.has_steer = steer.has_value();
  for (std::size_t k = 1; k < records.size(); ++k) {
    const core::CsvRecord& row = records[k];
    core::check_row_length(row, header.fields.size(), file);
    const RowReader r(row, file);
    TrajectorySample s;
    s.t_s = r.number(t, "t");
    s.x_m = r.number(x, "x");
    s.y_m = r.number(y, "y");
    s.yaw_rad = r.number(psi, "psi");
    s.speed_mps = checked_speed(r.number(v, "v"), r, v);
    if (steer) s.steer_rad = r.number(*steer, "steer");
    if (out.has_truck) {
      s.truck_x_m = r.number(*tx, "truck_x");
      s.truck_y_m = r.number(*ty, "truck_y");
      s.truck_yaw_rad = r.number(*tpsi, "truck_psi");
    }
    check_time(out, s.t_s, r, t);
    out.samples.push_back(s);
  }
  return out;
}

// esmini's `speed` is the reference point's (the rear axle's) distance along the trajectory over
// the last frame, a backward difference that its last frame does not update; the CG's speed comes
// instead from the CG's recorded positions, as the slope of the parabola through each sample and
// its neighbours (a central difference on esmini's even frames), as the yaw rate does. A last
// sample where the car did not move from the one before is at rest.
void speeds_from_positions(std::vector<TrajectorySample>& samples) {
  const std::size_t n = samples.size();
  if (n < 2) return;  // too short to judge: parse_trajectory_csv says so
  for (std::size_t k = 0; k < n; ++k) {
    const auto [first, points] = stencil(k, n);
    double ts[3], xs[3], ys[3];
    for (int j = 0; j < points; ++j) {
      const auto& p = samples[first + static_cast<std::size_t>(j)];
      ts[j] = p.t_s;
      xs[j] = p.x_m;
      ys[j] = p.y_m;
    }
    samples[k].speed_mps = std::hypot(slope(ts, xs, points, samples[k].t_s), slope(ts, ys, points, samples[k].t_s));
  }
  if (samples[n - 1].x_m == samples[n - 2].x_m && samples[n - 1].y_m == samples[n - 2].y_m)
    samples[n - 1].speed_mps = 0.0;
}

RecordedTrajectory parse_esmini(const std::vector<core::CsvRecord>& records, const std::string& file,
                                const sim::SceneConfig& config, const ExportOptions& options) {
  constexpr std::string_view kExpected = "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot";
  std::size_t first = 0;
  // dat2csv may begin with "Version: 2, OpenDRIVE: …, 3DModel: …".
  if (!records.empty() && trimmed(records.front().fields.front()).rfind("Version:", 0) == 0) first = 1;
  if (first >= records.size()) throw InputError({file, 1, 1}, fmt::format("expected a header ({})", kExpected));
  const core::CsvRecord& header = records[first];
  refuse_the_other_format(header, file, true);
  const Columns c = header_of(header);
  const std::size_t time = require_column(c, "time", header, file, kExpected);
  const std::size_t name = require_column(c, "name", header, file, kExpected);
  const std::size_t x = require_column(c, "x", header, file, kExpected);
  const std::size_t y = require_column(c, "y", header, file, kExpected);
  const std::size_t h = require_column(c, "h", header, file, kExpected);
  const double ego_back = ego_reference_offset_m(config.ego);
  const double truck_back = truck_reference_offset_m(config.truck, options);
  // The T-junction's truck is the entity "Truck" about its rear axle; another family's actors are
  // entities about their boxes' centres (a highway's truck among them), judged as the scene moves them.
  const bool tjunction_truck = sim::has_tjunction_analytics(config);

  RecordedTrajectory out;
  out.file = file;
  std::map<std::string, TrajectorySample> truck_at;  // by the time field's text
  std::vector<std::string> ego_times;
  bool any_truck = false;
  for (std::size_t k = first + 1; k < records.size(); ++k) {
    const core::CsvRecord& row = records[k];
    core::check_row_length(row, header.fields.size(), file);
    const RowReader r(row, file);
    const std::string entity = r.text(name);
    if (entity != kEgoEntity && !(entity == kTruckEntity && tjunction_truck)) continue;
    const double t = r.number(time, "time");
    const double px = r.number(x, "x");
    const double py = r.number(y, "y");
    const double heading = r.number(h, "h");
    if (entity == kTruckEntity) {
      any_truck = true;
      TrajectorySample s;
      s.truck_x_m = px + truck_back * std::cos(heading);
      s.truck_y_m = py + truck_back * std::sin(heading);
      s.truck_yaw_rad = heading;
      truck_at[r.text(time)] = s;
      continue;
    }
    // A frame esmini logs twice (the first, at t = 0) is one sample.
    if (!out.samples.empty() && t == out.samples.back().t_s) continue;
    TrajectorySample s;
    s.t_s = t;
    s.x_m = px + ego_back * std::cos(heading);
    s.y_m = py + ego_back * std::sin(heading);
    s.yaw_rad = heading;
    check_time(out, t, r, time);
    out.samples.push_back(s);
    ego_times.push_back(r.text(time));
  }
  if (out.samples.empty())
    throw InputError({file, header.lines.front(), 1},
                     fmt::format("expected rows of the entity '{}' (the ego as emrm export names it)", kEgoEntity));
  speeds_from_positions(out.samples);
  // The truck as recorded when it is there at every ego sample; else the scene's motion.
  out.has_truck = any_truck && std::all_of(ego_times.begin(), ego_times.end(),
                                           [&](const std::string& t) { return truck_at.count(t) > 0; });
  if (out.has_truck) {
    for (std::size_t k = 0; k < out.samples.size(); ++k) {
      const TrajectorySample& truck = truck_at.at(ego_times[k]);
      out.samples[k].truck_x_m = truck.truck_x_m;
      out.samples[k].truck_y_m = truck.truck_y_m;
      out.samples[k].truck_yaw_rad = truck.truck_yaw_rad;
    }
  }
  return out;
}

}  // namespace

std::string_view format_name(TrajectoryFormat format) noexcept {
  return format == TrajectoryFormat::kEsmini ? "esmini" : "emrm";
}

RecordedTrajectory parse_trajectory_csv(std::string_view text, const std::string& file_name, TrajectoryFormat format,
                                        const sim::SceneConfig& config, const ExportOptions& options) {
  const std::vector<core::CsvRecord> records = core::parse_csv(text, file_name);
  if (records.empty())
    throw InputError({file_name, 1, 1}, "expected a header and at least two samples, got an empty file");
  RecordedTrajectory out = format == TrajectoryFormat::kEsmini ? parse_esmini(records, file_name, config, options)
                                                               : parse_emrm(records, file_name);
  if (out.samples.size() < 2) {
    const int line = records.back().lines.front();
    throw InputError({file_name, line, 1}, fmt::format("expected at least two samples, got {}", out.samples.size()));
  }
  unwrap(out);
  return out;
}

RecordedTrajectory read_trajectory_csv(const std::filesystem::path& path, TrajectoryFormat format,
                                       const sim::SceneConfig& config, const ExportOptions& options) {
  return parse_trajectory_csv(core::read_input_file(path), path.string(), format, config, options);
}

}  // namespace emrm::exchange
