#include "emrm/fsm/dot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "emrm/core/error.hpp"
#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"

namespace emrm::fsm {
namespace {

constexpr std::size_t kLabelWidth = 24;  // characters per line of a wrapped description

/// A DOT double-quoted string.
std::string quote(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n' || c == '\r') {
      out += ' ';
      continue;
    }
    out += c;
  }
  out += '"';
  return out;
}

/// Text escaped for a Graphviz HTML-like label.
std::string html_escape(std::string_view text) {
  std::string out;
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
      default:
        out += c;
    }
  }
  return out;
}

/// A node label: the id in bold, the description lines below it in a smaller font (an HTML-like
/// label, so that long descriptions do not blow the circles up as much as plain text would).
std::string node_label(const std::string& id, const std::vector<std::string>& description_lines) {
  std::string out = "<<b>" + html_escape(id) + "</b>";
  if (!description_lines.empty()) {
    out += "<br/><font point-size=\"9\">";
    for (std::size_t i = 0; i < description_lines.size(); ++i)
      out += (i > 0 ? "<br/>" : "") + html_escape(description_lines[i]);
    out += "</font>";
  }
  out += ">";
  return out;
}

std::vector<std::string> wrap(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(std::move(line));
      line.clear();
    }
    if (!line.empty()) line += ' ';
    line += word;
  }
  if (!line.empty()) lines.push_back(std::move(line));
  return lines;
}

std::string count_attributes(std::size_t count, std::size_t max_count) {
  if (count == 0) return "color=\"#d62728\", fontcolor=\"#d62728\", style=dashed";
  // Log scale, so that one transition taken a thousand times does not wash out the rest.
  const double share =
      max_count <= 1 ? 1.0 : std::log1p(static_cast<double>(count)) / std::log1p(static_cast<double>(max_count));
  const int shade = 4 + static_cast<int>(std::lround(5.0 * share));  // blues9: 4 (light) .. 9 (dark)
  return fmt::format("colorscheme=blues9, color={}, fontcolor={}, penwidth={:.2f}", std::min(shade, 9),
                     std::min(shade, 9), 1.0 + 2.5 * share);
}

}  // namespace

std::string to_dot(const Generator& g, const DotOptions& options) {
  const auto& transitions = g.transitions();
  const bool with_counts = !options.transition_counts.empty();
  if (with_counts && options.transition_counts.size() != transitions.size())
    throw Error(fmt::format("fsm: {} transition counts given for {} transitions", options.transition_counts.size(),
                            transitions.size()));
  const std::string& rankdir = options.rank_direction;
  if (rankdir != "LR" && rankdir != "RL" && rankdir != "TB" && rankdir != "BT")
    throw Error(fmt::format("fsm: rank direction must be LR, RL, TB or BT, got '{}'", rankdir));

  std::string out;
  out += fmt::format("digraph {} {{\n", quote(g.name()));
  out += fmt::format("  graph [rankdir={}, label={}, labelloc=t, fontname=\"Helvetica\"];\n", rankdir, quote(g.name()));
  out += "  node [fontname=\"Helvetica\", fontsize=11];\n";
  out += "  edge [fontname=\"Helvetica\", fontsize=10];\n";
  // The initial arrow starts at an invisible point; '<' cannot appear in a state id, so no clash.
  if (const auto s0 = g.initial()) {
    out += "  \"<initial>\" [shape=point, width=0.08, label=\"\"];\n";
    out += fmt::format("  \"<initial>\" -> {};\n", quote(*s0));
  }
  for (int s = 0; s < g.state_count(); ++s) {
    const auto& state = g.states()[static_cast<std::size_t>(s)];
    const auto lines =
        options.descriptions_in_labels ? wrap(state.description, kLabelWidth) : std::vector<std::string>{};
    out += fmt::format("  {} [shape={}, label={}, tooltip={}];\n", quote(state.id),
                       g.is_marked(s) ? "doublecircle" : "circle", node_label(state.id, lines),
                       quote(state.description.empty() ? state.id : state.description));
  }

  if (with_counts) {
    const std::size_t max_count = *std::max_element(options.transition_counts.begin(), options.transition_counts.end());
    for (std::size_t i = 0; i < transitions.size(); ++i) {
      const auto& t = transitions[i];
      const std::size_t count = options.transition_counts[i];
      out += fmt::format("  {} -> {} [label={}, {}];\n", quote(t.from), quote(t.to),
                         quote(fmt::format("{} ({})", t.event, count)), count_attributes(count, max_count));
    }
  } else if (options.merge_parallel_edges) {
    std::vector<std::pair<std::string, std::string>> order;  // state pairs in first-transition order
    std::map<std::pair<std::string, std::string>, std::vector<std::string>> events;
    for (const auto& t : transitions) {
      auto key = std::pair{t.from, t.to};
      auto& list = events[key];
      if (list.empty()) order.push_back(key);
      list.push_back(t.event);
    }
    for (const auto& key : order) {
      std::string label;
      for (const auto& e : events[key]) label += (label.empty() ? "" : ", ") + e;
      out += fmt::format("  {} -> {} [label={}];\n", quote(key.first), quote(key.second), quote(label));
    }
  } else {
    for (const auto& t : transitions)
      out += fmt::format("  {} -> {} [label={}];\n", quote(t.from), quote(t.to), quote(t.event));
  }
  out += "}\n";
  return out;
}

bool dot_available(const std::string& dot_program) { return core::find_program(dot_program).has_value(); }

std::string render_svg(const std::string& dot_source, const std::string& dot_program) {
  return render(dot_source, "svg", dot_program);
}

std::string render(const std::string& dot_source, const std::string& format, const std::string& dot_program) {
  const auto program = core::find_program(dot_program);
  if (!program)
    throw Error(
        fmt::format("cannot render {}: the Graphviz program '{}' was not found on PATH; install Graphviz "
                    "(for example `apt install graphviz`) or write DOT with --dot instead",
                    format, dot_program));
  core::TempDir dir("emrm-dot");
  const auto input = dir.path() / "graph.dot";
  const auto output = dir.path() / ("graph." + format);
  core::write_file(input, dot_source);  // checked: a truncated graph could still render
  const auto run = core::run_program(*program, {"-T" + format, "-o", output.string(), input.string()});
  if (run.exit_code != 0)
    throw Error(fmt::format("'{} -T{}' failed{}{}", program->string(), format, run.error_output.empty() ? "" : ": ",
                            run.error_output));
  return core::read_file(output);
}

}  // namespace emrm::fsm
