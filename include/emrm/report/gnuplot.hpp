#pragma once

// Figures are drawn by gnuplot: emrm writes the data and a script, gnuplot renders PNG or SVG.
// The one place for what a script is made of: quoting, numbers, datablocks, a key strip, and
// rendering one script to both formats.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace emrm::report {

/// The gnuplot `set terminal` line for an output file, chosen by its extension: .png (pngcairo)
/// or .svg. Throws UsageError for any other extension.
[[nodiscard]] std::string gnuplot_terminal(const std::filesystem::path& output, int width_px, int height_px);

/// Where gnuplot draws `output` (the script's `set output`): a file of the same name in `work_dir`,
/// so that the figure reaches `output` only whole (run_gnuplot).
[[nodiscard]] std::filesystem::path drawing_path(const std::filesystem::path& work_dir,
                                                 const std::filesystem::path& output);

/// Runs gnuplot on `script` (written to a file in `work_dir`), which draws each of `outputs` at its
/// drawing_path; once gnuplot has succeeded, each drawing is written to its output atomically
/// (core::write_file). A failing gnuplot leaves the outputs as they were: no half-drawn figure.
/// Throws emrm::Error if gnuplot is not installed (saying how to install it), fails (with its
/// message) or drew nothing for an output.
void run_gnuplot(const std::string& script, const std::filesystem::path& work_dir,
                 const std::vector<std::filesystem::path>& outputs);

/// Draws `png` and `svg` with one gnuplot run: `data` (datablocks) once, then per terminal its
/// size, the font size `font_pt` and `body`, which starts from `reset` so that the second pass
/// sees none of the first one's settings. Throws as run_gnuplot.
void render_png_and_svg(const std::filesystem::path& png, const std::filesystem::path& svg, const std::string& data,
                        const std::string& body, int width_px, int height_px, int font_pt);

/// A gnuplot single-quoted string literal: nothing is escaped inside but a doubled quote.
[[nodiscard]] std::string single_quoted(std::string_view text);
/// A gnuplot double-quoted string literal: `"` and `\` escaped, a line break in `text` stays one.
[[nodiscard]] std::string double_quoted(std::string_view text);
/// `text` shown literally in an enhanced-text string: _ ^ { } @ & ~ \ escaped with a backslash.
[[nodiscard]] std::string enhanced_literal(std::string_view text);

/// A number in a script, a datablock or a figure's CSV: the shortest form to 10 significant
/// digits, so that 0.37000000000000005 reads 0.37.
[[nodiscard]] std::string plot_number(double x);
/// A percentage in a datablock or a figure's CSV: four decimals.
[[nodiscard]] std::string plot_percent(double x);
/// A colour "#rrggbb" as the integer `lc rgb variable` reads from a data column.
[[nodiscard]] long rgb_value(std::string_view colour);

/// A datablock `$name` holding `lines` (already whitespace-separated columns).
[[nodiscard]] std::string datablock(std::string_view name, const std::vector<std::string>& lines);

/// A key on its own along the bottom of a multiplot (screen 0..height): `entries` are plot items
/// of NaN with their style and title, in at most `max_rows` rows; `width_adjust` widens (or
/// narrows) the columns by that many characters. `labels` (set label commands) are drawn with it,
/// once. It unsets the panels' borders, tics, axis labels, titles, colour box and labels itself and
/// ends with its plot command.
[[nodiscard]] std::string key_strip(double height, int max_rows, int width_adjust,
                                    const std::vector<std::string>& entries, const std::string& labels = "");

}  // namespace emrm::report
