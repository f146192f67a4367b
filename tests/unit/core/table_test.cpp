#include "emrm/core/table.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "emrm/core/text.hpp"

namespace emrm::core {
namespace table_test {

using ::testing::HasSubstr;

TEST(Table, LatexEscapesSpecialCharacters) {
  EXPECT_EQ(latex_escape("a_b & 50% #1 {x} $y ~ ^ \\"),
            "a\\_b \\& 50\\% \\#1 \\{x\\} \\$y \\textasciitilde{} \\textasciicircum{} \\textbackslash{}");
  EXPECT_EQ(latex_escape("ΔLoss μ ≥ —"), "$\\Delta$Loss $\\mu$ $\\geq$ ---");
  Table t{"T", {"a_1", "b"}, {{"x%", "y"}}, {}};
  const auto tex = to_latex(t);
  EXPECT_THAT(tex, HasSubstr("\\begin{tabular}{|l|c|}"));
  EXPECT_THAT(tex, HasSubstr("a\\_1 & b \\\\ \\hline"));
  EXPECT_THAT(tex, HasSubstr("x\\% & y \\\\ \\hline"));
  EXPECT_THAT(tex, HasSubstr("\\end{tabular}"));
}

TEST(Table, MarkdownHasTitleTableAndNotesAsParagraphs) {
  const Table t{"Title", {"a", "b"}, {{"1", "x|y"}}, {"First note.", "Second note."}};
  EXPECT_EQ(to_markdown(t), "# Title\n\n" + markdown_table(t.header, t.rows) + "\nFirst note.\n\nSecond note.\n");
  EXPECT_EQ(to_csv(t), "a,b\n1,x|y\n");
}

TEST(Table, NumbersHaveTheirDecimalsAndMissingValuesADash) {
  EXPECT_EQ(format_number(3.14159, 2), "3.14");
  EXPECT_EQ(format_number(2.5, 0), "2");  // round half to even, as printf
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN(), 1), kNoValue);
  EXPECT_EQ(format_number(std::numeric_limits<double>::infinity(), 1), "inf");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity(), 1), "-inf");
}

TEST(Table, WritesMarkdownCsvAndLatexBesideEachOther) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-core-table-test";
  std::filesystem::remove_all(dir);
  const Table t{"T", {"a"}, {{"1"}}, {}};
  const auto files = write_table(dir / "tables", "t", t);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0], dir / "tables" / "t.md");
  EXPECT_EQ(read_input_file(files[1]), to_csv(t));
  EXPECT_EQ(read_input_file(files[2]), to_latex(t));
  std::filesystem::remove_all(dir);
}

}  // namespace table_test
}  // namespace emrm::core
