#include "emrm/core/text.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::core {
namespace text_test {

TEST(Csv, QuotesOnlyFieldsThatNeedIt) {
  EXPECT_EQ(csv_line({"a", "b c", "x,y", "say \"hi\"", "two\nlines"}),
            "a,b c,\"x,y\",\"say \"\"hi\"\"\",\"two\nlines\"\n");
}

// A row of another length than the header is refused at its first field too many, or at the last
// field of a row too short (a quoted field's newline counts).
TEST(Csv, ARowOfAnotherLengthThanTheHeaderIsRefusedAtItsEnd) {
  const auto records = parse_csv("a,b,c\n1,2,3\n1,\"x\ny\"\n1,2,3,4\n", "t.csv");
  ASSERT_EQ(records.size(), 4u);
  EXPECT_NO_THROW(check_row_length(records[1], 3, "t.csv"));
  const auto where = [&](const CsvRecord& row) -> std::string {
    try {
      check_row_length(row, 3, "t.csv");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(where(records[2]).rfind("t.csv:3:3: error: expected 3 fields as in the header, got 2", 0), 0u)
      << where(records[2]);
  EXPECT_EQ(where(records[3]).rfind("t.csv:5:7: error: expected 3 fields as in the header, got 4", 0), 0u)
      << where(records[3]);
}

// Whole numbers: decimal digits only, within the type; the limits themselves are read.
TEST(WholeNumber, ReadsExactlyTheNumbersTheTypeHolds) {
  EXPECT_EQ(parse_whole_number<int>("42"), 42);
  EXPECT_EQ(parse_whole_number<int>("-7"), -7);
  EXPECT_EQ(parse_whole_number<std::uint64_t>("18446744073709551615"), UINT64_MAX);
  EXPECT_EQ(parse_whole_number<std::int64_t>("-9223372036854775808"), INT64_MIN);
  for (const char* bad : {"", " 1", "1 ", "+1", "1.0", "1e3", "0x10", "abc", "2147483648"})
    EXPECT_FALSE(parse_whole_number<int>(bad)) << "'" << bad << "'";
  EXPECT_FALSE(parse_whole_number<std::uint64_t>("-1"));
  EXPECT_FALSE(parse_whole_number<std::uint64_t>("18446744073709551616"));
}

TEST(Markdown, EscapesPipesAndNewlines) {
  EXPECT_EQ(markdown_table({"a", "b"}, {{"x|y", "1\n2"}}), "| a | b |\n| --- | --- |\n| x\\|y | 1<br>2 |\n");
}

TEST(WriteFile, CreatesFoldersAndReplacesContent) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-text-test";
  std::filesystem::remove_all(dir);
  const auto path = dir / "sub" / "f.txt";
  write_file(path, "first");
  write_file(path, "second");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "second");
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::filesystem::remove_all(dir);
}

TEST(WriteFile, UnwritablePlaceIsAnError) {
  EXPECT_THROW(write_file("/proc/emrm-cannot-write/x.txt", "x"), emrm::Error);
}

// A fresh folder for one test of the atomic writers.
std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-text-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The names in `dir`, sorted.
std::vector<std::string> names_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string text_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The rename fails (the target is a folder that holds a file): an error, and no temporary left.
TEST(WriteFile, ATargetThatIsAFolderIsAnErrorAndLeavesNoTemporary) {
  const auto dir = fresh_dir("target-folder");
  std::filesystem::create_directories(dir / "out.csv");
  write_file(dir / "out.csv" / "inside.txt", "x");
  EXPECT_THROW(write_file(dir / "out.csv", "a,b\n"), emrm::Error);
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out.csv"});
  EXPECT_TRUE(std::filesystem::is_directory(dir / "out.csv"));
}

TEST(WriteFile, AParentThatIsAFileIsAnError) {
  const auto dir = fresh_dir("parent-file");
  write_file(dir / "plain", "x");
  EXPECT_THROW(write_file(dir / "plain" / "out.csv", "a\n"), emrm::Error);
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"plain"});
}

TEST(WriteFile, LeavesOnlyTheTargetBehind) {
  const auto dir = fresh_dir("only-target");
  write_file(dir / "a.txt", "one");
  write_file(dir / "a.txt", "two");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"a.txt"});
  EXPECT_EQ(text_of(dir / "a.txt"), "two");
}

// One target that cannot be written fails them all: the others keep their old content (or stay
// absent), and no temporary is left.
TEST(WriteFiles, AllOrNothing) {
  const auto dir = fresh_dir("all-or-nothing");
  write_file(dir / "first.txt", "old");
  std::filesystem::create_directories(dir / "second.txt" / "sub");
  EXPECT_THROW(write_files({{dir / "first.txt", "new"}, {dir / "third.txt", "3"}, {dir / "second.txt", "2"}}),
               emrm::Error);
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"first.txt", "second.txt"}));
  EXPECT_EQ(text_of(dir / "first.txt"), "old");

  write_files({{dir / "first.txt", "new"}, {dir / "sub" / "third.txt", "3"}});
  EXPECT_EQ(text_of(dir / "first.txt"), "new");
  EXPECT_EQ(text_of(dir / "sub" / "third.txt"), "3");
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"first.txt", "second.txt", "sub"}));
}

