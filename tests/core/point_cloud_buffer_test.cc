#include "ovpc/core/point_cloud_buffer.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ovpc {
namespace {

Eigen::Isometry3d Pose(const Vec3& t, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t;
  T.linear() = Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  return T;
}

PointCloudBuffer::Config NoFilter() {
  PointCloudBuffer::Config c;
  c.voxel_size_m = 0.0;
  c.min_hits = 1;
  return c;
}

TEST(PointCloudBufferTest, KnownPosesGiveKnownPointsInTheNewestSensorFrame) {
  PointCloudBuffer buffer(NoFilter());
  // Scan 1: sensor at (1, 2, 1.88) facing +y (yaw 90 deg); a point 3 m ahead in the sensor frame.
  buffer.Push({{Vec3(3, 0, 0)}, Pose(Vec3(1, 2, 1.88), DegToRad(90)), 0.0});
  // Scan 2 (newest): sensor at (4, 2, 1.88), yaw 0; a point 1 m to its left.
  buffer.Push({{Vec3(0, 1, 0)}, Pose(Vec3(4, 2, 1.88), 0.0), 0.05});
  const auto cloud = buffer.Build();
  ASSERT_EQ(cloud.points_L.size(), 2u);
  // L has the odometry axes and the newest sensor position as origin.
  EXPECT_TRUE(cloud.T_O_L.translation().isApprox(Vec3(4, 2, 1.88)));
  EXPECT_TRUE(cloud.T_O_L.linear().isIdentity());
  // Scan 1's point is at (1, 5, 1.88) in O, so (-3, 3, 0) in L.
  EXPECT_TRUE(cloud.points_L[0].isApprox(Vec3(-3, 3, 0), 1e-12)) << cloud.points_L[0].transpose();
  EXPECT_TRUE(cloud.points_L[1].isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_DOUBLE_EQ(cloud.time_s, 0.05);
}

TEST(PointCloudBufferTest, KeepsOnlyTheLastScans) {
  auto config = NoFilter();
  config.max_scans = 3;
  PointCloudBuffer buffer(config);
  for (int i = 0; i < 5; ++i) buffer.Push({{Vec3(i + 1.0, 0, 0)}, Eigen::Isometry3d::Identity(), 0.1 * i});
  EXPECT_EQ(buffer.num_scans(), 3u);
  const auto cloud = buffer.Build();
  ASSERT_EQ(cloud.points_L.size(), 3u);
  EXPECT_DOUBLE_EQ(cloud.points_L[0].x(), 3.0);
}

TEST(PointCloudBufferTest, SingleHitOutliersAreDroppedByTheVoxelFilter) {
  PointCloudBuffer::Config config;  // 0.1 m voxels, at least 2 hits
  PointCloudBuffer buffer(config);
  Points scan;
  for (int i = 0; i < 10; ++i) {
    scan.emplace_back(2.02, 0.03 + 0.3 * i, 0.05);  // hit twice (next line)
    scan.emplace_back(2.04, 0.05 + 0.3 * i, 0.06);
  }
  scan.emplace_back(7.55, 3.05, 1.05);   // a lone outlier
  scan.emplace_back(-4.05, 1.05, 0.55);  // another
  buffer.Push({scan, Eigen::Isometry3d::Identity(), 0.0});
  const auto cloud = buffer.Build();
  EXPECT_EQ(cloud.points_L.size(), 10u);
  EXPECT_EQ(cloud.stats.voxel_sparse, 2u);
  for (const Vec3& p : cloud.points_L) EXPECT_NEAR(p.x(), 2.03, 1e-12);  // voxel centroids
}

TEST(PointCloudBufferTest, CropNonFiniteAndSubsampleAreCounted) {
  auto config = NoFilter();
  config.crop_radius_m = 10.0;
  config.max_points = 100;
  PointCloudBuffer buffer(config);
  Points scan;
  for (int i = 0; i < 300; ++i) scan.emplace_back(0.01 * i, 1.0, 0.0);
  scan.emplace_back(50.0, 0.0, 0.0);
  scan.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  scan.emplace_back(0.0, std::numeric_limits<double>::infinity(), 0.0);
  buffer.Push({scan, Eigen::Isometry3d::Identity(), 0.0});
  const auto a = buffer.Build();
  EXPECT_EQ(a.stats.input, 303u);
  EXPECT_EQ(a.stats.non_finite, 2u);
  EXPECT_EQ(a.stats.out_of_range, 1u);
  EXPECT_EQ(a.stats.subsampled_out, 200u);
  EXPECT_EQ(a.stats.output, 100u);
  ASSERT_EQ(a.points_L.size(), 100u);
  // Deterministic, and spread over the whole line rather than its start.
  EXPECT_EQ(a.points_L, buffer.Build().points_L);
  EXPECT_LT(a.points_L.front().x(), 0.3);
  EXPECT_GT(a.points_L.back().x(), 2.7);
}

TEST(PointCloudBufferTest, EmptyBufferBuildsAnEmptyCloudAndBadInputThrows) {
  PointCloudBuffer buffer;
  EXPECT_TRUE(buffer.Build().points_L.empty());
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(buffer.Push({{Vec3(1, 0, 0)}, bad, 0.0}), std::invalid_argument);
  PointCloudBuffer::Config config;
  config.max_scans = 0;
  EXPECT_THROW(PointCloudBuffer{config}, std::invalid_argument);
  config = PointCloudBuffer::Config{};
  config.min_hits = 0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

TEST(PointCloudBufferTest, SubsampleKeepsOrderAndIsSeeded) {
  Points pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(i, 0, 0);
  const Points a = Subsample(pts, 100, 1);
  const Points b = Subsample(pts, 100, 2);
  ASSERT_EQ(a.size(), 100u);
  EXPECT_NE(a, b);
  for (std::size_t i = 1; i < a.size(); ++i) EXPECT_LT(a[i - 1].x(), a[i].x());
  EXPECT_EQ(Subsample(pts, 5000, 1), pts);
}

}  // namespace
}  // namespace ovpc
