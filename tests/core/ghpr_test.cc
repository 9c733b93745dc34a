#include "ovpc/core/ghpr.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "../support/test_clouds.h"

namespace ovpc {
namespace {

std::vector<int> VisibleSources(const GhprResult& r) {
  std::vector<int> v;
  for (int s : r.mesh.source_index) {
    if (s >= 0) v.push_back(s);
  }
  return v;
}

TEST(GhprTest, BoxRoomSeenFromInsideIsFullyVisibleWatertightAndEnclosesTheRoom) {
  const Vec3 half(3.0, 2.0, 1.5);  // 6 x 4 x 3 m = 72 m^3
  const Points room = testing::BoxRoom(half, 0.5);
  const GhprResult r = ComputeGhpr(room, Vec3(0.3, -0.2, 0.1), Ghpr::Config{});
  ASSERT_EQ(r.status, GhprStatus::kOk) << r.message;
  EXPECT_FALSE(r.viewpoint_on_hull);
  EXPECT_EQ(r.mesh.num_visible(), room.size());
  const MeshTopology topo = CheckTopology(r.mesh.triangles);
  EXPECT_TRUE(topo.watertight()) << "chi=" << topo.euler_characteristic;
  EXPECT_EQ(topo.num_vertices, room.size());
  // The only cut is along the room's edges between neighbouring grid points.
  EXPECT_NEAR(EnclosedVolume(r.mesh.vertices, r.mesh.triangles), 72.0, 0.72);
}

TEST(GhprTest, DenseRoomWithSmallGammaKeepsEveryPointAndTheExactVolume) {
  const Points room = testing::BoxRoom(Vec3(3.0, 2.0, 1.5), 0.1);
  Ghpr::Config config;
  config.gamma = -0.001;
  const GhprResult r = ComputeGhpr(room, Vec3(0.3, -0.2, 0.1), config);
  ASSERT_EQ(r.status, GhprStatus::kOk);
  EXPECT_EQ(r.mesh.num_visible(), room.size());
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
  EXPECT_NEAR(EnclosedVolume(r.mesh.vertices, r.mesh.triangles), 72.0, 1e-6);
}

TEST(GhprTest, DenseRoomWithPaperGammaHidesOnlyPointsNearConcaveEdges) {
  // With gamma = -0.03 a concave room edge becomes a shallow dent in image space; neighbours closer
  // than about 2|gamma| rad to the edge bridge it. Everything hidden must be near an edge.
  const Vec3 half(3.0, 2.0, 1.5);
  const Points room = testing::BoxRoom(half, 0.1);
  const GhprResult r = ComputeGhpr(room, Vec3(0.3, -0.2, 0.1), Ghpr::Config{});
  ASSERT_EQ(r.status, GhprStatus::kOk);
  std::vector<char> visible(room.size(), 0);
  for (int s : VisibleSources(r)) visible[s] = 1;
  int hidden = 0;
  for (std::size_t i = 0; i < room.size(); ++i) {
    if (visible[i]) continue;
    ++hidden;
    const Vec3 gap = half - room[i].cwiseAbs();
    std::vector<double> g = {gap.x(), gap.y(), gap.z()};
    std::sort(g.begin(), g.end());
    EXPECT_LT(g[1], 0.45) << "hidden point far from any room edge: " << room[i].transpose();
  }
  EXPECT_GT(hidden, 0);
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
}

TEST(GhprTest, WallHidesTheObjectBehindIt) {
  Points pts;
  for (double y = -3.0; y <= 3.0 + 1e-9; y += 0.2) {
    for (double z = -1.5; z <= 2.0 + 1e-9; z += 0.2) pts.emplace_back(5.0, y, z);
  }
  const std::size_t wall_end = pts.size();
  for (double y = -0.5; y <= 0.5 + 1e-9; y += 0.1) {
    for (double z = -0.5; z <= 0.5 + 1e-9; z += 0.1) {
      pts.emplace_back(7.0, y, z);  // face of a cube behind the wall
      pts.emplace_back(7.0 + (y + 0.5), y, 0.5);  // its top
    }
  }
  const GhprResult r = ComputeGhpr(pts, Vec3::Zero(), Ghpr::Config{});
  ASSERT_EQ(r.status, GhprStatus::kOk);
  EXPECT_TRUE(r.viewpoint_on_hull);  // nothing behind the viewpoint
  std::size_t wall_visible = 0;
  for (int s : VisibleSources(r)) {
    EXPECT_LT(static_cast<std::size_t>(s), wall_end) << "object point " << pts[s].transpose() << " seen through the wall";
    wall_visible += static_cast<std::size_t>(s) < wall_end;
  }
  EXPECT_EQ(wall_visible, wall_end);
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
  EXPECT_GT(EnclosedVolume(r.mesh.vertices, r.mesh.triangles), 0.0);
}

TEST(GhprTest, ExponentialKernelIsScaleInvariant) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  Points pts(2000);
  for (Vec3& p : pts) p = Vec3(u(rng), u(rng), u(rng));
  Points scaled = pts;
  for (Vec3& p : scaled) p *= 4.0;
  const GhprResult a = ComputeGhpr(pts, Vec3::Zero(), Ghpr::Config{});
  const GhprResult b = ComputeGhpr(scaled, Vec3::Zero(), Ghpr::Config{});
  ASSERT_EQ(a.status, GhprStatus::kOk);
  ASSERT_EQ(b.status, GhprStatus::kOk);
  EXPECT_EQ(VisibleSources(a), VisibleSources(b));
}

TEST(GhprTest, LinearKernelGivesAWatertightMeshAndChecksGamma) {
  const Points room = testing::BoxRoom(Vec3(3.0, 2.0, 1.5), 0.25);
  Ghpr::Config config;
  config.kernel = GhprKernel::kLinear;
  config.gamma = 100.0;
  const GhprResult r = ComputeGhpr(room, Vec3(0.3, -0.2, 0.1), config);
  ASSERT_EQ(r.status, GhprStatus::kOk);
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
  EXPECT_GT(EnclosedVolume(r.mesh.vertices, r.mesh.triangles), 60.0);

  config.gamma = 2.0;  // smaller than the farthest corner (about 4 m)
  EXPECT_EQ(ComputeGhpr(room, Vec3::Zero(), config).status, GhprStatus::kGammaTooSmall);
}

TEST(GhprTest, GammaOfTheWrongSignIsRejected) {
  const Points room = testing::BoxRoom(Vec3(1, 1, 1), 0.5);
  Ghpr::Config config;
  config.gamma = 0.03;
  EXPECT_THROW(ComputeGhpr(room, Vec3::Zero(), config), std::invalid_argument);
  config.kernel = GhprKernel::kLinear;
  config.gamma = -5.0;
  EXPECT_THROW(ComputeGhpr(room, Vec3::Zero(), config), std::invalid_argument);
  EXPECT_THROW(ParseKernel("cubic"), std::invalid_argument);
  EXPECT_EQ(ParseKernel("linear"), GhprKernel::kLinear);
}

// Past these bounds the image points overflow or collapse: gamma -103 with a point 1 mm from the
// viewpoint made an inf image point that crashed the exact hull (SIGFPE), -300 took 74 s.
TEST(GhprTest, GammaOutsideItsWellConditionedRangeIsRejected) {
  Points room = testing::BoxRoom(Vec3(1, 1, 1), 0.5);
  room.push_back(Vec3(1e-3, 0.0, 0.0));
  Ghpr::Config config;
  for (double gamma : {-103.0, -300.0, -1.0001}) {
    config.gamma = gamma;
    EXPECT_THROW(ComputeGhpr(room, Vec3::Zero(), config), std::invalid_argument) << gamma;
  }
  config.gamma = -1.0;
  EXPECT_EQ(ComputeGhpr(room, Vec3::Zero(), config).status, GhprStatus::kOk);
  config.kernel = GhprKernel::kLinear;
  for (double gamma : {1e308, 1e160, 1.1e7}) {
    config.gamma = gamma;
    EXPECT_THROW(ComputeGhpr(room, Vec3::Zero(), config), std::invalid_argument) << gamma;
  }
}

TEST(GhprTest, TooFewAndDegenerateCloudsGiveAStatus) {
  EXPECT_EQ(ComputeGhpr({Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, Vec3::Zero(), {}).status,
            GhprStatus::kTooFewPoints);
  // Coplanar with the viewpoint: no volume.
  const Points plane = testing::Grid(-2, 2, -2, 2, 0.0, 0.5);
  EXPECT_EQ(ComputeGhpr(plane, Vec3(0.1, 0.2, 0.0), {}).status, GhprStatus::kDegenerate);
  Points line;
  for (int i = 1; i < 10; ++i) line.emplace_back(i, 2.0 * i, 0.5 * i);
  EXPECT_EQ(ComputeGhpr(line, Vec3::Zero(), {}).status, GhprStatus::kDegenerate);
  // An oblique plane through the viewpoint: exactly coplanar as given, though the rounded image
  // points are not (this gave "100 % visible, watertight" and a zero-volume mesh).
  Points oblique;
  for (int i = 0; i < 1000; ++i) oblique.emplace_back(-10.0 + 0.02 * i, 5.0, -1.0);
  EXPECT_EQ(ComputeGhpr(oblique, Vec3::Zero(), {}).status, GhprStatus::kDegenerate);
  Points tilted;  // points on the plane x + 2y + 3z = 0 through the origin
  for (int i = -10; i <= 10; ++i) {
    for (int j = -10; j <= 10; ++j) {
      if (i != 0 || j != 0) tilted.emplace_back(3.0 * i, 3.0 * j, -(3.0 * i + 6.0 * j) / 3.0);
    }
  }
  EXPECT_EQ(ComputeGhpr(tilted, Vec3::Zero(), {}).status, GhprStatus::kDegenerate);
  // The same plane seen from above is the normal case of flat ground.
  const GhprResult ground = ComputeGhpr(plane, Vec3(0.1, 0.2, 1.88), {});
  ASSERT_EQ(ground.status, GhprStatus::kOk);
  EXPECT_TRUE(ground.viewpoint_on_hull);
  EXPECT_TRUE(CheckTopology(ground.mesh.triangles).watertight());
}

TEST(GhprTest, PointsAtTheViewpointBreakThePrecondition) {
  Points pts = testing::BoxRoom(Vec3(1, 1, 1), 0.5);
  pts.push_back(Vec3::Zero());
  EXPECT_THROW(ComputeGhpr(pts, Vec3::Zero(), {}), std::invalid_argument);
}

TEST(GhprTest, DuplicatesAndCoplanarGroupsStayWatertight) {
  Points pts = testing::BoxRoom(Vec3(2, 2, 1), 0.5);
  const std::size_t n = pts.size();
  for (std::size_t i = 0; i < n; i += 3) pts.push_back(pts[i]);  // exact duplicates
  const GhprResult r = ComputeGhpr(pts, Vec3(0.1, 0.05, -0.2), {});
  ASSERT_EQ(r.status, GhprStatus::kOk);
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
  // A duplicate pair is one hull vertex.
  EXPECT_LE(r.mesh.num_visible(), n);
}

TEST(GhprTest, DuplicatesInGeneralPositionStayOnTheFastHullWithTheSameVisibleSet) {
  // Points at random directions and ranges (general position), then 15 % of them repeated exactly,
  // as a scanner's self-hits are: the duplicates must not push the hull onto the slow path.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), range(4.0, 20.0);
  Points pts;
  while (pts.size() < 3000) {
    const Vec3 dir(u(rng), u(rng), 0.3 * u(rng));
    if (dir.norm() > 0.1) pts.push_back(dir.normalized() * range(rng));
  }
  const GhprResult plain = ComputeGhpr(pts, Vec3::Zero(), {});
  ASSERT_EQ(plain.status, GhprStatus::kOk);
  ASSERT_FALSE(plain.used_reference_hull);
  Points dup = pts;
  for (std::size_t i = 0; i < pts.size(); i += 7) dup.push_back(pts[i]);
  const GhprResult r = ComputeGhpr(dup, Vec3::Zero(), {});
  ASSERT_EQ(r.status, GhprStatus::kOk);
  EXPECT_FALSE(r.used_reference_hull);
  EXPECT_TRUE(CheckTopology(r.mesh.triangles).watertight());
  // The same visible points, each once, by its first index; the same hull.
  EXPECT_EQ(VisibleSources(r), VisibleSources(plain));
  EXPECT_EQ(r.mesh.triangles.size(), plain.mesh.triangles.size());
  // The reference hull (CGAL) agrees on the visible positions.
  Ghpr::Config reference;
  reference.reference_hull = true;
  const GhprResult ref = ComputeGhpr(dup, Vec3::Zero(), reference);
  ASSERT_EQ(ref.status, GhprStatus::kOk);
  EXPECT_EQ(ref.mesh.num_visible(), r.mesh.num_visible());
}

TEST(GhprTest, GroundFacesPointUpIntoFreeSpace) {
  const Points ground = testing::Grid(-5, 5, -5, 5, 0.0, 0.5);
  const GhprResult r = ComputeGhpr(ground, Vec3(0.0, 0.0, 1.88), {});
  ASSERT_EQ(r.status, GhprStatus::kOk);
  int up = 0, observed = 0;
  for (std::size_t f = 0; f < r.mesh.triangles.size(); ++f) {
    if (r.mesh.TouchesViewpoint(f)) continue;
    const auto& t = r.mesh.triangles[f];
    const Vec3 n = (r.mesh.vertices[t[1]] - r.mesh.vertices[t[0]]).cross(r.mesh.vertices[t[2]] - r.mesh.vertices[t[0]]);
    if (n.squaredNorm() == 0.0) {
      // Collinear grid points on the rim: the hull facet through the viewpoint and a grid edge line
      // is triangulated among the line's own points. Such faces exist only on the border.
      for (int v : t) EXPECT_DOUBLE_EQ(r.mesh.vertices[v].head<2>().cwiseAbs().maxCoeff(), 5.0);
      continue;
    }
    ++observed;
    up += n.z() > 0.0;
  }
  EXPECT_GT(observed, 300);
  EXPECT_EQ(up, observed);
}

}  // namespace
}  // namespace ovpc
