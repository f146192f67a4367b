#include "emrm/fsm/dot.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "emrm/fsm/load.hpp"

namespace emrm::fsm {
namespace dot_test {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

Generator shipped_emrm() { return load_generator(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/emrm_fsm.yaml"); }

TEST(Dot, DrawsInitialArrowAndMarkedStatesAsDoubleCircles) {
  const std::string dot = to_dot(shipped_emrm());
  EXPECT_THAT(dot, StartsWith("digraph \"emrm\" {"));
  EXPECT_THAT(dot, HasSubstr("\"<initial>\" -> \"S1\";"));
  EXPECT_THAT(dot, HasSubstr("\"S1\" [shape=doublecircle"));
  EXPECT_THAT(dot, HasSubstr("\"S6\" [shape=doublecircle"));
  EXPECT_THAT(dot, HasSubstr("\"S5\" [shape=circle"));
  EXPECT_THAT(dot, HasSubstr("tooltip=\"mitigation failure (loss)\""));
  EXPECT_THAT(dot, HasSubstr("\"S4\" -> \"S5\" [label=\"timeout_error\"];"));
}

TEST(Dot, MergesParallelTransitionsIntoOneEdge) {
  const Generator g = load_generator(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/loss_evaluation_fsm.yaml");
  const std::string merged = to_dot(g);
  EXPECT_THAT(merged, HasSubstr("\"evaluate_severity\" -> \"severe_evaluate_exposure\" [label=\"Se2, Se3\"];"));
  DotOptions separate;
  separate.merge_parallel_edges = false;
  EXPECT_THAT(to_dot(g, separate), HasSubstr("\"evaluate_severity\" -> \"severe_evaluate_exposure\" [label=\"Se3\"];"));
}

TEST(Dot, TransitionCountsLabelAndColourEdges) {
  DotOptions options;
  options.transition_counts = {10, 1, 9, 9, 8, 0, 0, 0};
  const std::string dot = to_dot(shipped_emrm(), options);
  EXPECT_THAT(dot, HasSubstr("label=\"hazard_detected (10)\", colorscheme=blues9, color=9"));
  EXPECT_THAT(dot, HasSubstr("label=\"timeout_error (0)\", color=\"#d62728\""));
  EXPECT_THAT(dot, HasSubstr("style=dashed"));
  // The most-taken transition is drawn thicker than a rarely taken one.
  EXPECT_THAT(dot, HasSubstr("hazard_detected (10)\", colorscheme=blues9, color=9, fontcolor=9, penwidth=3.50"));
  EXPECT_THAT(dot, Not(HasSubstr("no_risk (1)\", colorscheme=blues9, color=9")));
}

TEST(Dot, RejectsCountsThatDoNotMatchTheTransitions) {
  DotOptions options;
  options.transition_counts = {1, 2};
  EXPECT_THROW((void)to_dot(shipped_emrm(), options), Error);
  DotOptions sideways;
  sideways.rank_direction = "diagonal";
  EXPECT_THROW((void)to_dot(shipped_emrm(), sideways), Error);
}

TEST(Dot, EscapesQuotesAndMarkupInNames) {
  Generator g("say \"hi\"");
  g.add_event("e");
  g.add_state("a", "x < y & \"z\"");
  g.set_initial("a");
  const std::string dot = to_dot(g);
  EXPECT_THAT(dot, HasSubstr("digraph \"say \\\"hi\\\"\""));
  EXPECT_THAT(dot, HasSubstr("x &lt; y &amp; &quot;z&quot;"));
}

TEST(Dot, RendersSvgWithGraphviz) {
  if (!dot_available()) GTEST_SKIP() << "Graphviz dot is not installed";
  const std::string svg = render_svg(to_dot(shipped_emrm()));
  EXPECT_THAT(svg, StartsWith("<?xml"));
  EXPECT_THAT(svg, HasSubstr("<svg"));
  EXPECT_THAT(svg, HasSubstr("timeout_error"));
}

TEST(Dot, MissingGraphvizIsAClearError) {
  EXPECT_FALSE(dot_available("emrm-no-such-graphviz-dot"));
  try {
    (void)render_svg("digraph g {}", "emrm-no-such-graphviz-dot");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("install Graphviz"));
  }
}

TEST(Dot, GraphvizFailureReportsItsMessage) {
  if (!dot_available()) GTEST_SKIP() << "Graphviz dot is not installed";
  try {
    (void)render_svg("digraph g { this is not dot");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("failed"));
  }
}

}  // namespace dot_test
}  // namespace emrm::fsm
