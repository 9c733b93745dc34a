#include "ovpc/core/ovpc_mapper.h"

#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "../support/test_clouds.h"

namespace ovpc {
namespace {

TEST(OvpcMapperTest, DropsAndCountsNonFiniteAndViewpointPoints) {
  Points pts = testing::BoxRoom(Vec3(3, 2, 1.5), 0.5);
  const std::size_t good = pts.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  pts.emplace_back(nan, 0, 0);
  pts.emplace_back(0, inf, 0);
  pts.emplace_back(0, 0, -inf);
  const Vec3 viewpoint(0.3, -0.2, 0.1);
  pts.push_back(viewpoint);
  pts.push_back(viewpoint + Vec3(1e-4, 0, 0));
  const OvpcMap map = OvpcMapper().Update(pts, viewpoint);
  ASSERT_TRUE(map.ok()) << map.message;
  EXPECT_EQ(map.input.input, good + 5);
  EXPECT_EQ(map.input.non_finite, 3u);
  EXPECT_EQ(map.input.at_viewpoint, 2u);
  EXPECT_EQ(map.input.used, good);
  EXPECT_EQ(map.cloud.size(), good);
  EXPECT_TRUE(CheckTopology(map.mesh.triangles).watertight());
  // Timings are measured and add up.
  const StageTimings& t = map.timings;
  EXPECT_GT(t.hull_ms, 0.0);
  EXPECT_GE(t.total_ms + 1e-9, t.sanitize_ms + t.transform_ms + t.hull_ms + t.mesh_ms + t.traversability_ms +
                                   t.vertex_cloud_ms);
}

TEST(OvpcMapperTest, PointsBeyondTheDistanceBoundAreDroppedAndCounted) {
  // A tetrahedron of points 1e299 m out: their squared distance overflowed to inf, every image
  // point became 0 and the cloud was called coplanar with the viewpoint.
  const Points huge = {Vec3(1e299, 0, 0), Vec3(0, 1e299, 0), Vec3(0, 0, 1e299), Vec3(1e299, 1e299, 1e299)};
  const OvpcMap far = OvpcMapper().Update(huge, Vec3::Zero());
  EXPECT_EQ(far.status, GhprStatus::kTooFewPoints) << far.message;
  EXPECT_EQ(far.input.too_far, 4u);
  EXPECT_EQ(far.input.used, 0u);
  // Far but within the bound: a real map; one point past it is dropped, the rest still map.
  Points box;
  for (double x : {-1e11, 1e11}) {
    for (double y : {-1e11, 1e11}) {
      for (double z : {-1e11, 1e11}) box.emplace_back(x, y, z);
    }
  }
  box.emplace_back(2e12, 0, 0);
  const OvpcMap map = OvpcMapper().Update(box, Vec3::Zero());
  ASSERT_TRUE(map.ok()) << map.message;
  EXPECT_EQ(map.input.too_far, 1u);
  EXPECT_EQ(map.cloud.size(), 8u);
  EXPECT_TRUE(CheckTopology(map.mesh.triangles).watertight());
  EXPECT_THROW((void)ComputeGhpr(huge, Vec3::Zero(), Ghpr::Config{}), std::invalid_argument);
  // A rejected gamma is named in a short line.
  Ghpr::Config linear{GhprKernel::kLinear, 1e300};
  try {
    linear.Validate();
    FAIL() << "gamma 1e300 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_LT(std::string(e.what()).size(), 120u) << e.what();
    EXPECT_NE(std::string(e.what()).find("1e+300"), std::string::npos) << e.what();
  }
}

TEST(OvpcMapperTest, BadCloudsGiveAStatusNotACrash) {
  const OvpcMapper mapper;
  EXPECT_EQ(mapper.Update({}, Vec3::Zero()).status, GhprStatus::kTooFewPoints);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const OvpcMap all_nan = mapper.Update(Points(100, Vec3(nan, nan, nan)), Vec3::Zero());
  EXPECT_EQ(all_nan.status, GhprStatus::kTooFewPoints);
  EXPECT_EQ(all_nan.input.non_finite, 100u);
  EXPECT_EQ(mapper.Update(Points(50, Vec3::Zero()), Vec3::Zero()).status, GhprStatus::kTooFewPoints);
  const Points plane = testing::Grid(-2, 2, -2, 2, 1.0, 0.5);
  const OvpcMap flat = mapper.Update(plane, Vec3(0, 0, 1.0));
  EXPECT_EQ(flat.status, GhprStatus::kDegenerate);
  EXPECT_FALSE(flat.message.empty());
  EXPECT_TRUE(flat.cloud.empty());
  EXPECT_EQ(mapper.Update(plane, Vec3(nan, 0, 0)).status, GhprStatus::kDegenerate);
}

TEST(OvpcMapperTest, InvalidConfigThrowsNamingTheField) {
  OvpcMapper::Config config;
  config.ghpr.gamma = 0.5;
  try {
    OvpcMapper mapper(config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gamma"), std::string::npos);
  }
}

TEST(OvpcMapperTest, FlatGroundIsTraversableAwayFromTheRim) {
  const Points ground = testing::Grid(-10, 10, -10, 10, 0.0, 0.25);
  const OvpcMap map = OvpcMapper().Update(ground, Vec3(0.0, 0.0, 1.88));
  ASSERT_TRUE(map.ok());
  int inner = 0, inner_traversable = 0;
  for (std::size_t i = 0; i < map.cloud.size(); ++i) {
    const Vec3& p = map.cloud.points()[i];
    if (p.head<2>().cwiseAbs().maxCoeff() > 8.0) continue;
    ++inner;
    inner_traversable += map.cloud.traversable()[i];
    EXPECT_NEAR(map.cloud.normals()[i].z(), 1.0, 1e-9);
  }
  EXPECT_GT(inner, 1000);
  EXPECT_EQ(inner_traversable, inner);
}

}  // namespace
}  // namespace ovpc
