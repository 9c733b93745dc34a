// The suite's output folders: names that are never paths, folders cleared only when ovpc made
// them, one writer at a time, files written whole.
#include "ovpc/suite/output_folder.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class OutputFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ovpc_out_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void Write(const fs::path& path, const std::string& text) const {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }
  fs::path dir_;
};

TEST_F(OutputFolderTest, ANameIsOneFolderNameAndNeverAPath) {
  for (const std::string& name : std::vector<std::string>{"carport_2p5", "ramps_007", "a.b-c", std::string(200, 'x')}) {
    EXPECT_TRUE(IsSafeComponent(name)) << name;
  }
  std::string why;
  for (const std::string& name : std::vector<std::string>{"", ".", "..", "a/b", "/abs", std::string(201, 'x'), std::string("a\x01") + "b", std::string("a\nb")}) {
    EXPECT_FALSE(IsSafeComponent(name, &why)) << name;
    EXPECT_FALSE(why.empty());
  }
}

TEST_F(OutputFolderTest, AFolderIsClearedOnlyWhenOvpcMadeIt) {
  // A user's folder: refused, nothing removed.
  Write(dir_ / "user" / "thesis.tex", "mine");
  EXPECT_THROW(MakeFresh(dir_ / "user"), BadInput);
  EXPECT_EQ(ReadAll(dir_ / "user" / "thesis.tex"), "mine");
  // A folder this program made (marked) is cleared, and stays marked.
  MakeFresh(dir_ / "made");
  ASSERT_TRUE(fs::exists(dir_ / "made" / kMarker));
  Write(dir_ / "made" / "sub" / "old.txt", "old");
  MakeFresh(dir_ / "made");
  EXPECT_FALSE(fs::exists(dir_ / "made" / "sub"));
  EXPECT_TRUE(fs::exists(dir_ / "made" / kMarker));
  // A run folder from before the marker (only a run's files) is cleared; one more file keeps it.
  for (const char* f : {"result.json", "run.log", "trajectory.csv", "mesh_000_t1.1.ply", "frame_00120.png"}) {
    Write(dir_ / "legacy" / f, "x");
  }
  MakeFresh(dir_ / "legacy");
  EXPECT_FALSE(fs::exists(dir_ / "legacy" / "result.json"));
  Write(dir_ / "legacy2" / "result.json", "x");
  Write(dir_ / "legacy2" / "notes.md", "mine");
  EXPECT_THROW(MakeFresh(dir_ / "legacy2"), BadInput);
  EXPECT_EQ(ReadAll(dir_ / "legacy2" / "notes.md"), "mine");
  // A link and a file are never replaced.
  fs::create_directory_symlink(dir_ / "made", dir_ / "link");
  EXPECT_THROW(MakeFresh(dir_ / "link"), BadInput);
  Write(dir_ / "file", "x");
  EXPECT_THROW(MakeFresh(dir_ / "file"), BadInput);
  EXPECT_EQ(ReadAll(dir_ / "file"), "x");
}

TEST_F(OutputFolderTest, AFolderWithAUsersFilesIsNeverMarked) {
  Write(dir_ / "home" / "notes.md", "mine");
  MakeFolder(dir_ / "home");
  EXPECT_FALSE(fs::exists(dir_ / "home" / kMarker));
  MakeFolder(dir_ / "new" / "deep");
  EXPECT_TRUE(fs::exists(dir_ / "new" / "deep" / kMarker));
}

TEST_F(OutputFolderTest, OneWriterAtATime) {
  {
    const FolderLock first(dir_ / "out");
    EXPECT_THROW(FolderLock second(dir_ / "out"), BadInput);
  }
  EXPECT_NO_THROW(FolderLock again(dir_ / "out"));
  Write(dir_ / "plain", "x");
  EXPECT_THROW(FolderLock under_a_file(dir_ / "plain" / "out"), BadInput);
}

TEST_F(OutputFolderTest, AFileIsWrittenWholeOrTheEarlierOneStays) {
  WriteFileAtomic(dir_ / "summary.json", "{\"a\": 1}\n");
  EXPECT_EQ(ReadAll(dir_ / "summary.json"), "{\"a\": 1}\n");
  WriteFileAtomic(dir_ / "summary.json", "{\"a\": 2}\n");
  EXPECT_EQ(ReadAll(dir_ / "summary.json"), "{\"a\": 2}\n");
  fs::create_directories(dir_ / "junit.xml");
  try {
    WriteFileAtomic(dir_ / "junit.xml", "<x/>");
    ADD_FAILURE() << "a folder in the file's place must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir_ / "junit.xml").string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "junit.xml.part"));
  if (fs::exists("/dev/full") && ::geteuid() == 0) {  // the temporary file itself cannot be written
    fs::create_symlink("/dev/full", dir_ / "full.csv.part");
    EXPECT_THROW(WriteFileAtomic(dir_ / "full.csv", std::string(100000, 'x')), std::runtime_error);
    EXPECT_FALSE(fs::exists(dir_ / "full.csv"));
  }
}

TEST_F(OutputFolderTest, CsvFieldsAreQuotedWhenTheyHoldSeparators) {
  EXPECT_EQ(CsvField("plain"), "plain");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace ovpc::suite
