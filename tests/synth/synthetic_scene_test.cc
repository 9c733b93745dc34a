#include "ovpc/synth/synthetic_scene.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ovpc::synth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Unit direction at `elevation_rad` above the horizontal and heading `azimuth_rad`.
Vec3 Direction(double elevation_rad, double azimuth_rad) {
  return Vec3(std::cos(elevation_rad) * std::cos(azimuth_rad),
              std::cos(elevation_rad) * std::sin(azimuth_rad), std::sin(elevation_rad));
}

int FiringsPerScan(const SpinningLidarMount& mount) {
  return static_cast<int>(std::lround(2.0 * kPi / mount.azimuth_step_rad));
}

/// True if `p` lies on the boundary of `box` within `tol_m`.
bool OnBoxSurface(const Box& box, const Vec3& p, double tol_m) {
  const bool inside = (p.array() >= box.min.array() - tol_m).all() &&
                      (p.array() <= box.max.array() + tol_m).all();
  if (!inside) return false;
  const double to_face = std::min((p - box.min).cwiseAbs().minCoeff(),
                                  (box.max - p).cwiseAbs().minCoeff());
  return to_face <= tol_m;
}

// --- Ray casting on analytic shapes ------------------------------------------------------------

TEST(SceneRaycastTest, FlatGroundMatchesClosedForm) {
  const Scene scene;  // flat ground only
  for (const double height_m : {0.5, 1.88, 3.0}) {
    for (double angle_deg = 2.0; angle_deg <= 90.0; angle_deg += 4.0) {
      for (const double azimuth_deg : {0.0, 37.0, 181.0, 300.0}) {
        const double angle_rad = DegToRad(angle_deg);
        const Vec3 origin(1.5, -2.0, height_m);
        const double t_m =
            scene.Raycast(origin, Direction(-angle_rad, DegToRad(azimuth_deg)), 1000.0);
        EXPECT_NEAR(t_m, height_m / std::sin(angle_rad), 1e-9)
            << "h=" << height_m << " angle=" << angle_deg << " az=" << azimuth_deg;
      }
    }
  }
}

TEST(SceneRaycastTest, SkyAndOutOfRangeGiveInfinity) {
  const Scene scene = MakeOutdoorScene(1);
  const Vec3 origin(0.0, 0.0, 1.88);
  EXPECT_EQ(scene.Raycast(origin, Vec3::UnitZ(), 100.0), kInf);
  EXPECT_EQ(scene.Raycast(origin, Direction(DegToRad(60.0), 1.0), 100.0), kInf);
  // The ground is 1.88 / sin(1 deg) = 107.7 m away along a 1 deg downward ray: beyond 100 m.
  const Scene flat;
  EXPECT_EQ(flat.Raycast(origin, Direction(DegToRad(-1.0), 0.3), 100.0), kInf);
  EXPECT_NEAR(flat.Raycast(origin, Direction(DegToRad(-1.0), 0.3), 200.0),
              1.88 / std::sin(DegToRad(1.0)), 1e-9);
}

TEST(SceneRaycastTest, BoxHitAtAnalyticDistance) {
  Scene scene;
  scene.boxes.push_back(Box{Vec3(2.0, -1.0, 0.0), Vec3(3.0, 1.0, 2.0)});
  const Vec3 origin(0.0, 0.0, 1.0);
  EXPECT_NEAR(scene.Raycast(origin, Vec3::UnitX(), 100.0), 2.0, 1e-12);
  // Oblique ray through the near face: x = 2 at t = 2 / d.x.
  const Vec3 d = Vec3(1.0, 0.3, 0.2).normalized();
  EXPECT_NEAR(scene.Raycast(origin, d, 100.0), 2.0 / d.x(), 1e-12);
  // Onto the top face from above.
  EXPECT_NEAR(scene.Raycast(Vec3(2.5, 0.0, 5.0), -Vec3::UnitZ(), 100.0), 3.0, 1e-12);
  // From inside the box the ray hits the wall it leaves through.
  EXPECT_NEAR(scene.Raycast(Vec3(2.25, 0.0, 1.0), Vec3::UnitX(), 100.0), 0.75, 1e-12);
  // Passing beside the box, the ray runs on above flat ground to infinity.
  EXPECT_EQ(scene.Raycast(Vec3(0.0, 1.5, 1.0), Vec3::UnitX(), 100.0), kInf);
}

