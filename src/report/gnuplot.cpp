#include "emrm/report/gnuplot.hpp"

#include <fmt/format.h>

#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"

namespace emrm::report {

std::string gnuplot_terminal(const std::filesystem::path& output, int width_px, int height_px) {
  const std::string ext = output.extension().string();
  if (ext == ".png")
    return fmt::format("set terminal pngcairo size {},{} enhanced font 'Sans,10'", width_px, height_px);
  if (ext == ".svg") return fmt::format("set terminal svg size {},{} dynamic enhanced font 'Sans,10'", width_px, height_px);
  throw UsageError(fmt::format("cannot draw '{}': expected a file name ending in .png or .svg", output.string()));
}

void run_gnuplot(const std::string& script, const std::filesystem::path& work_dir) {
  const auto gnuplot = core::find_program("gnuplot");
  if (!gnuplot)
    throw Error("cannot draw figures: gnuplot was not found on PATH; install it (apt-get install gnuplot-nox)");
  const auto script_path = work_dir / "figure.gp";
  core::write_file(script_path, script);
  const auto run = core::run_program(*gnuplot, {script_path.string()});
  if (run.exit_code != 0)
    throw Error(fmt::format("gnuplot failed{}{}", run.error_output.empty() ? "" : ": ", run.error_output));
}

}  // namespace emrm::report
