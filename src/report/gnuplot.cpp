#include "emrm/report/gnuplot.hpp"

#include <fmt/format.h>

#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"

namespace emrm::report {

namespace fs = std::filesystem;

std::string gnuplot_terminal(const fs::path& output, int width_px, int height_px) {
  const std::string ext = output.extension().string();
  if (ext == ".png")
    return fmt::format("set terminal pngcairo size {},{} enhanced font 'Sans,10'", width_px, height_px);
  if (ext == ".svg")
    return fmt::format("set terminal svg size {},{} dynamic enhanced font 'Sans,10'", width_px, height_px);
  throw UsageError(fmt::format("cannot draw '{}': expected a file name ending in .png or .svg", output.string()));
}

fs::path drawing_path(const fs::path& work_dir, const fs::path& output) { return work_dir / output.filename(); }

void run_gnuplot(const std::string& script, const fs::path& work_dir, const std::vector<fs::path>& outputs) {
  const auto gnuplot = core::find_program("gnuplot");
  if (!gnuplot)
    throw Error("cannot draw figures: gnuplot was not found on PATH; install it (apt-get install gnuplot-nox)");
  const auto script_path = work_dir / "figure.gp";
  core::write_file(script_path, script);
  const auto run = core::run_program(*gnuplot, {script_path.string()});
  if (run.exit_code != 0)
    throw Error(fmt::format("gnuplot failed{}{}", run.error_output.empty() ? "" : ": ", run.error_output));
  // Only now does a figure reach its folder, whole: gnuplot writes its output as it draws.
  for (const fs::path& output : outputs) {
    const std::string drawing = core::read_file(drawing_path(work_dir, output));
    if (drawing.empty()) throw Error(fmt::format("gnuplot drew nothing for '{}'", output.string()));
    core::write_file(output, drawing);
  }
}

void render_png_and_svg(const fs::path& png, const fs::path& svg, const std::string& data, const std::string& body,
                        int width_px, int height_px, int font_pt) {
  core::TempDir work("emrm-figure");
  std::string script = "set encoding utf8\n" + data;
  for (const fs::path& output : {png, svg}) {
    script += gnuplot_terminal(output, width_px, height_px) + "\n";
    script += fmt::format("set termoption font 'Sans,{}'\n", font_pt);
    script += "set output " + single_quoted(drawing_path(work.path(), output).string()) + "\n";
    script += "reset\nset encoding utf8\nset datafile missing 'NaN'\n" + body + "unset output\n";
  }
  run_gnuplot(script, work.path(), {png, svg});
}

std::string single_quoted(std::string_view text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string double_quoted(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string enhanced_literal(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (std::string_view("_^{}@&~\\").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string plot_number(double x) { return fmt::format("{:.10g}", x); }

std::string plot_percent(double x) { return fmt::format("{:.4f}", x); }

long rgb_value(std::string_view colour) { return std::stol(std::string(colour.substr(1)), nullptr, 16); }

std::string datablock(std::string_view name, const std::vector<std::string>& lines) {
  std::string out = fmt::format("${} << EOD\n", name);
  for (const auto& line : lines) out += line + "\n";
  return out + "EOD\n";
}

std::string key_strip(double height, int max_rows, int width_adjust, const std::vector<std::string>& entries,
                      const std::string& labels) {
  std::string out = fmt::format(
      "set origin 0,0\nset size 1,{}\nset lmargin 0\nset rmargin 0\nset tmargin 0\nset bmargin 0\n"
      "unset border\nunset tics\nunset xlabel\nunset ylabel\nunset title\nunset colorbox\nunset label\n"
      "set xrange [0:1]\nset yrange [0:1]\n"
      "set key horizontal center center reverse Left samplen 4 spacing 1.2 width {} maxrows {}\n{}plot ",
      height, width_adjust, max_rows, labels);
  for (std::size_t i = 0; i < entries.size(); ++i) out += (i == 0 ? "" : ", ") + entries[i];
  return out + "\n";
}

}  // namespace emrm::report