TEST(SceneRaycastTest, SphereHitAtAnalyticDistance) {
  Scene scene;
  scene.spheres.push_back(Sphere{Vec3(5.0, 0.0, 3.0), 1.0});
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.0, 3.0), Vec3::UnitX(), 100.0), 4.0, 1e-12);
  // Off-centre by 0.6 m: the chord half-length is 0.8 m.
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.6, 3.0), Vec3::UnitX(), 100.0), 4.2, 1e-12);
  // Just missing it.
  EXPECT_EQ(scene.Raycast(Vec3(0.0, 1.01, 3.0), Vec3::UnitX(), 100.0), kInf);
  // From the centre, every direction hits at the radius.
  EXPECT_NEAR(scene.Raycast(Vec3(5.0, 0.0, 3.0), Direction(0.4, 2.0), 100.0), 1.0, 1e-12);
}

TEST(SceneRaycastTest, CylinderHitAtAnalyticDistance) {
  Scene scene;
  scene.cylinders.push_back(Cylinder{Vec3(4.0, 0.0, 0.0), 0.5, 2.0});
  // Lateral surface.
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.0, 1.0), Vec3::UnitX(), 100.0), 3.5, 1e-12);
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.3, 1.0), Vec3::UnitX(), 100.0), 4.0 - 0.4, 1e-12);
  // Over the top the horizontal ray misses everything.
  EXPECT_EQ(scene.Raycast(Vec3(0.0, 0.0, 2.1), Vec3::UnitX(), 100.0), kInf);
  // Top cap from above.
  EXPECT_NEAR(scene.Raycast(Vec3(4.1, 0.2, 5.0), -Vec3::UnitZ(), 100.0), 3.0, 1e-12);
  // Straight down 2 cm outside the radius: past the cap, onto the ground.
  EXPECT_NEAR(scene.Raycast(Vec3(4.52, 0.0, 5.0), -Vec3::UnitZ(), 100.0), 5.0, 1e-12);
  // A downward ray that passes the top rim hits the lateral surface: it enters the radius at
  // x = 3.5, where its height is 3 - 3.5 * tan(15 deg) = 2.062 m > 2 m, so it meets the cap.
  const double slope = std::tan(DegToRad(15.0));
  const Vec3 d = Vec3(1.0, 0.0, -slope).normalized();
  const double t_cap = (3.0 - 2.0) / slope / d.x();
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.0, 3.0), d, 100.0), t_cap, 1e-12);
  // Steeper (45 deg), it reaches the radius at height 3 - 3.5 = -0.5 < 0: the ground comes first.
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 0.0, 3.0), Vec3(1.0, 0.0, -1.0).normalized(), 100.0),
              3.0 * std::sqrt(2.0), 1e-12);
}

// --- Ramp ------------------------------------------------------------------------------------

TEST(SceneRampTest, GroundHeightMatchesClosedForm) {
  const Scene scene = MakeOutdoorScene(3);
  EXPECT_NEAR(scene.ramp_slope_rad, DegToRad(20.0), 1e-12);
  EXPECT_GT(scene.ramp_start_x, 4.0);
  EXPECT_LT(scene.ramp_start_x, 8.0);
  EXPECT_GE(scene.ramp_half_width, 3.5);
  const double tan_slope = std::tan(DegToRad(20.0));
  const double x0 = scene.ramp_start_x;
  const double plateau_m = tan_slope * (scene.ramp_end_x - x0);
  EXPECT_GT(plateau_m, 0.5);
  EXPECT_DOUBLE_EQ(scene.GroundHeight(x0 - 0.5, 0.0), 0.0);
  EXPECT_NEAR(scene.GroundHeight(x0 + 1.0, 0.0), tan_slope, 1e-12);
  EXPECT_NEAR(scene.GroundHeight(x0 + 2.0, 0.7 * scene.ramp_half_width), 2.0 * tan_slope, 1e-12);
  EXPECT_NEAR(scene.GroundHeight(scene.ramp_end_x + 5.0, -0.5), plateau_m, 1e-12);
  EXPECT_DOUBLE_EQ(scene.GroundHeight(x0 + 1.0, scene.ramp_half_width + 0.1), 0.0);
  EXPECT_DOUBLE_EQ(scene.GroundHeight(scene.ramp_end_x + 5.0, -scene.ramp_half_width - 0.1), 0.0);
}

