// The recorder's bounded map points and its cleaning of a run folder. Nothing here runs the loop.
#include "ovpc/scenarios/recorder.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

namespace fs = std::filesystem;

std::vector<Vec3> Map(std::size_t n, double z) {
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < n; ++i) points.emplace_back(static_cast<double>(i), 0.0, z);
  return points;
}

// Below its bound the sampler keeps every 7th point of every map, as the picture always had them.
TEST(MapPointSamplerTest, BelowItsBoundEverySeventhPointOfEveryMap) {
  MapPointSampler sampler(100000);
  std::vector<MapPoint> kept;
  Eigen::Isometry3d T_W_L = Eigen::Isometry3d::Identity();
  T_W_L.translation() = Vec3(10, 20, 0);
  for (int map = 0; map < 10; ++map) sampler.Add(Map(700, map), T_W_L, [](std::size_t i) { return i % 2 == 0; }, &kept);
  ASSERT_EQ(kept.size(), 1000u);
  EXPECT_EQ(sampler.stride(), 7u);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const std::size_t i = 7 * (k % 100);
    EXPECT_EQ(kept[k].position_W, Vec3(10.0 + static_cast<double>(i), 20.0, static_cast<double>(k / 100)));
    EXPECT_EQ(kept[k].traversable, i % 2 == 0);
  }
}

// However long the run, the points kept stay within the bound, spread over the whole run, the same
// every time.
TEST(MapPointSamplerTest, ALongRunStaysWithinItsBoundDeterministically) {
  const auto run = [](std::vector<MapPoint>* kept) {
    MapPointSampler sampler(1000);
    for (int map = 0; map < 20000; ++map) {
      sampler.Add(Map(700, map), Eigen::Isometry3d::Identity(), [](std::size_t) { return true; }, kept);
      ASSERT_LE(kept->size(), 1000u);
    }
    EXPECT_GT(sampler.stride(), 7u);
  };
  std::vector<MapPoint> a, b;
  run(&a);
  run(&b);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GE(a.size(), 250u);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].position_W, b[k].position_W);
  EXPECT_EQ(a.front().position_W.z(), 0.0);  // the first map and one of the last are both there
  EXPECT_GT(a.back().position_W.z(), 19000.0);
}

TEST(RecorderFilesTest, AnEarlierRunsPicturesAndNothingElseAreRemoved) {
  const fs::path dir = fs::temp_directory_path() / ("ovpc_recorder_files_" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  fs::create_directories(dir / "mesh_009_t9.0.ply");  // a folder of that name stays
  const std::vector<std::string> pictures = {"mesh_000_t1.0.ply", "mesh_1000_t250.5.ply", "mesh_001_t2.0.ply.partial",
                                             "frame_00050.png", "frame_123456.png"};
  const std::vector<std::string> others = {"mesh.ply", "my_mesh_000_t1.0.ply", "frame_x.png", "notes.txt", "mesh_000_t1.0.ply.bak",
                                           "frame_00050.png.old", "result.json", "sub/mesh_000_t1.0.ply"};
  for (const auto& name : pictures) std::ofstream(dir / name) << "x";
  for (const auto& name : others) std::ofstream(dir / name) << "x";
  for (const auto& name : pictures) EXPECT_TRUE(IsRecorderPicture(name)) << name;
  RemoveRecorderPictures(dir.string());
  for (const auto& name : pictures) EXPECT_FALSE(fs::exists(dir / name)) << name;
  for (const auto& name : others) EXPECT_TRUE(fs::exists(dir / name)) << name;
  EXPECT_TRUE(fs::is_directory(dir / "mesh_009_t9.0.ply"));
  RemoveRecorderPictures((dir / "missing").string());  // no folder: nothing to do
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ovpc::scenarios
