#include "ovpc/bench/normals_experiment.h"

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ovpc/bench/stats.h"

namespace ovpc::bench {
namespace {

/// The protocol's scene without noise or pose error.
SlopeSceneConfig Exact() {
  SlopeSceneConfig config;
  config.noise_m = 0.0;
  config.pose_error_deg = 0.0;
  config.pose_error_m = 0.0;
  return config;
}

/// A small scene (6 m x 6 m, 0.25 m grid, two clouds) for trials that run in a test.
SlopeSceneConfig Tiny() {
  SlopeSceneConfig config;
  config.half_extent_m = 3.0;
  config.slope_start_x_m = 1.0;
  config.spacing_m = 0.25;
  config.num_clouds = 2;
  return config;
}

// --- Scene ------------------------------------------------------------------------------------

TEST(SlopeSceneTest, SlopeNormalIsPerpendicularToTheSlope) {
  EXPECT_TRUE(SlopeNormal(0.0).isApprox(Vec3::UnitZ()));
  const double alpha = DegToRad(30.0);
  const Vec3 up_the_slope(std::cos(alpha), 0.0, std::sin(alpha));
  EXPECT_NEAR(SlopeNormal(alpha).dot(up_the_slope), 0.0, 1e-15);
  EXPECT_NEAR(SlopeNormal(alpha).norm(), 1.0, 1e-15);
  EXPECT_NEAR(RadToDeg(std::acos(SlopeNormal(alpha).z())), 30.0, 1e-12);
}

TEST(SlopeSceneTest, SamplesCoverTheTwentyMetreSquareOnAPointTwoMetreGrid) {
  for (const double alpha_deg : {0.0, 17.3, 35.0}) {
    const double alpha = DegToRad(alpha_deg);
    const SlopeSceneConfig config = Exact();
    Points points;
    std::vector<Surface> surface;
    SampleSurfaces(alpha, config, &points, &surface);
    ASSERT_EQ(points.size(), surface.size());
    // 101 columns along y; 65 ground rows (x = -10 .. 2.8) and the slope's rows along the surface.
    const int slope_rows = static_cast<int>(std::floor(7.0 / std::cos(alpha) / 0.2 + 1e-9)) + 1;
    EXPECT_EQ(points.size(), static_cast<std::size_t>(101 * (65 + slope_rows))) << alpha_deg;
    const Vec3 foot(3.0, 0.0, 0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3& p = points[i];
      ASSERT_LE(std::abs(p.x()), 10.0 + 1e-9);
      ASSERT_LE(std::abs(p.y()), 10.0 + 1e-9);
      if (surface[i] == Surface::kGround) {
        ASSERT_EQ(p.z(), 0.0);
        ASSERT_LT(p.x(), 3.0);
      } else {
        ASSERT_GE(p.x(), 3.0 - 1e-12);
        ASSERT_NEAR(SlopeNormal(alpha).dot(p - foot), 0.0, 1e-12);
      }
    }
    // Neighbouring slope rows are 0.2 m apart along the surface.
    const std::size_t first_slope = 101 * 65;
    ASSERT_EQ(surface[first_slope], Surface::kSlope);
    EXPECT_NEAR((points[first_slope + 101] - points[first_slope]).norm(), 0.2, 1e-12);
    EXPECT_NEAR((points[1] - points[0]).norm(), 0.2, 1e-12);
  }
}

TEST(SlopeSceneTest, ExactSceneIsTheSamplesRepeatedPerCloud) {
  const SlopeSceneConfig config = Exact();
  Points samples;
  std::vector<Surface> labels;
  SampleSurfaces(DegToRad(20.0), config, &samples, &labels);
  const SlopeScene scene = MakeSlopeScene(DegToRad(20.0), config, 3);
  ASSERT_EQ(scene.points.size(), 5 * samples.size());
  EXPECT_TRUE(scene.viewpoint.isApprox(Vec3(0.0, 0.0, 1.88)));
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    ASSERT_TRUE(scene.points[i].isApprox(samples[i % samples.size()], 1e-12));
    ASSERT_EQ(scene.surface[i], labels[i % samples.size()]);
  }
  EXPECT_TRUE(scene.TrueNormal(0).isApprox(Vec3::UnitZ()));
  EXPECT_TRUE(scene.TrueNormal(scene.points.size() - 1).isApprox(SlopeNormal(DegToRad(20.0))));
}

TEST(SlopeSceneTest, NoiseIsUniformWithinFiveCentimetresPerAxis) {
  SlopeSceneConfig config = Exact();
  config.noise_m = 0.05;
  Points samples;
  std::vector<Surface> labels;
  SampleSurfaces(DegToRad(10.0), config, &samples, &labels);
  const SlopeScene scene = MakeSlopeScene(DegToRad(10.0), config, 4);
  Vec3 max_abs = Vec3::Zero();
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    const Vec3 d = scene.points[i] - samples[i % samples.size()];
    max_abs = max_abs.cwiseMax(d.cwiseAbs());
    sum += d;
  }
  const double n = static_cast<double>(scene.points.size());
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(max_abs[axis], 0.05);
    EXPECT_GT(max_abs[axis], 0.0499);                  // the whole range is used
    EXPECT_NEAR(sum[axis] / n, 0.0, 0.001);            // centred
  }
}

