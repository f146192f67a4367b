#include "emrm/calibration/calibrate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>
#include <set>

#include "emrm/core/error.hpp"
#include "emrm/core/measured.hpp"
#include "emrm/core/text.hpp"
#include "fit.hpp"

namespace emrm::calibration {
namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

struct Column {
  std::string name;
  bool required = true;
};

// The columns' positions in a header row; InputError at the header for a missing one.
std::map<std::string, std::size_t> find_columns(const core::CsvRecord& header, const std::vector<Column>& columns,
                                                const std::string& file) {
  std::map<std::string, std::size_t> at;
  for (std::size_t i = 0; i < header.fields.size(); ++i) at[trim(header.fields[i])] = i;
  std::map<std::string, std::size_t> out;
  std::vector<std::string> expected;
  for (const auto& c : columns) expected.push_back(c.name);
  for (const auto& c : columns) {
    if (const auto it = at.find(c.name); it != at.end())
      out[c.name] = it->second;
    else if (c.required)
      throw InputError({file, header.lines.front(), 1},
                       fmt::format("missing column '{}'; expected the columns {}", c.name, core::join(expected, ", ")));
  }
  return out;
}

// A finite number from a field, or InputError at the field.
double number_at(const core::CsvRecord& r, std::size_t i, const std::string& column, const std::string& file) {
  if (i >= r.fields.size())
    throw InputError({file, r.lines.front(), r.columns.back()}, fmt::format("row has no '{}' field", column));
  const std::string text = trim(r.fields[i]);
  const std::optional<double> v = core::parse_finite_number(text);
  if (!v)
    throw InputError({file, r.lines[i], r.columns[i]},
                     fmt::format("{}: expected a finite number, got '{}'", column, text));
  return *v;
}

void require(bool ok, const core::CsvRecord& r, std::size_t i, const std::string& file, const std::string& what) {
  if (!ok) throw InputError({file, r.lines[i], r.columns[i]}, what);
}

std::vector<core::CsvRecord> records_of(const std::filesystem::path& file) {
  auto records = core::parse_csv(core::read_input_file(file), file.string());
  if (records.size() < 2) throw InputError({file.string(), 1, 1}, "expected a header row and at least one data row");
  return records;
}

}  // namespace

std::vector<StopRecord> read_stops(const std::filesystem::path& file) {
  const auto records = records_of(file);
  const std::string f = file.string();
  const auto col =
      find_columns(records.front(), {{"speed_kph"}, {"mu"}, {"stop_distance_m"}, {"time_to_stop_s", false}}, f);
  std::vector<StopRecord> out;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const auto& r = records[k];
    StopRecord s;
    s.speed_kph = number_at(r, col.at("speed_kph"), "speed_kph", f);
    require(s.speed_kph > 0.0, r, col.at("speed_kph"), f,
            fmt::format("speed_kph: expected a value > 0, got {}", s.speed_kph));
    s.mu = number_at(r, col.at("mu"), "mu", f);
    require(s.mu > 0.0 && s.mu <= 2.0, r, col.at("mu"), f, fmt::format("mu: expected 0 < mu <= 2, got {}", s.mu));
    s.stop_distance_m = number_at(r, col.at("stop_distance_m"), "stop_distance_m", f);
    require(s.stop_distance_m > 0.0, r, col.at("stop_distance_m"), f,
            fmt::format("stop_distance_m: expected a distance > 0, got {}", s.stop_distance_m));
    if (const auto it = col.find("time_to_stop_s"); it != col.end()) {
      s.time_to_stop_s = number_at(r, it->second, "time_to_stop_s", f);
      require(s.time_to_stop_s > 0.0, r, it->second, f,
              fmt::format("time_to_stop_s: expected a time > 0, got {}", s.time_to_stop_s));
    }
    out.push_back(s);
  }
  return out;
}

std::vector<TraceSample> read_decel_trace(const std::filesystem::path& file) {
  const auto records = records_of(file);
  const std::string f = file.string();
  const auto col = find_columns(records.front(), {{"run"}, {"t_s"}, {"speed_mps"}}, f);
  std::vector<TraceSample> out;
  std::map<std::string, double> last_t;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const auto& r = records[k];
    require(col.at("run") < r.fields.size(), r, r.fields.size() - 1, f, "row has no 'run' field");
    TraceSample s;
    s.run = trim(r.fields[col.at("run")]);
    s.t_s = number_at(r, col.at("t_s"), "t_s", f);
    const double measured = number_at(r, col.at("speed_mps"), "speed_mps", f);
    const auto speed = core::measured_speed_mps(measured);
    require(speed.has_value(), r, col.at("speed_mps"), f, "speed_mps: " + core::measured_speed_refusal(measured));
    s.speed_mps = speed.value_or(0.0);
    if (const auto it = last_t.find(s.run); it != last_t.end())
      require(
          s.t_s > it->second, r, col.at("t_s"), f,
          fmt::format("t_s: expected the times of run '{}' to increase, got {} after {}", s.run, s.t_s, it->second));
    last_t[s.run] = s.t_s;
    out.push_back(s);
  }
  return out;
}

