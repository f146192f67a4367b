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

}  // namespace emrm::core