TEST(SceneRampTest, RaysHitTheRampPlateauAndSideWall) {
  Scene scene;
  scene.ramp_start_x = 6.0;
  scene.ramp_end_x = 10.0;
  scene.ramp_half_width = 4.0;
  scene.ramp_centre_y = 1.0;
  scene.ramp_slope_rad = DegToRad(20.0);
  const double tan_slope = std::tan(scene.ramp_slope_rad);
  // Straight down onto the ramp and onto the plateau.
  EXPECT_NEAR(scene.Raycast(Vec3(7.5, 2.0, 5.0), -Vec3::UnitZ(), 100.0), 5.0 - 1.5 * tan_slope,
              1e-12);
  EXPECT_NEAR(scene.Raycast(Vec3(14.0, 2.0, 5.0), -Vec3::UnitZ(), 100.0), 5.0 - 4.0 * tan_slope,
              1e-12);
  // A ray from the vehicle's sensor, 5 deg down along +x: h - t sin(a) = tan(s) (t cos(a) - x0).
  const double a = DegToRad(5.0);
  const double t = (1.88 + tan_slope * 6.0) / (std::sin(a) + tan_slope * std::cos(a));
  ASSERT_GT(t * std::cos(a), 6.0);
  ASSERT_LT(t * std::cos(a), 10.0);
  EXPECT_NEAR(scene.Raycast(Vec3(0.0, 1.0, 1.88), Direction(-a, 0.0), 100.0), t, 1e-9);
  // A horizontal ray at 0.5 m along +y hits the plateau's side wall at y = 1 - 4 = -3.
  EXPECT_NEAR(scene.Raycast(Vec3(12.0, -6.0, 0.5), Vec3::UnitY(), 100.0), 3.0, 1e-12);
  // Above the plateau it flies on.
  EXPECT_EQ(scene.Raycast(Vec3(12.0, -6.0, 1.6), Vec3::UnitY(), 100.0), kInf);
}

// --- Outdoor scene layout ----------------------------------------------------------------------

TEST(OutdoorSceneTest, ObjectsKeepClearOfVehicleAndRamp) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Scene scene = MakeOutdoorScene(seed);
    ASSERT_EQ(scene.boxes.size(), 1u) << "the carport roof";
    const Box& roof = scene.boxes[0];
    EXPECT_NEAR(roof.min.z(), 2.5, 1e-12);
    EXPECT_NEAR(roof.max.z() - roof.min.z(), 0.1, 1e-12);
    EXPECT_NEAR((roof.max - roof.min).head<2>().norm(), std::hypot(6.0, 4.0), 1e-12);
    const int num_trees = static_cast<int>(scene.spheres.size());
    const int num_poles = static_cast<int>(scene.cylinders.size()) - 4 - num_trees;
    EXPECT_GE(num_trees, 5);
    EXPECT_LE(num_trees, 8);
    EXPECT_GE(num_poles, 6);
    EXPECT_LE(num_poles, 10);
    for (std::size_t i = 4; i < scene.cylinders.size(); ++i) {
      const Cylinder& c = scene.cylinders[i];
      const double dist_m = c.base.head<2>().norm();
      EXPECT_GE(dist_m - c.radius_m, 2.5);
      EXPECT_LE(dist_m, 20.0);
      const bool on_strip =
          c.base.x() + c.radius_m >= scene.ramp_start_x &&
          std::abs(c.base.y() - scene.ramp_centre_y) <= scene.ramp_half_width + c.radius_m;
      EXPECT_FALSE(on_strip) << "seed " << seed << " cylinder " << i;
    }
    for (const Sphere& s : scene.spheres) {
      EXPECT_GE(s.centre.head<2>().norm() - s.radius_m, 2.5);
      const bool over_strip =
          s.centre.x() + s.radius_m >= scene.ramp_start_x &&
          std::abs(s.centre.y() - scene.ramp_centre_y) <= scene.ramp_half_width + s.radius_m;
      EXPECT_FALSE(over_strip) << "seed " << seed;
    }
  }
  // The layout depends on the seed.
  const Scene a = MakeOutdoorScene(1);
  const Scene b = MakeOutdoorScene(2);
  ASSERT_GT(a.cylinders.size(), 4u);
  ASSERT_GT(b.cylinders.size(), 4u);
  EXPECT_NE(a.cylinders[4].base, b.cylinders[4].base);
}