TEST(SlopeSceneTest, PoseErrorIsRigidPerCloudAndWithinBounds) {
  SlopeSceneConfig config = Exact();
  config.pose_error_deg = 0.5;
  config.pose_error_m = 0.1;
  Points samples;
  std::vector<Surface> labels;
  SampleSurfaces(DegToRad(25.0), config, &samples, &labels);
  const SlopeScene scene = MakeSlopeScene(DegToRad(25.0), config, 5);
  const std::size_t m = samples.size();
  // Bound of the displacement of a sample s: |t| + |R - I| |s - v|, with |t| <= sqrt(3) 0.1 m and
  // the rotation angle at most 3 x 0.5 deg (three axes).
  const double max_angle = 3.0 * DegToRad(0.5);
  std::set<double> first_displacements;
  for (int k = 0; k < 5; ++k) {
    for (std::size_t i = 0; i < m; i += 97) {
      const Vec3& s = samples[i];
      const Vec3& p = scene.points[k * m + i];
      const double bound = std::sqrt(3.0) * 0.1 + 2.0 * std::sin(0.5 * max_angle) *
                                                      (s - scene.viewpoint).norm();
      ASSERT_LE((p - s).norm(), bound + 1e-12);
      // Rigid: distances between samples of one cloud are preserved.
      const std::size_t j = (i + 1234) % m;
      ASSERT_NEAR((scene.points[k * m + j] - p).norm(), (samples[j] - s).norm(), 1e-9);
    }
    first_displacements.insert((scene.points[k * m] - samples[0]).norm());
  }
  EXPECT_EQ(first_displacements.size(), 5u);  // every cloud has its own error
}

TEST(SlopeSceneTest, DeterministicFromTheSeed) {
  const SlopeSceneConfig config;
  const SlopeScene a = MakeSlopeScene(DegToRad(12.0), config, 42);
  const SlopeScene b = MakeSlopeScene(DegToRad(12.0), config, 42);
  const SlopeScene c = MakeSlopeScene(DegToRad(12.0), config, 43);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(a.points, b.points);
  EXPECT_NE(a.points, c.points);
  EXPECT_NE(TrialSeed(1, 0), TrialSeed(1, 1));
  EXPECT_NE(TrialSeed(1, 0), TrialSeed(2, 0));
  EXPECT_EQ(TrialSeed(7, 3), TrialSeed(7, 3));
}

