#include "emrm/report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "emrm/campaign/plan_settings.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/fsm/dot.hpp"
#include "emrm/report/plan_figures.hpp"
#include "emrm/report/trajectory_figure.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/diagnostics.hpp"
#include "emrm/results/profiles.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/version.hpp"
#include "html.hpp"
#include "side_sections.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using detail::coverage_candidates;
using detail::html_table;
using detail::read_or_empty;
using detail::Section;
using detail::sections_html;
using detail::shortfalls_html;
using detail::side_sections;
using Clock = std::chrono::steady_clock;

// The folder must be a results folder of this version: checked before anything is written.
void check_results_dir(const fs::path& dir) {
  (void)campaign::read_meta(campaign::results_store_in(dir, "emrm report"));  // and of this schema version
}

// Both drawing programs, found before the first figure: without one the report would stop halfway.
void require_drawing_programs() {
  if (!core::find_program("gnuplot"))
    throw Error(
        "emrm report: cannot draw figures: gnuplot was not found on PATH; install it (apt-get install "
        "gnuplot-nox)");
  if (!fsm::dot_available())
    throw Error(
        "emrm report: cannot draw the FSM figures: the Graphviz program 'dot' was not found on PATH; "
        "install Graphviz (apt-get install graphviz)");
}

// A table written by `emrm reproduce` (DIR/tables/NAME.csv with its Markdown twin): title, rows
// and the paragraphs that follow the Markdown table.
struct TableFile {
  std::string name;
  std::string title;
  std::vector<core::CsvRecord> rows;
  std::vector<std::string> notes;
};

std::vector<TableFile> read_tables(const fs::path& dir) {
  const results::ResultsDir folder(dir);
  std::vector<TableFile> tables;
  std::error_code ec;
  if (!fs::is_directory(folder.tables_dir(), ec)) return tables;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder.tables_dir()))
    if (entry.path().extension() == ".csv" && entry.path().filename() != folder.kpis_csv().filename())
      names.push_back(entry.path().stem());
  const std::vector<std::string> order{"emrm_vs_baseline",   "by_parameter", "regions",
                                       "regions_by_profile", "claims",       "coverage"};
  std::sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
    const auto rank = [&](const std::string& n) { return std::find(order.begin(), order.end(), n) - order.begin(); };
    return std::pair(rank(a), a) < std::pair(rank(b), b);
  });
  for (const auto& name : names) {
    TableFile t;
    t.name = name;
    const fs::path csv = folder.table_csv(name);
    t.rows = core::parse_csv(core::read_file(csv), csv.string());
    t.title = name;
    std::istringstream md(read_or_empty(folder.table_md(name)));
    bool after_table = false;
    std::string paragraph;
    for (std::string line; std::getline(md, line);) {
      if (line.rfind("# ", 0) == 0) {
        t.title = line.substr(2);
      } else if (!line.empty() && line[0] == '|') {
        after_table = true;
      } else if (after_table && line.empty()) {
        if (!paragraph.empty()) t.notes.push_back(std::move(paragraph));
        paragraph.clear();
      } else if (after_table) {
        paragraph += (paragraph.empty() ? "" : " ") + line;
      }
    }
    if (!paragraph.empty()) t.notes.push_back(std::move(paragraph));
    tables.push_back(std::move(t));
  }
  return tables;
}

// A note's Markdown, as far as our tables use it: `code`.
std::string inline_markdown(std::string_view text) {
  std::string out;
  bool code = false;
  for (char c : text) {
    if (c == '`') {
      out += code ? "</code>" : "<code>";
      code = !code;
    } else {
      out += html_escape(std::string_view(&c, 1));
    }
  }
  return code ? out + "</code>" : out;
}

// A drawn figure (one not drawn is listed among what the folder lacks).
std::string figure_html(const Figure& f, const fs::path& dir) {
  std::string out = fmt::format("<figure id=\"fig-{}\">\n", f.name);
  out += fmt::format("<img src=\"data:image/png;base64,{}\" alt=\"{}\">\n", base64(core::read_file(f.png)),
                     html_escape(f.title));
  const auto rel = [&](const fs::path& p) { return html_escape(fs::relative(p, dir).generic_string()); };
  out += fmt::format("<figcaption>{}{} <span class=\"files\">{} · {} · {}</span></figcaption>\n", html_escape(f.title),
                     f.note.empty() ? "" : " (" + html_escape(f.note) + ")", rel(f.svg), rel(f.png),
                     f.csv.empty() ? std::string("—") : rel(f.csv));
  return out + "</figure>\n";
}