// --- Scan simulation ---------------------------------------------------------------------------

/// A closed 20 m x 20 m x 10 m room on the ground around the vehicle: every ray hits a wall.
Scene BoxRoom() {
  Scene scene;
  scene.boxes.push_back(Box{Vec3(-8.0, -9.0, 0.0), Vec3(11.0, 10.0, 10.0)});
  return scene;
}

TEST(SimulateScansTest, OneRevolutionFiresSixteenBeamsPerAzimuthStep) {
  const SpinningLidarMount mount;
  const std::vector<Scan> scans =
      SimulateScans(BoxRoom(), mount, Eigen::Isometry3d::Identity(), 0.0, 1, 0.0, 1);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(FiringsPerScan(mount), 905);
  EXPECT_EQ(scans[0].points_S.size(), static_cast<std::size_t>(16 * FiringsPerScan(mount)));
}

TEST(SimulateScansTest, NoiselessHitsLieOnTheRoomAlongTheFiringTimeBeams) {
  const SpinningLidarMount mount;
  const Scene room = BoxRoom();
  Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  T_O_B.translation() = Vec3(1.0, 0.5, 0.0);
  T_O_B.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
  const double t0_s = 0.37;
  const int num_scans = 3;
  const std::vector<Scan> scans = SimulateScans(room, mount, T_O_B, t0_s, num_scans, 0.0, 5);
  ASSERT_EQ(scans.size(), static_cast<std::size_t>(num_scans));
  const int num_firings = FiringsPerScan(mount);
  const double period_s = 1.0 / mount.scan_hz;
  for (int k = 0; k < num_scans; ++k) {
    const Scan& scan = scans[k];
    const double t_start_s = t0_s + k * period_s;
    EXPECT_NEAR(scan.time_s, t_start_s + period_s, 1e-12);
    const Eigen::Isometry3d T_O_S_end = T_O_B * mount.T_B_S(scan.time_s);
    EXPECT_NEAR((scan.T_O_S.matrix() - T_O_S_end.matrix()).norm(), 0.0, 1e-12);
    ASSERT_EQ(scan.points_S.size(), static_cast<std::size_t>(16 * num_firings));
    for (std::size_t i = 0; i < scan.points_S.size(); i += 7) {
      const Vec3 p_O = scan.T_O_S * scan.points_S[i];
      EXPECT_TRUE(OnBoxSurface(room.boxes[0], p_O, 1e-6)) << "scan " << k << " point " << i;
      // Along the beam of its laser, from where the sensor was when it fired.
      const int firing = static_cast<int>(i / 16);
      const int laser = static_cast<int>(i % 16);
      const double t_s = t_start_s + firing * period_s / num_firings;
      const Eigen::Isometry3d T_O_S_fire = T_O_B * mount.T_B_S(t_s);
      const Vec3 beam_O =
          T_O_S_fire.linear() * Direction(DegToRad(kVlp16ElevationDeg[laser]),
                                          firing * mount.azimuth_step_rad);
      const Vec3 ray_O = p_O - T_O_S_fire.translation();
      EXPECT_NEAR((ray_O.normalized() - beam_O).norm(), 0.0, 1e-9)
          << "scan " << k << " point " << i;
      EXPECT_GE(ray_O.norm(), mount.min_range_m);
    }
  }
  // The base turns 9 deg per scan, so the end-of-scan frame differs from most firing frames by
  // up to that much: without motion compensation, far points would be metres off the walls.
  const Eigen::Matrix3d turn =
      scans[0].T_O_S.linear() * (T_O_B * mount.T_B_S(t0_s)).linear().transpose();
  EXPECT_NEAR(Eigen::AngleAxisd(turn).angle(), 2.0 * kPi * mount.spin_hz * period_s, 1e-9);
}

TEST(SimulateScansTest, RangesStayWithinSensorLimits) {
  SpinningLidarMount mount;
  mount.spin_hz = 0.0;  // the sensor frame does not move: range = |p_S|
  mount.min_range_m = 3.0;
  mount.max_range_m = 9.0;
  const std::vector<Scan> scans =
      SimulateScans(BoxRoom(), mount, Eigen::Isometry3d::Identity(), 0.0, 1, 0.0, 1);
  ASSERT_FALSE(scans[0].points_S.empty());
  EXPECT_LT(scans[0].points_S.size(), static_cast<std::size_t>(16 * FiringsPerScan(mount)));
  for (const Vec3& p : scans[0].points_S) {
    EXPECT_GE(p.norm(), 3.0 - 1e-9);
    EXPECT_LE(p.norm(), 9.0 + 1e-9);
  }
}

