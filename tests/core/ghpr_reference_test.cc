// The fast incremental hull must give exactly the mesh of CGAL's quickhull (the reference path), on
// many seeded clouds, including degenerate ones that it hands over to CGAL.
#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "../support/test_clouds.h"
#include "ovpc/core/ghpr.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc {
namespace {

// Triangles as sorted-rotation triples of input indices (-1 = viewpoint): independent of the order
// a hull algorithm emits faces and of where each triangle starts.
std::set<std::array<int, 3>> CanonicalFaces(const GhprResult& r) {
  std::set<std::array<int, 3>> faces;
  for (const Triangle& t : r.mesh.triangles) {
    std::array<int, 3> f = {r.mesh.source_index[t[0]], r.mesh.source_index[t[1]], r.mesh.source_index[t[2]]};
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    faces.insert(f);
  }
  return faces;
}

// Runs both paths; returns whether the fast path handled the cloud itself.
bool ExpectSameAsReference(const Points& points, const Vec3& viewpoint, Ghpr::Config config = {}) {
  config.reference_hull = false;
  const GhprResult fast = ComputeGhpr(points, viewpoint, config);
  config.reference_hull = true;
  const GhprResult ref = ComputeGhpr(points, viewpoint, config);
  EXPECT_EQ(fast.status, ref.status);
  if (fast.status != GhprStatus::kOk) return !fast.used_reference_hull;
  EXPECT_TRUE(ref.used_reference_hull);
  EXPECT_EQ(fast.mesh.source_index, ref.mesh.source_index) << "visible sets differ";
  EXPECT_EQ(fast.viewpoint_on_hull, ref.viewpoint_on_hull);
  EXPECT_EQ(CanonicalFaces(fast), CanonicalFaces(ref)) << "meshes differ";
  EXPECT_TRUE(CheckTopology(fast.mesh.triangles).watertight());
  return !fast.used_reference_hull;
}

TEST(GhprReferenceTest, OutdoorCloudsMatchCgalAndUseTheFastPath) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    for (std::size_t n : {2000u, 9000u}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " n " << n);
      EXPECT_TRUE(ExpectSameAsReference(synth::MakeOutdoorCloud(n, seed), Vec3::Zero()));
    }
  }
}

TEST(GhprReferenceTest, RandomCloudsBothKernelsAndViewpointsMatchCgal) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    const int n = 50 + trial * 60;
    Points pts(n);
    for (Vec3& p : pts) p = Vec3(u(rng), u(rng), 0.3 * u(rng));
    // Viewpoint inside the cloud, and outside it (then it is on the hull).
    const Vec3 viewpoint = trial % 2 ? Vec3(0.5, -0.3, 0.2) : Vec3(0.0, 0.0, 12.0);
    Ghpr::Config config;
    if (trial % 3 == 0) {
      config.kernel = GhprKernel::kLinear;
      config.gamma = 60.0;
    } else if (trial % 3 == 1) {
      config.gamma = -0.3;
    }
    EXPECT_TRUE(ExpectSameAsReference(pts, viewpoint, config));
  }
}

TEST(GhprReferenceTest, PointsOnASphereMatchCgal) {
  // All points on a sphere around the viewpoint: every point is visible.
  std::mt19937 rng(9);
  std::normal_distribution<double> g;
  Points pts(3000);
  for (Vec3& p : pts) p = 4.0 * Vec3(g(rng), g(rng), g(rng)).normalized();
  ExpectSameAsReference(pts, Vec3::Zero());
  const GhprResult r = ComputeGhpr(pts, Vec3::Zero(), {});
  EXPECT_EQ(r.mesh.num_visible(), pts.size());
}

TEST(GhprReferenceTest, DegenerateCloudsAreHandedToCgalAndStillMatch) {
  // Exact duplicates.
  Points dup = synth::MakeOutdoorCloud(2000, 3);
  for (std::size_t i = 0; i < 2000; i += 7) dup.push_back(dup[i]);
  ExpectSameAsReference(dup, Vec3::Zero());
  // Coplanar groups: grids on axis planes (a box room) and flat ground from above.
  EXPECT_FALSE(ExpectSameAsReference(testing::BoxRoom(Vec3(3, 2, 1.5), 0.25), Vec3(0.3, -0.2, 0.1)))
      << "a grid room has coplanar image points; expected the CGAL fallback";
  ExpectSameAsReference(testing::Grid(-6, 6, -6, 6, 0.0, 0.3), Vec3(0, 0, 1.88));
  // Ground grid with a roof grid and a post, viewpoint between them.
  Points scene = testing::Grid(-8, 8, -8, 8, 0.0, 0.4);
  const Points roof = testing::Grid(1, 5, -2, 2, 2.5, 0.25);
  scene.insert(scene.end(), roof.begin(), roof.end());
  ExpectSameAsReference(scene, Vec3(0, 0, 1.88));
  // Coplanar with the viewpoint: both report degenerate.
  ExpectSameAsReference(testing::Grid(-2, 2, -2, 2, 0.0, 0.5), Vec3(0.1, 0.2, 0.0));
  // A handful of points.
  ExpectSameAsReference({Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-1, -1, -1)}, Vec3(0.01, 0.02, 0.03));
}

TEST(GhprReferenceTest, RepeatedCallsReuseBuffersAndAgree) {
  const Points a = synth::MakeOutdoorCloud(6000, 4);
  const Points b = synth::MakeOutdoorCloud(3000, 5);
  const auto first = CanonicalFaces(ComputeGhpr(a, Vec3::Zero(), {}));
  ComputeGhpr(b, Vec3::Zero(), {});  // a smaller cloud in between
  EXPECT_EQ(CanonicalFaces(ComputeGhpr(a, Vec3::Zero(), {})), first);
}

}  // namespace
}  // namespace ovpc
