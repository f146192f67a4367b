#include "emrm/core/text.hpp"

#include "emrm/core/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace emrm::core {
namespace {

TEST(Csv, QuotesOnlyFieldsThatNeedIt) {
  EXPECT_EQ(csv_line({"a", "b c", "x,y", "say \"hi\"", "two\nlines"}),
            "a,b c,\"x,y\",\"say \"\"hi\"\"\",\"two\nlines\"\n");
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

}  // namespace
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
  EXPECT_EQ(first_invalid_utf8(std::string("a\x80")), 1u);                // a continuation alone
  EXPECT_EQ(first_invalid_utf8(std::string("\xC0\xAF")), 0u);            // overlong '/'
  EXPECT_EQ(first_invalid_utf8(std::string("\xE0\x80\xAF")), 0u);       // overlong, 3 bytes
  EXPECT_EQ(first_invalid_utf8(std::string("x\xED\xA0\x80")), 1u);      // a surrogate
  EXPECT_EQ(first_invalid_utf8(std::string("\xF4\x90\x80\x80")), 0u);  // above U+10FFFF
  EXPECT_EQ(first_invalid_utf8(std::string("ok \xE2\x82")), 3u);         // cut short at the end
  EXPECT_EQ(first_invalid_utf8(std::string("\xC3(")), 0u);                // a bad second byte
}

TEST(ReadInputFile, NamesTheLineAndColumnOfABadByteAndDropsAByteOrderMark) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-read-input";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.yaml", std::ios::binary) << "name: ok\nstates: [S\xFF" "1]\n";
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

}  // namespace emrm::core