TEST(SimulateScansTest, RangeNoiseHasTheRequestedSigma) {
  SpinningLidarMount mount;
  mount.spin_hz = 0.0;
  const Scene room = BoxRoom();
  const double sigma_m = 0.02;
  const Scan clean =
      SimulateScans(room, mount, Eigen::Isometry3d::Identity(), 0.0, 1, 0.0, 9)[0];
  const Scan noisy =
      SimulateScans(room, mount, Eigen::Isometry3d::Identity(), 0.0, 1, sigma_m, 9)[0];
  ASSERT_EQ(clean.points_S.size(), noisy.points_S.size());  // every range is far from the limits
  double sum = 0.0;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < clean.points_S.size(); ++i) {
    // Noise only along the beam.
    EXPECT_NEAR((clean.points_S[i].normalized() - noisy.points_S[i].normalized()).norm(), 0.0,
                1e-9);
    const double error_m = noisy.points_S[i].norm() - clean.points_S[i].norm();
    sum += error_m;
    sum_sq += error_m * error_m;
  }
  const double n = static_cast<double>(clean.points_S.size());
  EXPECT_NEAR(sum / n, 0.0, 5.0 * sigma_m / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum_sq / n), sigma_m, 0.05 * sigma_m);
}

TEST(SimulateScansTest, SameSeedSameScansOtherSeedOtherScans) {
  const Scene scene = MakeOutdoorScene(4);
  const SpinningLidarMount mount;
  const Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  const auto a = SimulateScans(scene, mount, T_O_B, 0.0, 2, 0.015, 11);
  const auto b = SimulateScans(scene, mount, T_O_B, 0.0, 2, 0.015, 11);
  const auto c = SimulateScans(scene, mount, T_O_B, 0.0, 2, 0.015, 12);
  ASSERT_EQ(a.size(), 2u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].points_S, b[k].points_S);
    EXPECT_NE(a[k].points_S, c[k].points_S);
  }
}

TEST(SimulateScansTest, RejectsBrokenArguments) {
  const Scene scene;
  SpinningLidarMount mount;
  const Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  EXPECT_THROW(SimulateScans(scene, mount, T_O_B, 0.0, -1, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(SimulateScans(scene, mount, T_O_B, 0.0, 1, -0.1, 1), std::invalid_argument);
  mount.scan_hz = 0.0;
  EXPECT_THROW(SimulateScans(scene, mount, T_O_B, 0.0, 1, 0.0, 1), std::invalid_argument);
  EXPECT_TRUE(SimulateScans(scene, SpinningLidarMount{}, T_O_B, 0.0, 0, 0.0, 1).empty());
}

// --- Buffered outdoor cloud --------------------------------------------------------------------

TEST(MakeOutdoorCloudTest, HasTheRequestedSizeAndFinitePoints) {
  const Points points_L = MakeOutdoorCloud(6000, 1);
  ASSERT_EQ(points_L.size(), 6000u);
  std::size_t near_ground = 0;
  for (const Vec3& p : points_L) {
    ASSERT_TRUE(p.allFinite());
    EXPECT_LE(p.norm(), 25.0 + 1e-9);  // the crop radius
    // The viewpoint is the origin: 1.88 m above the flat ground.
    if (std::abs(p.z() + 1.88) < 0.05) ++near_ground;
  }
  EXPECT_GT(near_ground, points_L.size() / 4);
}

TEST(MakeOutdoorCloudTest, ReachesFiftyThousandPoints) {
  EXPECT_EQ(MakeOutdoorCloud(50000, 2).size(), 50000u);
}

TEST(MakeOutdoorCloudTest, DeterministicFromTheSeed) {
  const Points a = MakeOutdoorCloud(6000, 1);
  EXPECT_EQ(a, MakeOutdoorCloud(6000, 1));
  EXPECT_NE(a, MakeOutdoorCloud(6000, 2));
}

}  // namespace
}  // namespace ovpc::synth
