// The Eigen PCA baseline against PCL's NormalEstimation on the same small clouds. Compiled only
// when PCL is installed (tests/CMakeLists.txt); the Eigen PCA is checked against analytic planes
// in pca_normals_test.cc whether or not PCL is there.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ovpc/baselines/pca_normals.h"
#include "ovpc/baselines/pcl_normals.h"
#include "pca_test_clouds.h"

namespace ovpc::baselines {
namespace {

using testing::PlanePatch;

double AngleDeg(const Vec3& a, const Vec3& b) {
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

/// A crease like the experiment's scene, small: a noisy ground patch and a noisy 25 deg slope
/// meeting it, on a 0.07 m grid (so that no grid distance is within float precision of the
/// 0.3 m radius), two clouds bundled, a few isolated points, 1.88 m viewpoint.
Points CreaseCloud() {
  const double alpha = DegToRad(25.0);
  const Vec3 slope_normal(-std::sin(alpha), 0.0, std::cos(alpha));
  Points points;
  for (std::uint64_t cloud = 0; cloud < 2; ++cloud) {
    for (const Vec3& p : PlanePatch(Vec3(-1.0, 0.0, 0.0), Vec3::UnitZ(), 1.0, 0.07, 0.02,
                                    2 * cloud + 1)) {
      points.push_back(p);
    }
    const Vec3 slope_centre = Vec3(std::cos(alpha), 0.0, std::sin(alpha));  // foot at x = 0
    for (const Vec3& p : PlanePatch(slope_centre, slope_normal, 1.0, 0.07, 0.02, 2 * cloud + 2)) {
      if (p.x() >= 0.0) points.push_back(p);
    }
  }
  points.emplace_back(6.0, 0.0, 0.0);
  points.emplace_back(6.0, 4.0, 0.0);
  points.emplace_back(6.1, 4.0, 0.0);
  return points;
}

TEST(PclNormalsTest, EigenPcaAgreesWithPclNormalEstimation) {
  const Points points = CreaseCloud();
  const Vec3 viewpoint(0.0, 0.0, 1.88);
  const PcaNormalsConfig config;  // radius 0.3 m
  const PcaNormals eigen = EstimatePcaNormals(points, viewpoint, config);
  const PcaNormals pcl = EstimatePclNormals(points, viewpoint, config);
  ASSERT_EQ(eigen.normals.size(), points.size());
  ASSERT_EQ(pcl.normals.size(), points.size());
  EXPECT_EQ(eigen.num_without_normal, 3u);
  EXPECT_EQ(pcl.num_without_normal, eigen.num_without_normal);
  double max_deg = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(eigen.normals[i].isZero(0.0), pcl.normals[i].isZero(0.0)) << "point " << i;
    if (eigen.normals[i].isZero(0.0)) continue;
    max_deg = std::max(max_deg, AngleDeg(eigen.normals[i], pcl.normals[i]));
  }
  // Same neighbourhoods, same orientation rule; PCL works in single precision.
  EXPECT_LT(max_deg, 0.05);
  RecordProperty("max_angle_between_eigen_and_pcl_deg", std::to_string(max_deg));
}

TEST(PclNormalsTest, AgreesOnAnalyticPlanesAndFlipsTheSameWay) {
  for (const Vec3& viewpoint : {Vec3(0.2, 0.1, 2.0), Vec3(0.2, 0.1, -2.0)}) {
    const Points points = PlanePatch(Vec3::Zero(), Vec3(0.0, -0.5, 1.0).normalized(), 0.8, 0.07,
                                     0.0, 1);
    const PcaNormals eigen = EstimatePcaNormals(points, viewpoint, PcaNormalsConfig{});
    const PcaNormals pcl = EstimatePclNormals(points, viewpoint, PcaNormalsConfig{});
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_LT(AngleDeg(eigen.normals[i], pcl.normals[i]), 0.01) << i;
      ASSERT_GE(pcl.normals[i].dot(viewpoint - points[i]), 0.0);
    }
  }
}

}  // namespace
}  // namespace ovpc::baselines
