// Planning a suite: sweep combinations and input files, refused up front when they cannot be met.
#include "plan.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

TEST(SweepCombinationsTest, EveryCombinationInOrder) {
  const auto combos = SweepCombinations({"a=1,2", "b=x,y,z"});
  ASSERT_EQ(combos.size(), 6u);
  EXPECT_EQ(combos.front(), (std::vector<std::string>{"a=1", "b=x"}));
  EXPECT_EQ(combos[1], (std::vector<std::string>{"a=1", "b=y"}));
  EXPECT_EQ(combos.back(), (std::vector<std::string>{"a=2", "b=z"}));
  EXPECT_EQ(SweepCombinations({}).size(), 1u);
}

TEST(SweepCombinationsTest, TooManyOrMalformedAreRefusedWithTheCount) {
  std::string values;
  for (int i = 0; i < 1000; ++i) values += (i ? "," : "") + std::to_string(i);
  try {
    SweepCombinations({"a=" + values, "b=" + values});
    ADD_FAILURE() << "10^6 combinations must be refused";
  } catch (const BadInput& e) {
    EXPECT_NE(std::string(e.what()).find("1000000 combinations"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SweepCombinations({"a=1,,2"}), BadInput);
  EXPECT_THROW(SweepCombinations({"=1"}), BadInput);
  EXPECT_THROW(SweepCombinations({"a="}), BadInput);
  EXPECT_THROW(SweepCombinations({"a=1", "b=2", "a=3"}), BadInput) << "one key swept twice";
}

TEST(CollectFilesTest, AFileGivenTwiceOrNotAFileIsRefused) {
  const fs::path dir = fs::temp_directory_path() / ("ovpc_collect_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "a.yaml") << "name: a\n";
  std::ofstream(dir / "b.yaml") << "name: b\n";
  EXPECT_EQ(CollectFiles({dir.string()}), (std::vector<std::string>{(dir / "a.yaml").string(), (dir / "b.yaml").string()}));
  EXPECT_THROW(CollectFiles({dir.string(), (dir / "a.yaml").string()}), BadInput);
  EXPECT_THROW(CollectFiles({(dir / "a.yaml").string(), (dir / "." / "a.yaml").string()}), BadInput);
  EXPECT_THROW(CollectFiles({(dir / "missing.yaml").string()}), BadInput);
  ASSERT_EQ(::mkfifo((dir / "fifo.yaml").c_str(), 0644), 0);
  try {
    CollectFiles({(dir / "fifo.yaml").string()});
    ADD_FAILURE() << "a FIFO is not a scenario file";
  } catch (const BadInput& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ovpc::suite
