#include "ovpc/core/vertex_cloud.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ovpc/core/traversability.h"

namespace ovpc {
namespace {

TraversabilityCloud RandomCloud(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  Points pts(n);
  for (Vec3& p : pts) p = Vec3(u(rng), u(rng), 0.2 * u(rng));
  return TraversabilityCloud(pts, std::vector<Vec3>(n, Vec3::UnitZ()), std::vector<std::uint8_t>(n, 1));
}

TEST(VertexCloudTest, QueriesMatchBruteForce) {
  const TraversabilityCloud cloud = RandomCloud(3000, 3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-11.0, 11.0);
  for (int q = 0; q < 50; ++q) {
    const Vec3 query(u(rng), u(rng), 0.1 * u(rng));
    int best = -1;
    double best_d = 1e300;
    std::vector<int> within;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const double d = (cloud.points()[i] - query).norm();
      if (d < best_d) best_d = d, best = static_cast<int>(i);
      if (d <= 1.5) within.push_back(static_cast<int>(i));
    }
    const auto nearest = cloud.Nearest(query);
    ASSERT_TRUE(nearest.has_value());
    EXPECT_EQ(nearest->index, best);
    EXPECT_NEAR(nearest->distance_m, best_d, 1e-12);

    // The k nearest: the first k of all points sorted by distance (ties are measure-zero here).
    std::vector<std::pair<double, int>> by_distance;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      by_distance.push_back({(cloud.points()[i] - query).norm(), static_cast<int>(i)});
    }
    std::sort(by_distance.begin(), by_distance.end());
    std::vector<TraversabilityCloud::Neighbor> knn;
    cloud.KNearest(query, 7, &knn);
    ASSERT_EQ(knn.size(), 7u);
    for (std::size_t k = 0; k < knn.size(); ++k) {
      EXPECT_EQ(knn[k].index, by_distance[k].second);
      EXPECT_NEAR(knn[k].distance_m, by_distance[k].first, 1e-12);
    }

    const auto found = cloud.WithinRadius(query, 1.5);
    std::vector<int> got;
    for (const auto& nb : found) got.push_back(nb.index);
    EXPECT_TRUE(std::is_sorted(found.begin(), found.end(),
                               [](const auto& a, const auto& b) { return a.distance_m < b.distance_m; }));
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, within);

    // An oriented box: 4 x 2 x 1 m, yawed 30 deg and pitched 10 deg.
    Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();
    T_L_B.translation() = query;
    T_L_B.linear() = (Eigen::AngleAxisd(DegToRad(30), Vec3::UnitZ()) *
                      Eigen::AngleAxisd(DegToRad(10), Vec3::UnitY())).toRotationMatrix();
    const Vec3 half(2.0, 1.0, 0.5);
    std::vector<int> in_box;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const Vec3 p_B = T_L_B.inverse() * cloud.points()[i];
      if ((p_B.cwiseAbs().array() <= half.array()).all()) in_box.push_back(static_cast<int>(i));
    }
    EXPECT_EQ(cloud.InBox(T_L_B, half), in_box);
  }
}

TEST(VertexCloudTest, EmptyCloudAnswersNothing) {
  const TraversabilityCloud cloud;
  EXPECT_TRUE(cloud.empty());
  EXPECT_FALSE(cloud.Nearest(Vec3::Zero()).has_value());
  EXPECT_TRUE(cloud.WithinRadius(Vec3::Zero(), 5.0).empty());
  std::vector<TraversabilityCloud::Neighbor> knn = {{0, 1.0}};
  cloud.KNearest(Vec3::Zero(), 3, &knn);
  EXPECT_TRUE(knn.empty());
  EXPECT_TRUE(cloud.InBox(Eigen::Isometry3d::Identity(), Vec3::Ones()).empty());
  EXPECT_THROW(TraversabilityCloud({Vec3::Zero()}, {}, {}), std::invalid_argument);
}

TEST(VertexCloudTest, CopiesShareDataAndStayValid) {
  TraversabilityCloud copy;
  {
    const TraversabilityCloud original = RandomCloud(500, 9);
    copy = original;
  }
  ASSERT_EQ(copy.size(), 500u);
  const auto nb = copy.Nearest(copy.points()[123]);
  ASSERT_TRUE(nb.has_value());
  EXPECT_EQ(nb->index, 123);
}

