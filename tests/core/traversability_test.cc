#include "ovpc/core/traversability.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <gtest/gtest.h>

#include "../support/test_clouds.h"
#include "ovpc/core/ovpc_mapper.h"

namespace ovpc {
namespace {

// One triangle whose normal (a->b->c, right hand) is tilted by `angle_rad` from up about the y axis.
FreeSpaceMesh TiltedTriangle(double angle_rad, double size_m) {
  FreeSpaceMesh mesh;
  const Vec3 u(std::cos(angle_rad), 0.0, -std::sin(angle_rad));  // downhill along +x
  const Vec3 v(0.0, 1.0, 0.0);
  mesh.vertices = {Vec3::Zero(), size_m * u, size_m * v};
  mesh.source_index = {0, 1, 2};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

TEST(TraversabilityTest, SurfaceAngleJustBelowAndAbove30Degrees) {
  Traversability::Config config;
  config.delta_h_max_m = 100.0;  // isolate the angle test
  for (double deg : {0.0, 10.0, 29.9}) {
    FreeSpaceMesh mesh = TiltedTriangle(DegToRad(deg), 1.0);
    ClassifyFaces(config, &mesh);
    EXPECT_NEAR(RadToDeg(std::acos(mesh.face_normals[0].z())), deg, 1e-9);
    EXPECT_EQ(mesh.face_traversable[0], 1) << deg << " deg";
  }
  for (double deg : {30.1, 45.0, 89.0, 120.0, 180.0}) {
    FreeSpaceMesh mesh = TiltedTriangle(DegToRad(deg), 1.0);
    ClassifyFaces(config, &mesh);
    EXPECT_EQ(mesh.face_traversable[0], 0) << deg << " deg";
  }
}

TEST(TraversabilityTest, HeightSpreadJustBelowAndAbove25Centimetres) {
  Traversability::Config config;
  // A 3 m triangle tilted so that its vertices span the given height: under 5 deg, far from 30.
  auto spread_mesh = [](double spread_m) {
    return TiltedTriangle(std::asin(spread_m / 3.0), 3.0);
  };
  for (double spread : {0.10, 0.249}) {
    FreeSpaceMesh mesh = spread_mesh(spread);
    ClassifyFaces(config, &mesh);
    EXPECT_EQ(mesh.face_traversable[0], 1) << spread;
  }
  for (double spread : {0.251, 0.40}) {
    FreeSpaceMesh mesh = spread_mesh(spread);
    ClassifyFaces(config, &mesh);
    EXPECT_EQ(mesh.face_traversable[0], 0) << spread;
  }
}

TEST(TraversabilityTest, NoiseFloorJudgesLowSliversByHeightAlone) {
  // A 5 cm sliver tilted 40 deg spans 3.2 cm: steep by the angle, flat by the noise floor.
  FreeSpaceMesh sliver = TiltedTriangle(DegToRad(40.0), 0.05);
  FreeSpaceMesh ceiling = TiltedTriangle(DegToRad(140.0), 0.05);
  FreeSpaceMesh slope = TiltedTriangle(DegToRad(40.0), 1.0);  // spans 0.64 m: a real slope
  FreeSpaceMesh fold = TiltedTriangle(DegToRad(100.0), 0.04);  // on edge, leaning over: noise
  Traversability::Config paper;
  ClassifyFaces(paper, &sliver);
  EXPECT_EQ(sliver.face_traversable[0], 0);
  Traversability::Config noisy;
  noisy.noise_floor_m = 0.05;
  ClassifyFaces(noisy, &sliver);
  ClassifyFaces(noisy, &ceiling);
  ClassifyFaces(noisy, &slope);
  ClassifyFaces(noisy, &fold);
  EXPECT_EQ(sliver.face_traversable[0], 1);
  EXPECT_EQ(fold.face_traversable[0], 1) << "a low fold of noisy ground is ground";
  EXPECT_EQ(ceiling.face_traversable[0], 0) << "a face looking down is never ground";
  EXPECT_EQ(slope.face_traversable[0], 0);
  noisy.noise_floor_m = 0.3;  // not below delta_h_max
  EXPECT_THROW(noisy.Validate(), std::invalid_argument);
}

// A 0.2 m grid on a plane rising along +x at `slope_deg`, each vertex moved along z by up to
// +-`noise_m` (a fixed pseudo-random pattern), triangulated with normals facing up.
FreeSpaceMesh NoisySlope(double slope_deg, double noise_m, double spacing_m = 0.2) {
  FreeSpaceMesh mesh;
  constexpr int kN = 21;
  std::uint32_t state = 12345;
  const auto next = [&state]() {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / static_cast<double>(1u << 24) * 2.0 - 1.0;
  };
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      const double x = spacing_m * i, y = spacing_m * j;
      mesh.vertices.emplace_back(x, y, x * std::tan(DegToRad(slope_deg)) + noise_m * next());
      mesh.source_index.push_back(static_cast<int>(mesh.source_index.size()));
    }
  }
  for (int i = 0; i + 1 < kN; ++i) {
    for (int j = 0; j + 1 < kN; ++j) {
      const int a = i * kN + j, b = (i + 1) * kN + j, c = (i + 1) * kN + j + 1, d = i * kN + j + 1;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  return mesh;
}

int CountTraversable(const FreeSpaceMesh& mesh) {
  int n = 0;
  for (auto t : mesh.face_traversable) n += t;
  return n;
}

TEST(TraversabilityTest, NoiseFloorOnASlopeJudgesSliversAgainstTheLocalSurface) {
  // On a 25 deg slope, 4 cm of noise tilts many 0.2 m faces past 30 deg; the paper's rule rejects
  // them, the noise floor (relief across the local surface) keeps them. A 35 deg slope with the same
  // noise stays non-traversable: its local surface fails the angle test.
  Traversability::Config paper;
  Traversability::Config noisy;
  noisy.noise_floor_m = 0.05;
  noisy.noise_floor_on_slopes = true;
  Traversability::Config flat_only;
  flat_only.noise_floor_m = 0.05;
  FreeSpaceMesh gentle = NoisySlope(25.0, 0.02);
  const int faces = static_cast<int>(gentle.triangles.size());
  ClassifyFaces(paper, &gentle);
  const int gentle_paper = CountTraversable(gentle);
  EXPECT_LT(gentle_paper, faces * 95 / 100) << "the noise must matter for the paper's rule";
  ClassifyFaces(flat_only, &gentle);
  EXPECT_EQ(CountTraversable(gentle), gentle_paper) << "5 cm is less than any face's rise on the slope";
  ClassifyFaces(noisy, &gentle);
  EXPECT_GT(CountTraversable(gentle), faces * 99 / 100);

  FreeSpaceMesh steep = NoisySlope(35.0, 0.02);
  ClassifyFaces(noisy, &steep);
  EXPECT_LT(CountTraversable(steep), faces * 15 / 100);
  FreeSpaceMesh steep_clean = NoisySlope(35.0, 0.0);
  ClassifyFaces(noisy, &steep_clean);
  EXPECT_EQ(CountTraversable(steep_clean), 0);

  // A 15 cm step across a flat grid (37 deg over one 0.2 m cell): the faces over it rise about 10 cm
  // across the local surface, twice the noise floor, and stay non-traversable.
  FreeSpaceMesh step = NoisySlope(0.0, 0.0);
  for (Vec3& v : step.vertices) {
    if (v.x() > 2.05) v.z() += 0.15;
  }
  ClassifyFaces(noisy, &step);
  for (std::size_t f = 0; f < step.triangles.size(); ++f) {
    const auto& t = step.triangles[f];
    const bool spans_step = (step.vertices[t[0]].x() < 2.05) != (step.vertices[t[1]].x() < 2.05) ||
                            (step.vertices[t[0]].x() < 2.05) != (step.vertices[t[2]].x() < 2.05);
    EXPECT_EQ(step.face_traversable[f], spans_step ? 0 : 1) << f;
  }
}

// A slope seen sparsely (at a grazing angle, below a crest): faces 1 m long rise up to 0.5 m on a
// 20 deg ramp, over the paper's 25 cm step, yet they lie in the ramp's surface. With the noise floor
// on slopes they are judged by their relief across the local surface and are traversable; a 0.3 m
// step seen as sparsely (a curb, the lip of a drop) still stands out of the surface around it, and a
// sparse 35 deg slope still fails the angle test.
TEST(TraversabilityTest, ASparselySeenRampIsNotAStepAndASparselySeenStepIs) {
  Traversability::Config paper;
  Traversability::Config noisy;
  noisy.noise_floor_m = 0.05;
  noisy.noise_floor_on_slopes = true;
  FreeSpaceMesh ramp = NoisySlope(20.0, 0.01, 1.0);
  const int faces = static_cast<int>(ramp.triangles.size());
  ClassifyFaces(paper, &ramp);
  EXPECT_EQ(CountTraversable(ramp), 0) << "every face rises more than 25 cm";
  ClassifyFaces(noisy, &ramp);
  EXPECT_EQ(CountTraversable(ramp), faces);

  FreeSpaceMesh steep = NoisySlope(35.0, 0.01, 1.0);
  ClassifyFaces(noisy, &steep);
  EXPECT_EQ(CountTraversable(steep), 0);

  FreeSpaceMesh curb = NoisySlope(0.0, 0.01, 1.0);
  for (Vec3& v : curb.vertices) {
    if (v.x() > 10.5) v.z() += 0.3;
  }
  ClassifyFaces(noisy, &curb);
  for (std::size_t f = 0; f < curb.triangles.size(); ++f) {
    const auto& t = curb.triangles[f];
    const bool spans_step = (curb.vertices[t[0]].x() < 10.5) != (curb.vertices[t[1]].x() < 10.5) ||
                            (curb.vertices[t[0]].x() < 10.5) != (curb.vertices[t[2]].x() < 10.5);
    EXPECT_EQ(curb.face_traversable[f], spans_step ? 0 : 1) << f;
  }
}

TEST(TraversabilityTest, DegenerateAndViewpointFacesAreNotTraversable) {
  Traversability::Config config;
  FreeSpaceMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}};
  mesh.viewpoint_vertex = 3;
  ClassifyFaces(config, &mesh);
  EXPECT_EQ(mesh.face_traversable[0], 0);  // zero area
  EXPECT_EQ(mesh.face_normals[0], Vec3::Zero());
  EXPECT_EQ(mesh.face_traversable[1], 0);  // touches the viewpoint
}

TEST(TraversabilityTest, ConfigIsValidated) {
  Traversability::Config config;
  config.alpha_max_rad = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = Traversability::Config{};
  config.delta_h_max_m = -1.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  FreeSpaceMesh mesh;
  EXPECT_THROW(ClassifyFaces(Traversability::Config{}, &mesh, Vec3(0, 0, 2)), std::invalid_argument);
}

TEST(TraversabilityTest, RoofIsNotTraversableAndTheGroundUnderItIs) {
  // Ground 24 x 24 m, a 5 x 5 m roof slab underside at 2.5 m next to the sensor at 1.88 m.
  Points pts = testing::Grid(-12, 12, -12, 12, 0.0, 0.25);
  const std::size_t ground_end = pts.size();
  const Points roof = testing::Grid(1.0, 6.0, -2.5, 2.5, 2.5, 0.25);
  pts.insert(pts.end(), roof.begin(), roof.end());
  const OvpcMap map = OvpcMapper().Update(pts, Vec3(0.0, 0.0, 1.88));
  ASSERT_TRUE(map.ok()) << map.message;
  EXPECT_TRUE(CheckTopology(map.mesh.triangles).watertight());

  int roof_vertices = 0, roof_traversable = 0, under = 0, under_traversable = 0;
  for (std::size_t i = 0; i < map.cloud.size(); ++i) {
    const Vec3& p = map.cloud.points()[i];
    const bool trav = map.cloud.traversable()[i] != 0;
    if (static_cast<std::size_t>(map.mesh.source_index[i]) >= ground_end) {
      ++roof_vertices;
      roof_traversable += trav;
      EXPECT_LT(map.cloud.normals()[i].z(), 0.0) << "roof normal must point down into free space";
    } else if (p.x() > 1.75 && p.x() < 5.25 && std::abs(p.y()) < 1.75) {
      ++under;
      under_traversable += trav;
    }
  }
  EXPECT_GT(roof_vertices, 100);
  EXPECT_EQ(roof_traversable, 0);
  ASSERT_GT(under, 100);
  EXPECT_GT(under_traversable, 0.9 * under) << under_traversable << " of " << under;
}

}  // namespace
}  // namespace ovpc