// A file streamed in pieces appears only at commit(); abandoned (an exception on the way), it
// leaves the target as it was and no temporary.
TEST(OutputFile, PublishesOnlyOnCommitAndCleansUpWhenAbandoned) {
  const auto dir = fresh_dir("output-file");
  write_file(dir / "data.csv", "old\n");
  try {
    OutputFile file(dir / "data.csv");
    file.stream() << "half of the ";
    EXPECT_EQ(text_of(dir / "data.csv"), "old\n");
    throw std::runtime_error("a corrupt row");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"data.csv"});
  EXPECT_EQ(text_of(dir / "data.csv"), "old\n");
  {
    OutputFile file(dir / "data.csv");
    file.stream() << "new\n";
    file.commit();
  }
  EXPECT_EQ(text_of(dir / "data.csv"), "new\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"data.csv"});
}

// Two writers of one file at once (two processes, or two threads) each have their own temporary:
// the file is one writer's whole text, never a mix.
TEST(OutputFile, TwoWritersOfOneFileDoNotShareATemporary) {
  const auto dir = fresh_dir("two-writers");
  OutputFile first(dir / "shared.txt");
  OutputFile second(dir / "shared.txt");
  first.stream() << std::string(100000, 'a');
  second.stream() << "b";
  first.commit();
  EXPECT_EQ(text_of(dir / "shared.txt"), std::string(100000, 'a'));
  second.commit();
  EXPECT_EQ(text_of(dir / "shared.txt"), "b");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"shared.txt"});
}

}  // namespace text_test
TEST(DidYouMean, SuggestsTheNearestNameOrAPrefixAndNothingFar) {
  const std::vector<std::string> keys{"severity", "simulation", "safe_state"};
  EXPECT_EQ(did_you_mean("severty", keys), " (did you mean 'severity'?)");
  EXPECT_EQ(did_you_mean("Simulaton", keys), " (did you mean 'simulation'?)");
  EXPECT_EQ(did_you_mean("--speed", {"--seed", "--speed-kph", "--ttc-s"}), " (did you mean '--speed-kph'?)");
  EXPECT_EQ(did_you_mean("colour", keys), "");
  EXPECT_EQ(did_you_mean("x", {}), "");
}

// Well-formed UTF-8 of every length passes; every kind of malformed sequence is found at its first
// byte (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF, no stray continuation).
TEST(Utf8, FindsTheFirstByteThatIsNotUtf8) {
  EXPECT_EQ(first_invalid_utf8("plain ASCII"), std::nullopt);
  EXPECT_EQ(first_invalid_utf8("μ Δv → 𝜇"), std::nullopt);  // 2-, 3- and 4-byte sequences
  EXPECT_EQ(first_invalid_utf8(std::string("ab\xFF")), 2u);
  EXPECT_EQ(first_invalid_utf8(std::string("a\x80")), 1u);             // a continuation alone
  EXPECT_EQ(first_invalid_utf8(std::string("\xC0\xAF")), 0u);          // overlong '/'
  EXPECT_EQ(first_invalid_utf8(std::string("\xE0\x80\xAF")), 0u);      // overlong, 3 bytes
  EXPECT_EQ(first_invalid_utf8(std::string("x\xED\xA0\x80")), 1u);     // a surrogate
  EXPECT_EQ(first_invalid_utf8(std::string("\xF4\x90\x80\x80")), 0u);  // above U+10FFFF
  EXPECT_EQ(first_invalid_utf8(std::string("ok \xE2\x82")), 3u);       // cut short at the end
  EXPECT_EQ(first_invalid_utf8(std::string("\xC3(")), 0u);             // a bad second byte
}

TEST(ReadInputFile, NamesTheLineAndColumnOfABadByteAndDropsAByteOrderMark) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-read-input";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.yaml", std::ios::binary) << "name: ok\nstates: [S\xFF"
                                                       "1]\n";
  try {
    (void)read_input_file(dir / "bad.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 11);
    EXPECT_EQ(e.message(), "byte 0xFF is not UTF-8; expected text in UTF-8 (save the file as UTF-8)");
  }
  std::ofstream(dir / "bom.yaml", std::ios::binary) << "\xEF\xBB\xBFname: x\n";
  EXPECT_EQ(read_input_file(dir / "bom.yaml"), "name: x\n");
  std::filesystem::remove_all(dir);
}

namespace text_test {

// Issue 40, 7: float noise (4.9500000000000002) in the report's configuration and the exported XML.
// At most 15 significant digits: the noise goes, and the value read back is within 5e-15 of it.
TEST(ReadableNumber, DropsTheLastBitsNoiseAndKeepsTheValue) {
  EXPECT_EQ(readable_number(0.1 + 0.2), "0.3");
  EXPECT_EQ(readable_number(4.95 + 1e-15), "4.95");
  EXPECT_EQ(readable_number(1.4100000000000001), "1.41");
  EXPECT_EQ(readable_number(-0.0), "0");
  EXPECT_EQ(readable_number(42.0), "42");
  EXPECT_EQ(readable_number(1e-7), "1e-07");
  for (const double v : {22.916666666666668, -1.5707963267948966, 125.67466666666667, 1.0 / 3.0, 6.02214076e23}) {
    const double back = std::stod(readable_number(v));
    EXPECT_NEAR(back, v, 5e-15 * std::abs(v)) << readable_number(v);
  }
}

}  // namespace text_test

}  // namespace emrm::core
