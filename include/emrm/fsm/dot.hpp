#pragma once

// Graphviz export of a generator: the diagram of the paper's FSM figures, and the same diagram with
// every transition coloured by how often a campaign (or a trace file) exercised it.

#include <cstddef>
#include <string>
#include <vector>

#include "emrm/fsm/generator.hpp"

namespace emrm::fsm {

struct DotOptions {
  /// How often each transition was taken, in g.transitions() order (for example
  /// TransitionCoverage::counts). Empty: a plain diagram. Given: one edge per transition, labelled
  /// "event (count)", never-taken transitions dashed red, the others darker and thicker the more
  /// often they were taken (log scale, relative to the most-taken one).
  std::vector<std::size_t> transition_counts;
  /// Show each state's description under its id (it is always the node's tooltip).
  bool descriptions_in_labels = true;
  /// Without counts, draw transitions between the same two states as one edge labelled "e1, e2".
  bool merge_parallel_edges = true;
  /// Graphviz rankdir: "LR" (left to right) or "TB" (top to bottom).
  std::string rank_direction = "LR";
};

/// DOT source of G: an arrow from a point into s0, marked states as double circles, the others as
/// circles, one labelled edge per transition (or per state pair, see DotOptions). Deterministic
/// output for a given G and options. Throws emrm::Error if transition_counts is neither empty nor
/// one count per transition, or rank_direction is not LR, RL, TB or BT.
[[nodiscard]] std::string to_dot(const Generator& g, const DotOptions& options = {});

/// True if `dot_program` (a name searched on PATH, or a path) is an executable file.
[[nodiscard]] bool dot_available(const std::string& dot_program = "dot");

/// Renders DOT source to SVG by running `dot_program -Tsvg`. Throws emrm::Error if the program is
/// not installed (saying to install Graphviz) or if it fails (with its error output).
[[nodiscard]] std::string render_svg(const std::string& dot_source, const std::string& dot_program = "dot");
/// As render_svg, to any Graphviz output format (`svg`, `png`, ...); the bytes of the output.
[[nodiscard]] std::string render(const std::string& dot_source, const std::string& format,
                                 const std::string& dot_program = "dot");

}  // namespace emrm::fsm
