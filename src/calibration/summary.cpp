// What `emrm calibrate` prints: the fit as JSON (--json) or as text.

#include <fmt/format.h>

#include <string>

#include "emrm/calibration/calibrate.hpp"

namespace emrm::calibration {

nlohmann::ordered_json to_json(const CalibrationResult& r, const RegionCalibration* regions) {
  nlohmann::ordered_json j;
  j["fitted"] = nlohmann::ordered_json::object();
  for (const auto& [name, v] : r.fitted)
    j["fitted"][name] = {
        {"value", v.value}, {"ci_low", v.ci_low}, {"ci_high", v.ci_high}, {"identifiable", v.identifiable}};
  j["residual_rms"] = r.residual_rms;
  j["observations"] = r.observations;
  j["converged"] = r.converged;
  j["warnings"] = r.warnings;
  if (regions != nullptr) {
    j["grid"] = regions->grid;
    j["feasible_cells"] = regions->feasible_cells;
    j["sweeps"] = regions->sweeps;
    j["fractions"] = nlohmann::ordered_json::object();
    for (const auto& [name, pct] : regions->fitted_pct) {
      const auto t = regions->target_pct.find(name);
      j["fractions"][name] = {{"fitted_pct", pct},
                              {"target_pct", t != regions->target_pct.end() ? nlohmann::ordered_json(t->second)
                                                                            : nlohmann::ordered_json(nullptr)}};
    }
  }
  return j;
}

std::string to_text(const CalibrationResult& r, const RegionCalibration* regions, const std::string& source,
                    std::string_view unit, const std::string& output) {
  std::string out;
  if (regions != nullptr)
    out += fmt::format(
        "Calibrated to {} (grid '{}', {} feasible cells, {} simulation(s) of the grid), residual RMS {:.4g} "
        "points:\n",
        source, regions->grid, regions->feasible_cells, regions->sweeps, r.residual_rms);
  else
    out += fmt::format("Calibrated from {} ({} observations), residual RMS {:.4g} {}:\n", source, r.observations,
                       r.residual_rms, unit);
  for (const auto& [name, v] : r.fitted)
    out += fmt::format("  {:<22} {:>9.4f}   95 % interval [{:.4f}, {:.4f}]{}\n", name, v.value, v.ci_low, v.ci_high,
                       v.identifiable ? "" : "   NOT IDENTIFIABLE");
  if (regions != nullptr)
    for (const auto& [name, pct] : regions->fitted_pct) {
      const auto t = regions->target_pct.find(name);
      out += fmt::format("  {} {:>5.1f} %{}\n", name, pct,
                         t != regions->target_pct.end() ? fmt::format("   target {:.1f} %", t->second)
                                                        : std::string("   (not fitted)"));
    }
  for (const auto& w : r.warnings) out += fmt::format("warning: {}\n", w);
  if (r.converged)
    out += fmt::format("Wrote {}\n", output);
  else
    out += fmt::format("The fit did not converge: no profile written.\n");
  return out;
}

}  // namespace emrm::calibration