TEST(VertexCloudTest, NormalIsTheMeanOfAdjacentFacesAndFlagNeedsAllFaces) {
  // A tetrahedron-like fan: vertex 0 shared by a flat face and a 40 deg face; the viewpoint closes it.
  FreeSpaceMesh mesh;
  const double a = DegToRad(40.0);
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-std::cos(a), 0, std::sin(a)),
                   Vec3(0, 0, 5)};
  mesh.source_index = {0, 1, 2, 3, -1};
  mesh.viewpoint_vertex = 4;
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}};  // not closed; enough for the per-vertex rules
  ClassifyFaces(Traversability::Config{}, &mesh);
  ASSERT_EQ(mesh.face_traversable[0], 1);
  ASSERT_EQ(mesh.face_traversable[1], 0);
  VertexNormals::Config mean_of_faces;
  mean_of_faces.rule = VertexNormals::Rule::kMeanOfFaces;
  const TraversabilityCloud cloud = BuildTraversabilityCloud(mesh, mean_of_faces);
  ASSERT_EQ(cloud.size(), 4u);
  const Vec3 expected = (mesh.face_normals[0] + mesh.face_normals[1]).normalized();
  EXPECT_TRUE(cloud.normals()[0].isApprox(expected, 1e-12));
  EXPECT_EQ(cloud.traversable()[0], 0);  // one adjacent face is too steep
  // Vertex 1 has the flat face and a viewpoint face: the normal ignores the viewpoint face, the flag
  // does not.
  EXPECT_TRUE(cloud.normals()[1].isApprox(mesh.face_normals[0], 1e-12));
  EXPECT_EQ(cloud.traversable()[1], 0);
}

// A foot is a non-traversable point whose steep faces all rise from it, higher than a step and close
// by (a wall's foot); a lip, whose steep face falls away from it, is not one, nor is the wall's point
// above the foot, a point with no face, ground far past a post, or a steep ramp's foot.
TEST(VertexCloudTest, FeetAreWhereSteepFacesRiseNotWhereTheyFall) {
  FreeSpaceMesh mesh;
  // 0-1: ground at a wall's foot, 2: on the wall 1 m up, 3: ground before it (a flat face with 0-1);
  // 4-5: a lip at z = 0, 6: the bottom of a drop 1 m below it (a steep face falling from 4-5), 7: a
  // point with no face; 8-9: ground 3 m past the top of a 2 m post at 10 (a face across its shadow);
  // 11-12: the foot of a 45 deg ramp whose next point 13 is 0.1 m higher (no step); 14: the viewpoint.
  mesh.vertices = {Vec3(0, 0, 0),  Vec3(0, 1, 0),  Vec3(0.3, 0.5, 1.0), Vec3(-1, 0.5, 0.02), Vec3(5, 0, 0),
                   Vec3(5, 1, 0),  Vec3(5.3, 0.5, -1.0), Vec3(9, 9, 0),  Vec3(3, 5, 0),      Vec3(3, 6, 0),
                   Vec3(0, 5.5, 2.0), Vec3(6, 6, 0), Vec3(6, 7, 0), Vec3(6.1, 6.5, 0.1), Vec3(-3, 0, 1.88)};
  mesh.source_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, -1};
  mesh.viewpoint_vertex = 14;
  // Normals towards free space.
  mesh.triangles = {{1, 0, 2}, {0, 1, 3}, {5, 4, 6}, {4, 5, 3}, {8, 9, 10}, {12, 11, 13}};
  ClassifyFaces(Traversability::Config{}, &mesh);
  ASSERT_EQ(mesh.face_traversable[0], 0);
  ASSERT_EQ(mesh.face_traversable[1], 1);
  ASSERT_EQ(mesh.face_traversable[2], 0);
  ASSERT_EQ(mesh.face_traversable[4], 0);
  ASSERT_EQ(mesh.face_traversable[5], 0);
  const TraversabilityCloud cloud = BuildTraversabilityCloud(mesh);
  ASSERT_EQ(cloud.size(), 14u);
  for (int i : {0, 1, 4, 5}) EXPECT_EQ(cloud.traversable()[i], 0) << i;
  EXPECT_TRUE(cloud.IsFoot(0));
  EXPECT_TRUE(cloud.IsFoot(1));
  EXPECT_FALSE(cloud.IsFoot(2));  // its steep face falls to the ground
  EXPECT_FALSE(cloud.IsFoot(3));  // traversable
  EXPECT_FALSE(cloud.IsFoot(4));  // a lip
  EXPECT_FALSE(cloud.IsFoot(5));
  EXPECT_TRUE(cloud.IsFoot(6));   // the drop's bottom: its face rises from it
  EXPECT_FALSE(cloud.IsFoot(7));  // no face
  EXPECT_EQ(cloud.traversable()[8], 0);
  EXPECT_FALSE(cloud.IsFoot(8));  // its face rises 3 m away, across a shadow
  EXPECT_FALSE(cloud.IsFoot(9));
  EXPECT_EQ(cloud.traversable()[11], 0);
  EXPECT_FALSE(cloud.IsFoot(11));  // the ramp rises 0.1 m from it: a slope, not an obstacle
  EXPECT_FALSE(cloud.IsFoot(12));
  EXPECT_FALSE(cloud.IsFoot(100));
  // A cloud made from flags alone knows no feet.
  const TraversabilityCloud flags(cloud.points(), cloud.normals(), cloud.traversable());
  EXPECT_FALSE(flags.IsFoot(0));
}

}  // namespace
}  // namespace ovpc