double braked_speed_mps(const sim::ActuationConfig& a, double mu, double v0, double t_s) {
  const double decel = a.full_decel_mps2(mu);
  const double s = t_s - a.brake_dead_time_s;
  if (s <= 0.0) return v0;
  const double tr = a.brake_ramp_s;
  const double v = tr > 0.0 && s <= tr ? v0 - decel * s * s / (2.0 * tr) : v0 - decel * (0.5 * tr + (s - tr));
  return std::max(0.0, v);
}

CalibrationResult calibrate_stops(const std::vector<StopRecord>& stops, const CalibrationRequest& request) {
  fit::Problem p;
  fit::add_fitted(p, request);
  p.observations = 0;
  for (const auto& s : stops) p.observations += s.time_to_stop_s > 0.0 ? 2 : 1;
  p.sse = [&stops, &request](const std::vector<double>& x) {
    const sim::ActuationConfig a = fit::with(request, x);
    double sum = 0.0;
    for (const auto& s : stops) {
      const double v = s.speed_kph / 3.6;
      const double d = a.stopping_distance_m(v, s.mu, false) - s.stop_distance_m;
      sum += d * d;
      if (s.time_to_stop_s > 0.0) {
        const double t = (a.stopping_time_s(v, s.mu, false) - s.time_to_stop_s) * v;  // in metres, like d
        sum += t * t;
      }
    }
    return sum;
  };
  return fit::solve(p, request);
}

CalibrationResult calibrate_trace(const std::vector<TraceSample>& trace, const CalibrationRequest& request) {
  fit::Problem p;
  fit::add_fitted(p, request);
  // Each run's initial speed is a nuisance parameter within 2 m/s of its first sample.
  std::vector<std::string> runs;
  std::map<std::string, std::size_t> run_index;
  for (const auto& s : trace)
    if (!run_index.contains(s.run)) {
      run_index[s.run] = runs.size();
      runs.push_back(s.run);
      p.low.push_back(std::max(0.0, s.speed_mps - 2.0));
      p.high.push_back(s.speed_mps + 2.0);
    }
  const std::size_t fitted = request.fit.size();
  p.observations = trace.size();
  std::vector<std::size_t> index_of;
  for (const auto& s : trace) index_of.push_back(fitted + run_index.at(s.run));
  p.sse = [&trace, &request, index_of](const std::vector<double>& x) {
    const sim::ActuationConfig a = fit::with(request, x);
    double sum = 0.0;
    for (std::size_t k = 0; k < trace.size(); ++k) {
      const double d = braked_speed_mps(a, 1.0, x[index_of[k]], trace[k].t_s) - trace[k].speed_mps;
      sum += d * d;
    }
    return sum;
  };
  return fit::solve(p, request);
}

std::string profile_yaml(const CalibrationResult& result, const std::string& command, const std::string& description) {
  const sim::ActuationConfig& a = result.actuation;
  std::string fitted;
  for (const auto& [name, v] : result.fitted)
    fitted += fmt::format("#   {} = {:.4g}  (95 % interval {:.4g} to {:.4g}{})\n", name, v.value, v.ci_low, v.ci_high,
                          v.identifiable ? "" : ", NOT IDENTIFIABLE");
  std::string warnings;
  for (const auto& w : result.warnings) warnings += "# warning: " + w + "\n";
  return fmt::format(
      "# Made by: {}\n# Fitted (residual RMS {:.4g} over {} observations):\n{}{}"
      "description: {}\n"
      "actuation:\n"
      "  perception_latency_s: {}\n  brake_dead_time_s: {}\n  brake_ramp_s: {}\n  max_decel_mps2: {}\n"
      "  steer_dead_time_s: {}\n  steer_time_constant_s: {}\n",
      command, result.residual_rms, result.observations, fitted, warnings, nlohmann::json(description).dump(),
      a.perception_latency_s, a.brake_dead_time_s, a.brake_ramp_s, a.max_decel_mps2, a.steer_dead_time_s,
      a.steer_time_constant_s);
}

}  // namespace emrm::calibration
