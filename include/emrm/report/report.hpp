#pragma once

// `emrm report DIR` (docs/report.md): every figure of the paper's evaluation from a
// results folder written by `emrm sweep`, `emrm run` or `emrm reproduce`, each as PNG and SVG with
// its CSV, and one self-contained DIR/report.html with the configuration, the tables (ours beside
// the paper's), the figures, the diagnostics and the findings.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/fsm/generator.hpp"
#include "emrm/report/figures.hpp"

namespace emrm::report {

/// (6) An FSM diagram with every transition coloured by how often the stored traces took it:
/// DIR/NAME.dot, .svg and .png (Graphviz) and NAME.csv (from, event, to, count).
Figure draw_fsm_figure(const fsm::Generator& g, const std::vector<std::size_t>& counts, const std::string& name,
                       const std::string& title, const std::filesystem::path& dir);

struct ReportSummary {
  std::vector<Figure> figures;  ///< every figure attempted (with a note when it has no files)
  std::filesystem::path html;
  double figure_seconds = 0.0;  ///< wall time spent rendering figures
};

/// Writes DIR/figures/* and DIR/report.html. Every input is read, and gnuplot and Graphviz are
/// found, before the first figure is drawn; each file is written whole (core::write_file), and
/// report.html last. Throws UsageError (exit 2) when DIR is missing, is not a folder, holds no
/// results.sqlite, or its store is of another schema version; InputError for a malformed file in
/// it; emrm::Error when gnuplot or Graphviz is missing or fails.
ReportSummary write_report(const std::filesystem::path& dir);

/// The report's sections that come from side files of DIR, as report.html shows them: the plan's
/// shortfalls first, then the planned run's estimates (estimates.json and the coverage.json it
/// names), the verification (verify.json), the diagnostics (diagnostics.json) and the findings
/// (analysis/findings.json). A missing file leaves its section out, and one of another shape is
/// shown as it is with a note: no content of these files makes it throw.
[[nodiscard]] std::string side_files_html(const std::filesystem::path& dir);

/// Base64 (RFC 4648) of bytes, for data: URIs.
[[nodiscard]] std::string base64(std::string_view bytes);
/// Text safe inside HTML elements and attributes.
[[nodiscard]] std::string html_escape(std::string_view text);

}  // namespace emrm::report