TEST(SlopeSceneTest, InvalidArgumentsThrow) {
  EXPECT_THROW(MakeSlopeScene(DegToRad(90.0), SlopeSceneConfig{}, 1), std::invalid_argument);
  EXPECT_THROW(MakeSlopeScene(-0.1, SlopeSceneConfig{}, 1), std::invalid_argument);
  SlopeSceneConfig config;
  config.spacing_m = 0.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = SlopeSceneConfig{};
  config.slope_start_x_m = 10.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = SlopeSceneConfig{};
  config.num_clouds = 0;
  try {
    config.Validate();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("num_clouds"), std::string::npos);
  }
}

// --- Metric -----------------------------------------------------------------------------------

TEST(AngularErrorTest, KnownAngles) {
  EXPECT_NEAR(AngularErrorDeg(Vec3::UnitZ(), Vec3::UnitZ()), 0.0, 1e-12);
  EXPECT_NEAR(AngularErrorDeg(Vec3::UnitX(), Vec3::UnitZ()), 90.0, 1e-12);
  EXPECT_NEAR(AngularErrorDeg(-Vec3::UnitZ(), Vec3::UnitZ()), 180.0, 1e-12);  // oriented
  EXPECT_NEAR(AngularErrorDeg(SlopeNormal(DegToRad(30.0)), Vec3::UnitZ()), 30.0, 1e-12);
  // Not sensitive to length.
  EXPECT_NEAR(AngularErrorDeg(3.0 * SlopeNormal(DegToRad(7.0)), 0.5 * Vec3::UnitZ()), 7.0, 1e-12);
  // Accurate for tiny angles (acos of a dot product would return 0 here).
  const double tiny = 1e-9;
  EXPECT_NEAR(AngularErrorDeg(Vec3(std::sin(tiny), 0.0, std::cos(tiny)), Vec3::UnitZ()),
              RadToDeg(tiny), 1e-15);
}

TEST(AngularErrorTest, UnorientedFoldsFlippedNormals) {
  EXPECT_DOUBLE_EQ(UnorientedDeg(0.0), 0.0);
  EXPECT_DOUBLE_EQ(UnorientedDeg(30.0), 30.0);
  EXPECT_DOUBLE_EQ(UnorientedDeg(90.0), 90.0);
  EXPECT_DOUBLE_EQ(UnorientedDeg(170.0), 10.0);
  EXPECT_DOUBLE_EQ(UnorientedDeg(AngularErrorDeg(-Vec3::UnitZ(), Vec3::UnitZ())), 0.0);
}

TEST(AngularErrorTest, NoNormalIsNaN) {
  EXPECT_TRUE(std::isnan(AngularErrorDeg(Vec3::Zero(), Vec3::UnitZ())));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(AngularErrorDeg(Vec3(nan, 0.0, 1.0), Vec3::UnitZ())));
}

TEST(AngularErrorTest, PointNormalErrorsUseEachPointsSurface) {
  SlopeScene scene;
  scene.alpha_rad = DegToRad(20.0);
  scene.slope_normal = SlopeNormal(scene.alpha_rad);
  scene.points = {Vec3(0, 0, 0), Vec3(5, 0, 1), Vec3(6, 0, 1)};
  scene.surface = {Surface::kGround, Surface::kSlope, Surface::kSlope};
  baselines::PcaNormals normals;
  normals.normals = {Vec3::UnitZ(), Vec3::UnitZ(), Vec3::Zero()};
  const MethodErrors errors = PointNormalErrors(scene, normals);
  ASSERT_EQ(errors.errors.size(), 2u);
  EXPECT_EQ(errors.without_normal, 1u);
  EXPECT_NEAR(errors.errors[0].error_deg, 0.0, 1e-12);
  EXPECT_NEAR(errors.errors[1].error_deg, 20.0, 1e-12);
  EXPECT_EQ(errors.errors[1].index, 1u);
  normals.normals.pop_back();
  EXPECT_THROW(PointNormalErrors(scene, normals), std::invalid_argument);
}

// --- A whole trial, small -----------------------------------------------------------------------

