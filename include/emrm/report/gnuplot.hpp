#pragma once

// Figures are drawn by gnuplot: emrm writes the data and a script, gnuplot renders PNG or SVG.

#include <filesystem>
#include <string>

namespace emrm::report {

/// The gnuplot `set terminal` line for an output file, chosen by its extension: .png (pngcairo)
/// or .svg. Throws UsageError for any other extension.
[[nodiscard]] std::string gnuplot_terminal(const std::filesystem::path& output, int width_px, int height_px);

/// Runs gnuplot on `script` (written to a file in `work_dir`). Throws emrm::Error if gnuplot is
/// not installed (saying how to install it) or fails (with its message).
void run_gnuplot(const std::string& script, const std::filesystem::path& work_dir);

}  // namespace emrm::report
