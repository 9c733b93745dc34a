#include "ovpc/planner/path.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ovpc::planner {
namespace {

TEST(PathTest, NormalizeYawIsInMinusPiToPi) {
  EXPECT_EQ(NormalizeYaw(kPi), -kPi);  // +pi is outside OMPL's SO(2) bounds
  EXPECT_EQ(NormalizeYaw(-kPi), -kPi);
  EXPECT_EQ(NormalizeYaw(0.0), 0.0);
  EXPECT_NEAR(NormalizeYaw(3.0 * kPi), -kPi, 1e-12);
  EXPECT_NEAR(NormalizeYaw(2.0 * kPi + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(NormalizeYaw(-2.0 * kPi - 0.1), -0.1, 1e-12);
  EXPECT_NEAR(NormalizeYaw(kPi - 1e-9), kPi - 1e-9, 1e-15);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 10000; ++i) {
    const double yaw = u(rng);
    const double n = NormalizeYaw(yaw);
    ASSERT_GE(n, -kPi);
    ASSERT_LT(n, kPi);
    ASSERT_NEAR(std::remainder(n - yaw, 2.0 * kPi), 0.0, 1e-9);
  }
}

TEST(PathTest, PosesListsCuspsOnceAndLengthsAddUp) {
  const Path path({{Direction::kForward, {{{0, 0, 0}, 0}, {{1, 0, 0}, 0}, {{2, 0, 0}, 0}}},
                   {Direction::kReverse, {{{2, 0, 0}, 0}, {{2, 1, 0}, 0}}}});
  EXPECT_EQ(path.NumCusps(), 1);
  EXPECT_DOUBLE_EQ(path.segments()[0].Length(), 2.0);
  EXPECT_DOUBLE_EQ(path.Length(), 3.0);
  const auto poses = path.Poses();
  ASSERT_EQ(poses.size(), 4u);
  EXPECT_EQ(poses[2].pose.x_m, 2.0);
  EXPECT_EQ(poses[3].pose.y_m, 1.0);
  EXPECT_EQ(Path{}.NumCusps(), 0);
  EXPECT_TRUE(Path{}.Poses().empty());
  EXPECT_STREQ(DirectionName(Direction::kReverse), "reverse");
}

// The distance to the polyline through the poses: to a segment's inside, past its ends, at a cusp,
// and none for an empty path.
TEST(PathTest, DistanceToPolylineIsToTheNearestSegment) {
  const Path path({{Direction::kForward, {{{0, 0, 0}, 0}, {{2, 0, 0}, 0}}},
                   {Direction::kReverse, {{{2, 0, 0}, 0}, {{2, 3, 0}, 0}}}});
  EXPECT_DOUBLE_EQ(DistanceToPolyline(path, Eigen::Vector2d(1.0, 0.5)), 0.5);
  EXPECT_DOUBLE_EQ(DistanceToPolyline(path, Eigen::Vector2d(-3.0, -4.0)), 5.0) << "past the first pose";
  EXPECT_DOUBLE_EQ(DistanceToPolyline(path, Eigen::Vector2d(1.5, 2.0)), 0.5) << "beside the second segment";
  EXPECT_DOUBLE_EQ(DistanceToPolyline(path, Eigen::Vector2d(3.0, -1.0)), std::sqrt(2.0)) << "off the corner";
  EXPECT_DOUBLE_EQ(DistanceToPolyline(path, Eigen::Vector2d(2.0, 5.0)), 2.0) << "past the last pose";
  EXPECT_TRUE(std::isinf(DistanceToPolyline(Path{}, Eigen::Vector2d(0.0, 0.0))));
  EXPECT_DOUBLE_EQ(DistanceToSegment(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 0.0)),
                   std::sqrt(2.0)) << "a segment of no length is a point";
}

TEST(PathTest, PosesAreStoredWithThePathNotRebuiltAtEveryCall) {
  Path path({{Direction::kForward, {{{0, 0, 0}, 0}, {{1, 0, 0}, 0}}}, {Direction::kReverse, {{{1, 0, 0}, 0}, {{1, 1, 0}, 0}}}});
  const PathPose* first = path.Poses().data();
  EXPECT_EQ(path.Poses().data(), first);  // one stored list, not a new vector per call
  const PathPose& end = path.Poses().back();
  const Path copy = path;  // a copy has its own, equal poses
  ASSERT_EQ(copy.Poses().size(), 3u);
  EXPECT_NE(copy.Poses().data(), first);
  EXPECT_EQ(copy.Poses()[2].pose.y_m, 1.0);
  const Path shifted = path.Shifted(10.0, 0.0, 0.5);  // poses follow the segments
  EXPECT_EQ(shifted.Poses()[1].pose.x_m, 11.0);
  EXPECT_EQ(shifted.segments()[1].poses[0].pose.x_m, 11.0);
  EXPECT_EQ(shifted.Poses()[2].z_m, 0.5);
  EXPECT_EQ(end.pose.y_m, 1.0);  // the reference into the original is untouched
  path = Path();  // reassigned: poses and segments change together
  EXPECT_TRUE(path.Poses().empty());
  EXPECT_TRUE(path.segments().empty());
}

TEST(PathTest, SliceKeepsSegmentsAndCuspsOfTheRange) {
  const Path path({{Direction::kForward, {{{0, 0, 0}, 0}, {{1, 0, 0}, 0}, {{2, 0, 0}, 0}}},
                   {Direction::kReverse, {{{2, 0, 0}, 0}, {{2, 1, 0}, 0}, {{2, 2, 0}, 0}}}});
  // Poses(): (0,0) (1,0) (2,0)=cusp (2,1) (2,2)
  const Path all = path.Slice(0, 4);
  ASSERT_EQ(all.segments().size(), 2u);
  EXPECT_DOUBLE_EQ(all.Length(), 4.0);
  const Path across = path.Slice(1, 3);  // (1,0) (2,0) forward, then (2,0) (2,1) reverse
  ASSERT_EQ(across.segments().size(), 2u);
  EXPECT_EQ(across.segments()[0].direction, Direction::kForward);
  EXPECT_EQ(across.segments()[1].direction, Direction::kReverse);
  EXPECT_DOUBLE_EQ(across.Length(), 2.0);
  EXPECT_EQ(across.Poses().size(), 3u);
  const Path first = path.Slice(0, 2);  // up to the cusp: forward only
  ASSERT_EQ(first.segments().size(), 1u);
  EXPECT_DOUBLE_EQ(first.Length(), 2.0);
  const Path second = path.Slice(2, 4);  // from the cusp: reverse only
  ASSERT_EQ(second.segments().size(), 1u);
  EXPECT_EQ(second.segments()[0].direction, Direction::kReverse);
  EXPECT_TRUE(path.Slice(3, 3).empty());   // one pose is no path
  EXPECT_TRUE(path.Slice(9, 12).empty());  // past the end
}

}  // namespace
}  // namespace ovpc::planner