NormalEstimator EigenPca() {
  return [](const Points& points, const Vec3& viewpoint) {
    return baselines::EstimatePcaNormals(points, viewpoint, baselines::PcaNormalsConfig{});
  };
}

TEST(NormalsTrialTest, ExactSceneGivesNearPerfectNormalsAwayFromTheCrease) {
  SlopeSceneConfig config = Tiny();
  config.noise_m = 0.0;
  config.pose_error_deg = 0.0;
  config.pose_error_m = 0.0;
  config.num_clouds = 1;
  const OvpcMapper mapper;
  const NormalsTrial trial = RunNormalsTrial(20.0, config, mapper, EigenPca(), 1);
  ASSERT_EQ(trial.ovpc_status, GhprStatus::kOk);
  ASSERT_FALSE(trial.ovpc.errors.empty());
  ASSERT_FALSE(trial.pca.errors.empty());
  // Noise-free planes: every point is visible from above and both methods are exact on the
  // planes' interiors; only points at the crease and the scene's rim differ.
  EXPECT_LT(Summarize(trial.pca.Degrees()).median, 1e-6);
  EXPECT_LT(Summarize(trial.ovpc.Degrees()).median, 1e-6);
  EXPECT_EQ(trial.pca.errors.size() + trial.pca.without_normal, trial.points);
}

TEST(NormalsTrialTest, NoisyTrialEvaluatesVisiblePointsAndAllPoints) {
  const OvpcMapper mapper;
  const NormalsTrial trial = RunNormalsTrial(15.0, Tiny(), mapper, EigenPca(), 9);
  ASSERT_EQ(trial.ovpc_status, GhprStatus::kOk);
  EXPECT_EQ(trial.alpha_deg, 15.0);
  EXPECT_EQ(trial.seed, 9u);
  // OVPC evaluates only its visible points, PCA every point; pca_visible is PCA on OVPC's set.
  EXPECT_LT(trial.ovpc.errors.size(), trial.points);
  EXPECT_LE(trial.pca_visible.errors.size(), trial.pca.errors.size());
  EXPECT_EQ(trial.pca_visible.errors.size() + trial.pca_visible.without_normal,
            trial.ovpc.errors.size() + trial.ovpc.without_normal);
  const SampleStats ovpc = Summarize(trial.ovpc.Degrees());
  const SampleStats pca = Summarize(trial.pca.Degrees());
  EXPECT_GT(ovpc.mean, 0.0);
  EXPECT_LT(ovpc.median, 20.0);
  EXPECT_GT(pca.mean, 0.0);
  EXPECT_LT(pca.median, 20.0);
}

TEST(NormalsTrialTest, VoxelFilteredInputIsScoredByTheSurfaceUnderEachVertex) {
  const SlopeSceneConfig config = Tiny();
  EXPECT_EQ(SurfaceAt(Vec3(0.99, 0.0, 0.0), config), Surface::kGround);
  EXPECT_EQ(SurfaceAt(Vec3(1.0, 0.0, 0.0), config), Surface::kSlope);
  const OvpcMapper mapper;
  OvpcInputFilter filter;
  filter.voxel_size_m = 0.2;
  filter.min_hits = 1;
  const NormalsTrial trial = RunNormalsTrial(25.0, config, mapper, EigenPca(), 3, filter);
  ASSERT_EQ(trial.ovpc_status, GhprStatus::kOk);
  EXPECT_LT(trial.ovpc_input_points, trial.points);
  ASSERT_FALSE(trial.ovpc.errors.empty());
  for (const PointError& e : trial.ovpc.errors) {
    ASSERT_EQ(e.surface, SurfaceAt(e.position, config));
  }
  EXPECT_TRUE(trial.pca_visible.errors.empty());  // centroids are not points of the cloud
  EXPECT_EQ(trial.pca.errors.size() + trial.pca.without_normal, trial.points);
}

}  // namespace
}  // namespace ovpc::bench
