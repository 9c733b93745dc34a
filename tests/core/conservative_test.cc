// Conservativeness: the mesh volume is free space, so no input point may lie inside it. Checked
// independently of GHPR with CGAL's point-in-mesh test and the point-to-mesh distance.
#include <random>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include "../support/test_clouds.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

struct InsideCount {
  std::size_t inside_by_more_than_1cm = 0;
  double deepest_m = 0.0;
};

InsideCount CountPointsInside(const FreeSpaceMesh& fsm, const Points& points) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> v;
  for (const Vec3& p : fsm.vertices) v.push_back(mesh.add_vertex(K::Point_3(p.x(), p.y(), p.z())));
  for (const Triangle& t : fsm.triangles) {
    const Vec3 n = (fsm.vertices[t[1]] - fsm.vertices[t[0]]).cross(fsm.vertices[t[2]] - fsm.vertices[t[0]]);
    if (n.squaredNorm() == 0.0) continue;  // zero-area faces bound no volume
    mesh.add_face(v[t[0]], v[t[1]], v[t[2]]);
  }
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  CGAL::Side_of_triangle_mesh<Mesh, K> side(tree);
  InsideCount count;
  for (const Vec3& p : points) {
    const K::Point_3 q(p.x(), p.y(), p.z());
    if (side(q) != CGAL::ON_BOUNDED_SIDE) continue;
    const double depth = std::sqrt(tree.squared_distance(q));
    count.deepest_m = std::max(count.deepest_m, depth);
    if (depth > 0.01) ++count.inside_by_more_than_1cm;
  }
  return count;
}

void ExpectConservative(const Points& points, const Vec3& viewpoint, const Ghpr::Config& ghpr) {
  OvpcMapper::Config config;
  config.ghpr = ghpr;
  const OvpcMap map = OvpcMapper(config).Update(points, viewpoint);
  ASSERT_TRUE(map.ok()) << map.message;
  ASSERT_TRUE(CheckTopology(map.mesh.triangles).watertight());
  ASSERT_LT(map.mesh.num_visible(), points.size()) << "the cloud should hide some points";
  const InsideCount c = CountPointsInside(map.mesh, points);
  EXPECT_EQ(c.inside_by_more_than_1cm, 0u) << "deepest " << c.deepest_m << " m";
}

TEST(ConservativeTest, TheCheckFindsPointsThatAreInside) {
  // Control: points pulled halfway towards the viewpoint from visible vertices are inside.
  const Points cloud = synth::MakeOutdoorCloud(6000, 1);
  const OvpcMap map = OvpcMapper().Update(cloud, Vec3::Zero());
  ASSERT_TRUE(map.ok());
  Points probes;
  for (std::size_t i = 0; i < map.cloud.size(); i += 10) {
    if (map.cloud.points()[i].norm() > 3.0) probes.push_back(0.5 * map.cloud.points()[i]);
  }
  ASSERT_GT(probes.size(), 100u);
  const InsideCount c = CountPointsInside(map.mesh, probes);
  EXPECT_GT(c.inside_by_more_than_1cm, probes.size() * 9 / 10);
}

TEST(ConservativeTest, GeneratedOutdoorCloudsHaveNoPointInsideTheMesh) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    ExpectConservative(synth::MakeOutdoorCloud(6000, seed), Vec3::Zero(), Ghpr::Config{});
  }
}

TEST(ConservativeTest, RandomClutterHasNoPointInsideTheMeshForBothKernels) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-8.0, 8.0);
  Points pts(4000);
  for (Vec3& p : pts) {
    do {
      p = Vec3(u(rng), u(rng), 0.4 * u(rng));
    } while (p.norm() < 0.5);
  }
  ExpectConservative(pts, Vec3::Zero(), Ghpr::Config{});
  Ghpr::Config gentle;
  gentle.gamma = -0.01;
  ExpectConservative(pts, Vec3::Zero(), gentle);
  Ghpr::Config linear;
  linear.kernel = GhprKernel::kLinear;
  linear.gamma = 40.0;
  ExpectConservative(pts, Vec3::Zero(), linear);
}

TEST(ConservativeTest, GroundWithPostsAndARoofHasNoPointInsideTheMesh) {
  Points pts = testing::Grid(-12, 12, -12, 12, 0.0, 0.3);
  const Points roof = testing::Grid(2.0, 7.0, -2.5, 2.5, 2.5, 0.2);
  pts.insert(pts.end(), roof.begin(), roof.end());
  for (double x : {-4.0, 3.0, 8.0}) {  // posts of radius 0.1 m
    for (double z = 0.1; z < 3.0; z += 0.1) {
      for (int k = 0; k < 12; ++k) {
        const double a = 2.0 * kPi * k / 12.0;
        pts.emplace_back(x + 0.1 * std::cos(a), 4.0 + 0.1 * std::sin(a), z);
      }
    }
  }
  ExpectConservative(pts, Vec3(0.0, 0.0, 1.88), Ghpr::Config{});
}

}  // namespace
}  // namespace ovpc
