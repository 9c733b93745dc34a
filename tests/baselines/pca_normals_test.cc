#include "ovpc/baselines/pca_normals.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "pca_test_clouds.h"

namespace ovpc::baselines {
namespace {

using testing::PlanePatch;

double AngleDeg(const Vec3& a, const Vec3& b) {
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

TEST(PcaNormalsTest, NormalOfAnAnalyticPlaneNeighbourhood) {
  const Points plane = PlanePatch(Vec3::Zero(), Vec3::UnitZ(), 0.5, 0.1, 0.0, 1);
  const Vec3 n = PcaNormalOf(plane);
  EXPECT_NEAR(std::abs(n.z()), 1.0, 1e-12);
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_TRUE(PcaNormalOf({Vec3::Zero(), Vec3::UnitX()}).isZero(0.0));
}

TEST(PcaNormalsTest, TiltedAnalyticPlanesGiveTheirNormalEverywhere) {
  // Planes at 0, 10, 30 and 60 deg and one in a general direction, seen from above: every point's
  // PCA normal (radius 0.3 m, grid step 0.07 m) is the plane's normal, facing the viewpoint.
  const Vec3 general = Vec3(0.3, -0.5, 0.8).normalized();
  for (const Vec3& normal :
       {Vec3::UnitZ().eval(), Vec3(-std::sin(DegToRad(10.0)), 0.0, std::cos(DegToRad(10.0))),
        Vec3(-std::sin(DegToRad(30.0)), 0.0, std::cos(DegToRad(30.0))),
        Vec3(0.0, -std::sin(DegToRad(60.0)), std::cos(DegToRad(60.0))), general}) {
    const Vec3 centre(2.0, 1.0, 0.5);
    const Points points = PlanePatch(centre, normal, 1.0, 0.07, 0.0, 1);
    const Vec3 viewpoint = centre + 3.0 * normal + Vec3(0.5, 0.2, 0.0);
    const PcaNormals result = EstimatePcaNormals(points, viewpoint, PcaNormalsConfig{});
    ASSERT_EQ(result.normals.size(), points.size());
    EXPECT_EQ(result.num_without_normal, 0u);
    for (const Vec3& n : result.normals) {
      ASSERT_NEAR(AngleDeg(n, normal), 0.0, 1e-6) << "plane normal " << normal.transpose();
      ASSERT_NEAR(n.norm(), 1.0, 1e-12);
    }
  }
}

TEST(PcaNormalsTest, NormalsAreFlippedTowardsTheViewpoint) {
  const Points points = PlanePatch(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.07, 0.0, 1);
  const PcaNormals below = EstimatePcaNormals(points, Vec3(0.3, 0.0, -2.0), PcaNormalsConfig{});
  for (const Vec3& n : below.normals) ASSERT_NEAR(n.z(), -1.0, 1e-9);
  const PcaNormals above = EstimatePcaNormals(points, Vec3(0.3, 0.0, 2.0), PcaNormalsConfig{});
  for (const Vec3& n : above.normals) ASSERT_NEAR(n.z(), 1.0, 1e-9);
  EXPECT_TRUE(FlipTowardsViewpoint(Vec3::UnitZ(), Vec3::Zero(), Vec3(0, 0, -1))
                  .isApprox(-Vec3::UnitZ()));
  EXPECT_TRUE(FlipTowardsViewpoint(Vec3::UnitZ(), Vec3::Zero(), Vec3(0, 0, 1))
                  .isApprox(Vec3::UnitZ()));
}

TEST(PcaNormalsTest, NoisyPlaneErrorShrinksWithTheRadius) {
  // Uniform noise of +-2 cm along the normal on a 5 cm grid: the bigger neighbourhood averages
  // more noise away.
  const Points points = PlanePatch(Vec3::Zero(), Vec3::UnitZ(), 2.0, 0.05, 0.02, 7);
  auto mean_error = [&](double radius_m) {
    PcaNormalsConfig config;
    config.radius_m = radius_m;
    const PcaNormals result = EstimatePcaNormals(points, Vec3(0, 0, 2), config);
    double sum = 0.0;
    for (const Vec3& n : result.normals) sum += AngleDeg(n, Vec3::UnitZ());
    return sum / static_cast<double>(points.size());
  };
  const double small = mean_error(0.12);
  const double large = mean_error(0.3);
  EXPECT_GT(small, large);
  EXPECT_LT(large, 5.0);
}

TEST(PcaNormalsTest, PointsWithTooFewNeighboursGetNoNormal) {
  Points points = PlanePatch(Vec3::Zero(), Vec3::UnitZ(), 0.5, 0.07, 0.0, 1);
  const std::size_t plane_points = points.size();
  points.emplace_back(10.0, 0.0, 0.0);  // alone
  points.emplace_back(20.0, 0.0, 0.0);  // a pair: two points cannot span a plane
  points.emplace_back(20.1, 0.0, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  points.emplace_back(nan, 0.0, 0.0);  // not finite: neither queried nor a neighbour
  const PcaNormals result = EstimatePcaNormals(points, Vec3(0, 0, 2), PcaNormalsConfig{});
  EXPECT_EQ(result.num_without_normal, 4u);
  for (std::size_t i = plane_points; i < points.size(); ++i) {
    EXPECT_TRUE(result.normals[i].isZero(0.0)) << i;
  }
  for (std::size_t i = 0; i < plane_points; ++i) EXPECT_NEAR(result.normals[i].z(), 1.0, 1e-9);

  // A stricter minimum leaves the sparse points of a coarse grid without normals.
  PcaNormalsConfig strict;
  strict.min_neighbours = 6;  // a 0.25 m grid has 5 points within 0.3 m: itself and 4 neighbours
  const Points coarse = PlanePatch(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.25, 0.0, 1);
  EXPECT_EQ(EstimatePcaNormals(coarse, Vec3(0, 0, 2), strict).num_without_normal, coarse.size());
}

TEST(PcaNormalsTest, EmptyCloudAndInvalidArguments) {
  EXPECT_TRUE(EstimatePcaNormals({}, Vec3::Zero(), PcaNormalsConfig{}).normals.empty());
  PcaNormalsConfig config;
  config.radius_m = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config.radius_m = 0.3;
  config.min_neighbours = 2;
  EXPECT_THROW(EstimatePcaNormals({Vec3::Zero()}, Vec3::UnitZ(), config), std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(EstimatePcaNormals({Vec3::Zero()}, Vec3(nan, 0, 0), PcaNormalsConfig{}),
               std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::baselines