constexpr const char* kStyle = R"css(
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 0 auto; max-width: 1200px;
       padding: 1rem 1.5rem 3rem; color: #1a1a1a; line-height: 1.45; }
h1 { margin-bottom: 0.2rem; } h2 { border-bottom: 1px solid #ccc; padding-bottom: 0.2rem; margin-top: 2.2rem; }
nav ul { columns: 2; padding-left: 1.2rem; }
.scroll { overflow-x: auto; }
table { border-collapse: collapse; margin: 0.6rem 0; font-size: 0.88rem; }
th, td { border: 1px solid #bbb; padding: 0.25rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f0f0f0; }
figure { margin: 1.2rem 0; page-break-inside: avoid; }
figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 0.9rem; color: #333; } .files { color: #777; font-size: 0.8rem; }
.missing { color: #8a5a00; background: #fff6e0; padding: 0.4rem 0.6rem; }
pre { background: #f7f7f7; padding: 0.6rem; overflow-x: auto; font-size: 0.8rem; max-height: 30rem; }
.note { font-size: 0.9rem; color: #333; }
.ok { color: #1b7f2a; } .bad { color: #b00020; }
@media print { body { max-width: none; font-size: 10pt; } pre { max-height: none; white-space: pre-wrap; }
               nav { display: none; } h2 { page-break-before: auto; } a { color: inherit; text-decoration: none; } }
)css";

// Marks the page once loaded: images that failed to decode, script errors and console errors are
// counted on <body>, so a headless browser can check the report from its DOM alone.
constexpr const char* kScript = R"js(
(function () {
  var errors = 0;
  var consoleError = console.error;
  console.error = function () { errors++; return consoleError.apply(console, arguments); };
  window.addEventListener('error', function () { errors++; }, true);
  window.addEventListener('load', function () {
    var broken = 0;
    for (var i = 0; i < document.images.length; i++) {
      var img = document.images[i];
      if (!img.complete || img.naturalWidth === 0) broken++;
    }
    document.body.setAttribute('data-images', String(document.images.length));
    document.body.setAttribute('data-broken-images', String(broken));
    document.body.setAttribute('data-errors', String(errors));
  });
})();
)js";

std::string regions_html(const std::vector<campaign::CellRecord>& records) {
  core::Row header{"grid", "cells", "feasible", "G %", "Y %", "O %", "R %", "O/R certified", "O/R undecided"};
  std::vector<core::Row> rows;
  for (const auto& g : results::grid_names(records)) {
    const auto c = results::count_regions(records, g);
    std::size_t certified = 0;
    std::size_t undecided = 0;
    for (const auto& r : records)
      if (r.grid == g && r.feasible) {
        certified += r.evidence == campaign::CellEvidence::kCertificate;
        undecided += r.evidence == campaign::CellEvidence::kUndecided;
      }
    rows.push_back({g, std::to_string(c.cells), std::to_string(c.feasible), fmt::format("{:.1f}", c.pct(c.g)),
                    fmt::format("{:.1f}", c.pct(c.y)), fmt::format("{:.1f}", c.pct(c.o)),
                    fmt::format("{:.1f}", c.pct(c.r)), std::to_string(certified), std::to_string(undecided)});
  }
  return html_table(header, rows) +
         "<p class=\"note\">G and Y cells are backed by a witness (the avoiding trajectory, replayable with "
         "<code>emrm verify</code>); O and R cells by a certificate of unavoidability, or undecided when a search "
         "found no avoidance and no proof exists (docs/verify.md).</p>\n";
}

// The grid whose trajectories the trajectory figure shows: `canonical`, else the first with any;
// empty when no grid has stored trajectories.
std::string trajectory_grid(const std::vector<campaign::CellRecord>& records) {
  std::string first;
  for (const auto& r : records)
    for (const auto& o : r.outcomes)
      if (!o.path.empty()) {
        if (r.grid == "canonical") return r.grid;
        if (first.empty()) first = r.grid;
      }
  return first;
}

std::vector<safety::TraceRow> find_traceability(const fs::path& dir, std::string& source) {
  const results::ResultsDir folder(dir);
  for (const fs::path& file :
       {folder.plan_results().traceability_csv(), folder.traceability_csv(), folder.analysis_traceability_csv()}) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) continue;
    source = fs::relative(file, dir).generic_string();
    return safety::read_traceability_csv(file);
  }
  return {};
}

}  // namespace

std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const auto n = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                   static_cast<unsigned char>(bytes[i + 2]);
    out += {kAlphabet[(n >> 18) & 63], kAlphabet[(n >> 12) & 63], kAlphabet[(n >> 6) & 63], kAlphabet[n & 63]};
  }
  if (i + 1 == bytes.size()) {
    const auto n = static_cast<unsigned char>(bytes[i]) << 16;
    out += {kAlphabet[(n >> 18) & 63], kAlphabet[(n >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const auto n = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out += {kAlphabet[(n >> 18) & 63], kAlphabet[(n >> 12) & 63], kAlphabet[(n >> 6) & 63], '='};
  }
  return out;
}

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

Figure draw_fsm_figure(const fsm::Generator& g, const std::vector<std::size_t>& counts, const std::string& name,
                       const std::string& title, const fs::path& dir) {
  Figure f;
  f.name = name;
  f.title = title;
  fsm::DotOptions options;
  options.transition_counts = counts;
  const std::string dot = fsm::to_dot(g, options);
  std::vector<core::Row> rows;
  for (std::size_t t = 0; t < g.transitions().size(); ++t) {
    const auto& tr = g.transitions()[t];
    rows.push_back({tr.from, tr.event, tr.to, t < counts.size() ? std::to_string(counts[t]) : "0"});
  }
  f.csv = dir / (name + ".csv");
  f.svg = dir / (name + ".svg");
  f.png = dir / (name + ".png");
  // Rendered first, then the four files together: a failing Graphviz leaves none of them.
  core::write_files({{dir / (name + ".dot"), dot},
                     {f.csv, core::csv_table({"from", "event", "to", "count"}, rows)},
                     {f.svg, fsm::render(dot, "svg")},
                     {f.png, fsm::render(dot, "png")}});
  return f;
}

namespace {

// Which actuation made the results (docs/actuation.md), with the name of the profile it is when
// `reproduce` swept the profiles side by side: every figure and table of the report is under it,
// but the per-profile figure, whose panels name their own.
std::string actuation_html(const sim::ActuationConfig& a, const std::vector<results::ProfileRun>& profiles) {
  std::string name;
  for (const auto& p : profiles)
    if (p.reused) name = fmt::format(" (the <code>{}</code> profile)", html_escape(p.name));
  return fmt::format("<p>Actuation: {}{} (docs/actuation.md). Every figure and table below is under it{}.</p>\n",
                     html_escape(a.summary()), name,
                     profiles.empty() ? "" : ", but the map under each profile and its table, which name theirs");
}

// The sweep curves: by the ODD's bins when the headline grid is a planned run's (and the ODD is
// known), else by exact speed; a planned run beside another grid (reproduce) adds its own curves.
Figure sweep_curves(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                    const std::string& grid, const std::optional<PlannedRun>& planned, const fs::path& figures_dir) {
  if (planned && !planned->factors.empty() && grid == campaign::kPlanGrid)
    return draw_plan_sweep_curves(*planned, factors, figures_dir);
  return draw_sweep_curves(records, factors, grid, figures_dir);
}

// Every input of a report that can be malformed, read before the first figure is drawn so that a
// broken one fails the report with nothing written.
struct ReportInputs {
  results::FoundRunEstimates estimates;  ///< the planned run's, read once for every section that shows it
  std::optional<PlannedRun> planned;
  std::vector<results::ProfileRun> runs;  ///< those whose store exists
  std::vector<std::vector<campaign::CellRecord>> per_profile;
  std::optional<std::vector<scenario::CoverageReport>> coverage;
  std::string trace_source;
  std::vector<safety::TraceRow> trace_rows;
  std::vector<TableFile> tables;
};

ReportInputs read_inputs(const fs::path& dir) {
  ReportInputs in;
  in.estimates = results::find_run_estimates(dir);
  in.planned = read_planned_run(in.estimates);
  in.runs = results::read_profile_index(dir);
  std::error_code ec;
  std::erase_if(in.runs, [&](const results::ProfileRun& r) { return !fs::is_regular_file(dir / r.store, ec); });
  for (const auto& run : in.runs) in.per_profile.push_back(campaign::read_results(dir / run.store));
  for (const fs::path& file : coverage_candidates(dir, in.estimates)) {
    const std::string text = read_or_empty(file);
    if (text.empty()) continue;
    in.coverage = scenario::parse_coverage_json(text, file.string());
    break;
  }
  in.trace_rows = find_traceability(dir, in.trace_source);
  in.tables = read_tables(dir);
  return in;
}

}  // namespace

ReportSummary write_report(const fs::path& dir) {
  check_results_dir(dir);
  require_drawing_programs();
  const results::ResultsDir folder(dir);
  const auto store_path = folder.store();
  const campaign::CampaignMeta meta = campaign::read_meta(store_path);
  const std::vector<campaign::CellRecord> records = campaign::read_results(store_path);
  const sim::SceneConfig scene = sim::parse_stored_scene_config(meta.scene_yaml, store_path.string() + " (scene)");
  const sim::FactorTable factors = sim::scenario_factors(scene);
  const fs::path figures_dir = folder.figures_dir();
  const ReportInputs in = read_inputs(dir);
  const std::optional<PlannedRun>& planned = in.planned;

  ReportSummary summary;
  std::vector<std::string> absent;  // what the folder lacks, and how to make it (the report's last list)
  const auto start = Clock::now();
  const std::string grid = results::headline_grid(records);
  // The dashed stop boundary as a latency: perception, brake dead time and half the ramp (the ramp's
  // a·t_r²/(24 v) and a brake cap below mu·g are left out of the line, not out of the check). NaN, no
  // line, for a family without the boundary.
  const auto& act = scene.actuation;
  const bool stop_boundary = sim::stop_boundary_applies(scene);
  const double boundary_latency_s = stop_boundary
                                        ? act.perception_latency_s + act.brake_dead_time_s + 0.5 * act.brake_ramp_s
                                        : std::numeric_limits<double>::quiet_NaN();
  // The paper's four-panel maps when the store holds one of their grids; any other grid its own maps.
  const MapPanels paper;
  const std::vector<std::string> paper_grids{paper.coarse, paper.fine, paper.speed_mu, paper.ttc_mu};
  const auto grids = results::grid_names(records);
  GridMapOptions grid_maps;
  grid_maps.skip = paper_grids;
  if (planned) grid_maps.skip.push_back(campaign::kPlanGrid);  // scenarios, not a grid: mapped by the ODD's cells
  grid_maps.latency_s = boundary_latency_s;
  if (std::any_of(paper_grids.begin(), paper_grids.end(),
                  [&](const std::string& g) { return std::find(grids.begin(), grids.end(), g) != grids.end(); })) {
    summary.figures.push_back(draw_mitigability_map(records, factors, figures_dir, paper, boundary_latency_s));
    summary.figures.push_back(draw_harm_reduction_map(records, factors, figures_dir, paper, boundary_latency_s));
  }
  for (Figure& f : draw_grid_maps(records, factors, figures_dir, grid_maps)) summary.figures.push_back(std::move(f));
  if (planned)
    for (Figure& f : draw_plan_maps(*planned, figures_dir)) summary.figures.push_back(std::move(f));
  if (stop_boundary) summary.figures.push_back(draw_brake_sensitivity(records, grid, scene.actuation, figures_dir));
  if (!in.runs.empty())
    summary.figures.push_back(draw_profile_maps(in.runs, in.per_profile, factors, grid, figures_dir));
  if (const std::string trees = trajectory_grid(records); !trees.empty())
    summary.figures.push_back(draw_trajectory_grid(records, scene, trees, figures_dir));
  else
    absent.push_back(
        "the planners' trajectory trees: a grid swept with <code>keep_trees: true</code> in its campaign (the "
        "paper's <code>canonical</code> grid)");
  summary.figures.push_back(draw_loss_comparison(records, grid, figures_dir));
  summary.figures.push_back(sweep_curves(records, factors, grid, planned, figures_dir));
  if (planned && !planned->factors.empty() && grid != campaign::kPlanGrid)
    summary.figures.push_back(draw_plan_sweep_curves(*planned, factors, figures_dir, "plan_sweep_curves"));
  if (in.coverage)
    summary.figures.push_back(draw_coverage_comparison(*in.coverage, figures_dir));
  else
    absent.push_back(
        "the coverage of a minimum scenario set against its baselines: <code>emrm plan</code> writes coverage.json "
        "(here, or beside the scenarios.csv a run here read)");
  const auto emrm_coverage = results::emrm_fsm_coverage(records, sim::default_emrm_fsm());
  summary.figures.push_back(draw_fsm_figure(sim::default_emrm_fsm(), emrm_coverage.coverage.counts, "emrm_fsm",
                                            "EMRM hazard–loss FSM, transitions coloured by how often the runs took "
                                            "them (dashed red: never)",
                                            figures_dir));
  const auto loss_coverage = results::loss_evaluation_fsm_coverage(records, sim::default_loss_evaluation_fsm());
  summary.figures.push_back(draw_fsm_figure(sim::default_loss_evaluation_fsm(), loss_coverage.coverage.counts,
                                            "loss_evaluation_fsm",
                                            "Loss-evaluation FSM, transitions coloured by how often emrm's decisions "
                                            "took them (dashed red: never)",
                                            figures_dir));
  if (in.trace_rows.empty()) {
    absent.push_back(
        "the traceability matrix (hazards, UCAs, FSM transitions and scenarios): <code>emrm analyze</code>, "
        "<code>emrm run</code> or <code>emrm reproduce</code> write traceability.csv");
  } else {
    summary.figures.push_back(draw_traceability(in.trace_rows, figures_dir));
    summary.figures.back().note = "from " + in.trace_source;
  }
  summary.figure_seconds = std::chrono::duration<double>(Clock::now() - start).count();

  // report.html, last: written only when every figure was drawn.
  std::string html = "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += fmt::format("<title>emrm report: {}</title>\n<style>{}</style>\n<script>{}</script>\n</head>\n<body>\n",
                      html_escape(dir.filename().string().empty() ? dir.string() : dir.filename().string()), kStyle,
                      kScript);
  html += "<h1>EMRM verification and validation report</h1>\n";
  html += fmt::format(
      "<p>Results folder <code>{}</code>: {} cells in {} grid(s), strategies {}; written by emrm {} (store "
      "configuration {}); this report by emrm {}.</p>\n",
      html_escape(dir.string()), records.size(), meta.grids.size(), html_escape(core::join(meta.strategies, ", ")),
      html_escape(meta.emrm_version), html_escape(meta.config_hash), kVersion);
  html += shortfalls_html(in.estimates);
  html += actuation_html(scene.actuation, in.runs);
  // A section shows when it has something to say; what the folder lacks is listed once, at the end.
  std::vector<Section> sections{{"regions", "Regions", "Regions per grid", regions_html(records), ""}};
  // The paper's claims table is written only where its numbers stand beside ours (docs/results.md).
  const bool beside_paper =
      std::any_of(in.tables.begin(), in.tables.end(), [](const auto& t) { return t.name == "claims"; });
  std::string tables;
  for (const auto& t : in.tables) {
    tables += fmt::format("<h3 id=\"table-{}\">{}</h3>\n", html_escape(t.name), html_escape(t.title));
    tables += html_table(t.rows);
    for (const auto& note : t.notes) tables += "<p class=\"note\">" + inline_markdown(note) + "</p>\n";
  }
  sections.push_back({"tables", "Tables", beside_paper ? "Tables (ours beside the paper's)" : "Tables",
                      std::move(tables), "the KPI tables: <code>emrm reproduce</code> writes them"});
  std::string figures;
  for (const auto& f : summary.figures) {
    if (f.png.empty())
      absent.push_back(html_escape(f.title) + ": " + html_escape(f.note));
    else
      figures += figure_html(f, dir);
  }
  sections.push_back({"figures", "Figures", "Figures", std::move(figures), ""});
  for (Section& s : side_sections(dir, in.estimates)) sections.push_back(std::move(s));
  for (const auto& s : sections)
    if (s.body.empty() && !s.absent.empty()) absent.push_back(s.absent);
  if (!absent.empty()) {
    std::string list = "<p>Not in this folder, and what would add it:</p>\n<ul>\n";
    for (const auto& line : absent) list += "<li>" + line + "</li>\n";
    sections.push_back({"absent", "Not in this folder", "Not in this folder", list + "</ul>\n", ""});
  }
  sections.push_back({"configuration", "Configuration", "Effective configuration",
                      "<details><summary>campaign (as stored)</summary><pre>" + html_escape(meta.campaign_yaml) +
                          "</pre></details>\n<details><summary>scene</summary><pre>" +
                          html_escape(core::readable_yaml(meta.scene_yaml)) + "</pre></details>\n",
                      ""});
  html += "<nav><ul>";
  for (const auto& s : sections)
    if (!s.body.empty()) html += fmt::format("<li><a href=\"#{}\">{}</a></li>", s.id, s.nav);
  html += "</ul></nav>\n" + sections_html(sections);
  html += "</body>\n</html>\n";
  summary.html = folder.report_html();
  core::write_file(summary.html, html);
  return summary;
}

}  // namespace emrm::report
