#include "ovpc/sim/vlp16.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/sim/ray_caster.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSensorHeight_m = 1.88;

/// A world and its ray caster, built once per test.
struct Scene {
  explicit Scene(World w) : world(std::move(w)), terrain(MakeHeightfield(world.terrain)),
                            solids(ResolveSolids(world, terrain)), caster(terrain, solids) {}
  World world;
  Heightfield terrain;
  std::vector<Solid> solids;
  RayCaster caster;
};

World FlatWorld(double size_m, double cell_m) {
  World world;
  world.terrain.size_x_m = size_m;
  world.terrain.size_y_m = size_m;
  world.terrain.cell_m = cell_m;
  return world;
}

/// Four walls 15 m away and a roof at 8 m: every ray hits something.
World ClosedRoom() {
  World world = FlatWorld(40.0, 1.0);
  const double d = 15.0;
  for (int i = 0; i < 4; ++i) {
    BoxObject wall;
    wall.x_m = i == 0 ? d : (i == 1 ? -d : 0.0);
    wall.y_m = i == 2 ? d : (i == 3 ? -d : 0.0);
    wall.length_m = i < 2 ? 0.5 : 31.0;
    wall.width_m = i < 2 ? 31.0 : 0.5;
    wall.height_m = 9.0;
    world.boxes.push_back(wall);
  }
  BoxObject roof;
  roof.length_m = 31.0;
  roof.width_m = 31.0;
  roof.base_m = 8.0;
  roof.height_m = 0.5;
  world.boxes.push_back(roof);
  return world;
}

Vlp16Sim::Config NoiseFree() {
  Vlp16Sim::Config config;
  config.range_sigma_m = 0.0;
  return config;
}

/// Runs the sensor on a parked vehicle (B = W) for `duration_s` in steps of `step_s`.
std::vector<TrueScan> RunParked(Vlp16Sim* lidar, double duration_s, double step_s) {
  std::vector<TrueScan> scans;
  const long steps = std::lround(duration_s / step_s);
  for (long i = 0; i < steps; ++i) {
    const TimedPose from{i * step_s, Eigen::Isometry3d::Identity()};
    const TimedPose to{(i + 1) * step_s, Eigen::Isometry3d::Identity()};
    lidar->Advance(from, to, &scans);
  }
  return scans;
}

Eigen::Isometry3d TiltedSensor() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Vec3(0.0, 0.0, kSensorHeight_m);
  T.linear() = Eigen::AngleAxisd(DegToRad(45.0), Vec3::UnitX()).toRotationMatrix();
  return T;
}

TEST(Vlp16Test, PlaneHitsMatchClosedFormDistances) {
  const Scene scene(FlatWorld(240.0, 2.0));  // flat: the cell size does not matter
  const Vlp16Sim lidar(NoiseFree(), &scene.caster);
  const Eigen::Isometry3d T_W_S = TiltedSensor();
  int hits = 0;
  for (double az_deg = 0.0; az_deg < 360.0; az_deg += 7.5) {
    const std::vector<double> ranges = lidar.CastFiring(T_W_S, DegToRad(az_deg));
    for (int laser = 0; laser < 16; ++laser) {
      const Vec3 dir_W = T_W_S.linear() * Vlp16Sim::BeamDirection(laser, DegToRad(az_deg));
      double expected = dir_W.z() < 0.0 ? kSensorHeight_m / -dir_W.z() : kInf;
      if (expected < 1.0 || expected > 100.0) expected = kInf;
      const double range = ranges[static_cast<std::size_t>(laser)];
      if (std::isinf(expected)) {
        EXPECT_TRUE(std::isinf(range)) << az_deg << " " << laser;
      } else {
        ++hits;
        EXPECT_NEAR(range, expected, 1e-3) << az_deg << " " << laser;
      }
    }
  }
  EXPECT_GT(hits, 300);
}

TEST(Vlp16Test, BoxHitsMatchClosedFormDistances) {
  World world = FlatWorld(60.0, 1.0);
  BoxObject wall;  // near face at x = 4.5
  wall.x_m = 5.0;
  wall.length_m = 1.0;
  wall.width_m = 20.0;
  wall.height_m = 6.0;
  world.boxes.push_back(wall);
  const Scene scene(world);
  const Vlp16Sim lidar(NoiseFree(), &scene.caster);
  Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();  // level sensor
  T_W_S.translation() = Vec3(0.0, 0.0, kSensorHeight_m);
  int wall_hits = 0;
  for (double az_deg = -60.0; az_deg <= 60.0; az_deg += 5.0) {
    const std::vector<double> ranges = lidar.CastFiring(T_W_S, DegToRad(az_deg));
    for (int laser = 0; laser < 16; ++laser) {
      const Vec3 dir = Vlp16Sim::BeamDirection(laser, DegToRad(az_deg));
      const double to_ground = dir.z() < 0.0 ? kSensorHeight_m / -dir.z() : kInf;
      double to_wall = 4.5 / dir.x();
      const Vec3 on_wall = T_W_S.translation() + to_wall * dir;
      if (std::abs(on_wall.y()) > 10.0 || on_wall.z() < 0.0 || on_wall.z() > 6.0) to_wall = kInf;
      const double expected = std::min(to_ground, to_wall);
      if (to_wall < to_ground) ++wall_hits;
      EXPECT_NEAR(ranges[static_cast<std::size_t>(laser)], expected, 1e-3) << az_deg << " " << laser;
    }
  }
  EXPECT_GT(wall_hits, 200);
}

TEST(Vlp16Test, ScanHasTheBeamElevationsAndRayCount) {
  const Scene scene(ClosedRoom());
  Vlp16Sim::Config config = NoiseFree();
  config.mount.spin_hz = 0.0;  // a still base: the sensor frame is the same all scan long
  Vlp16Sim lidar(config, &scene.caster);
  EXPECT_EQ(lidar.firings_per_scan(), 905);  // 360 / 0.398 deg at 20 Hz
  const std::vector<TrueScan> scans = RunParked(&lidar, 1.0, 0.005);
  ASSERT_EQ(scans.size(), 20u);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const TrueScan& scan = scans[k];
    EXPECT_NEAR(scan.time_s, 0.05 * static_cast<double>(k + 1), 1e-9);
    EXPECT_EQ(scan.rays, 905u * 16u);
    ASSERT_EQ(scan.points_S.size(), 905u * 16u) << "every ray hits in the closed room";
  }
  const Points& pts = scans[3].points_S;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3& p = pts[i];
    const double elevation_deg = RadToDeg(std::asin(p.z() / p.norm()));
    EXPECT_NEAR(elevation_deg, kVlp16ElevationDeg[i % 16], 1e-6) << i;
  }
  // Firing j points at azimuth j * 0.398 deg.
  for (const std::size_t j : {0u, 1u, 226u, 452u, 904u}) {
    const Vec3& p = pts[16 * j];
    const double az_deg = RadToDeg(std::atan2(p.y(), p.x()));
    EXPECT_NEAR(std::remainder(az_deg - 0.398 * static_cast<double>(j), 360.0), 0.0, 1e-6) << j;
  }
}

TEST(Vlp16Test, SpinningBaseCoversAllAroundIn2Seconds) {
  // A roof 3 m above the ground over the sensor: each scan of the tilted sensor sees it on one
  // side only; the base's half turn per second brings every side into view within 2 s.
  World world = FlatWorld(40.0, 1.0);
  BoxObject roof;
  roof.length_m = 12.0;
  roof.width_m = 12.0;
  roof.base_m = 3.0;
  roof.height_m = 0.2;
  world.boxes.push_back(roof);
  const Scene scene(world);
  Vlp16Sim lidar(NoiseFree(), &scene.caster);
  const std::vector<TrueScan> scans = RunParked(&lidar, 2.0, 0.005);
  ASSERT_EQ(scans.size(), 40u);
  constexpr int kSectors = 12;
  auto sectors_seen = [](const std::vector<TrueScan>& run, std::size_t num_scans) {
    std::set<int> seen;
    for (std::size_t k = 0; k < num_scans; ++k) {
      for (const Vec3& p_S : run[k].points_S) {
        const Vec3 p_W = run[k].T_W_S * p_S;  // = B here
        if (p_W.z() < 2.9) continue;  // roof underside only
        const double az = std::atan2(p_W.y(), p_W.x()) + kPi;
        seen.insert(std::min(kSectors - 1, static_cast<int>(az / (2.0 * kPi) * kSectors)));
      }
    }
    return seen.size();
  };
  EXPECT_EQ(sectors_seen(scans, 40), static_cast<std::size_t>(kSectors));
  // Without the spin the same 2 s leave part of the roof unseen.
  Vlp16Sim::Config still = NoiseFree();
  still.mount.spin_hz = 0.0;
  Vlp16Sim still_lidar(still, &scene.caster);
  EXPECT_LT(sectors_seen(RunParked(&still_lidar, 2.0, 0.005), 40),
            static_cast<std::size_t>(kSectors) - 2);
  // Each scan carries the sensor pose at its end time.
  const SpinningLidarMount mount;
  for (const TrueScan& scan : scans) {
    EXPECT_TRUE(scan.T_W_S.isApprox(mount.T_B_S(scan.time_s), 1e-12));
  }
}

TEST(Vlp16Test, EachFiringUsesThePoseAtItsOwnTime) {
  // The vehicle drives at 5 m/s while turning at 30 deg/s over flat ground, in 5 ms physics
  // steps: carried into the world with the scan's end pose, every return lies on the ground.
  const Scene scene(FlatWorld(80.0, 1.0));
  Vlp16Sim lidar(NoiseFree(), &scene.caster);
  auto pose_at = [](double t) {
    TimedPose p;
    p.time_s = t;
    p.T_W_B.translation() = Vec3(5.0 * t, 0.0, 0.0);
    p.T_W_B.linear() = Eigen::AngleAxisd(DegToRad(30.0) * t, Vec3::UnitZ()).toRotationMatrix();
    return p;
  };
  std::vector<TrueScan> scans;
  for (int i = 0; i < 100; ++i) lidar.Advance(pose_at(0.005 * i), pose_at(0.005 * (i + 1)), &scans);
  ASSERT_EQ(scans.size(), 10u);
  for (const TrueScan& scan : scans) {
    ASSERT_FALSE(scan.points_S.empty());
    for (const Vec3& p_S : scan.points_S) EXPECT_NEAR((scan.T_W_S * p_S).z(), 0.0, 1e-3);
  }
}

TEST(Vlp16Test, NothingCloserThanMinRangeAndNothingBehindIt) {
  World world = FlatWorld(40.0, 1.0);
  BoxObject plate;  // 0.5 m in front of the sensor
  plate.x_m = 0.55;
  plate.length_m = 0.1;
  plate.width_m = 2.0;
  plate.height_m = 4.0;
  world.boxes.push_back(plate);
  BoxObject behind;
  behind.x_m = 5.0;
  behind.width_m = 2.0;
  behind.height_m = 4.0;
  world.boxes.push_back(behind);
  const Scene scene(world);
  const Vlp16Sim lidar(NoiseFree(), &scene.caster);
  Eigen::Isometry3d T_W_S = Eigen::Isometry3d::Identity();
  T_W_S.translation() = Vec3(0.0, 0.0, kSensorHeight_m);
  const std::vector<double> ranges = lidar.CastFiring(T_W_S, 0.0);
  for (int laser = 0; laser < 16; ++laser) {
    EXPECT_TRUE(std::isinf(ranges[static_cast<std::size_t>(laser)])) << laser;
  }
}

/// Range residuals of a scan of flat ground seen from a parked vehicle (origin on the mast);
/// +inf for returns of beams pointing at the sky (outliers).
std::vector<double> GroundResiduals(const TrueScan& scan) {
  std::vector<double> residuals;
  const Vec3 origin = scan.T_W_S.translation();
  for (const Vec3& p_S : scan.points_S) {
    const Vec3 p = scan.T_W_S * p_S;
    const Vec3 dir = (p - origin).normalized();
    residuals.push_back(dir.z() < 0.0 ? (p - origin).norm() - origin.z() / -dir.z() : kInf);
  }
  return residuals;
}

double Rms(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x * x;
  return std::sqrt(sum / static_cast<double>(v.size()));
}

TEST(Vlp16Test, NoiseAndFaultsFollowTheirParameters) {
  const Scene scene(FlatWorld(240.0, 2.0));
  auto one_scan = [&](const Vlp16Sim::Config& config) {
    Vlp16Sim lidar(config, &scene.caster);
    return RunParked(&lidar, 0.05, 0.005).at(0);
  };
  const TrueScan clean = one_scan(NoiseFree());
  ASSERT_GT(clean.points_S.size(), 5000u);
  EXPECT_LT(Rms(GroundResiduals(clean)), 1e-4);

  Vlp16Sim::Config noisy;  // default sigma 0.015 m
  EXPECT_NEAR(Rms(GroundResiduals(one_scan(noisy))), 0.015, 0.0015);

  Vlp16Sim::Config extra;
  extra.extra_noise_sigma_m = 0.05;
  EXPECT_NEAR(Rms(GroundResiduals(one_scan(extra))), std::hypot(0.015, 0.05), 0.004);

  Vlp16Sim::Config dropout = NoiseFree();
  dropout.dropout_fraction = 0.3;
  const TrueScan dropped = one_scan(dropout);
  const double kept = static_cast<double>(dropped.points_S.size()) / clean.points_S.size();
  EXPECT_NEAR(kept, 0.7, 0.03);
  EXPECT_EQ(dropped.points_S.size() + dropped.dropouts, clean.points_S.size());

  Vlp16Sim::Config outliers = NoiseFree();
  outliers.outlier_fraction = 0.1;
  const TrueScan spoiled = one_scan(outliers);
  EXPECT_NEAR(static_cast<double>(spoiled.outliers) / spoiled.rays, 0.1, 0.01);
  std::size_t off_ground = 0;
  for (const double r : GroundResiduals(spoiled)) off_ground += std::abs(r) > 0.05 ? 1 : 0;
  // Every outlier is a return (misses included) in front of what the beam would have hit.
  EXPECT_NEAR(static_cast<double>(off_ground), static_cast<double>(spoiled.outliers),
              0.05 * spoiled.outliers);
  for (const double r : GroundResiduals(spoiled)) {
    if (std::isfinite(r)) {
      EXPECT_LT(r, 1e-3);
    }
  }
}

/// Rough ground 40 m across, and a sensor with dropouts and outliers: every random draw in use.
World RoughWorld() {
  World world = FlatWorld(40.0, 0.5);
  world.terrain.kind = TerrainConfig::Kind::kRough;
  world.terrain.rough.amplitude_m = 0.3;
  return world;
}

Vlp16Sim::Config FaultyConfig(std::uint64_t seed) {
  Vlp16Sim::Config config;
  config.dropout_fraction = 0.1;
  config.outlier_fraction = 0.05;
  config.seed = seed;
  return config;
}

TEST(Vlp16Test, DeterministicFromTheSeedWhateverTheStepSize) {
  const Scene scene(RoughWorld());
  Vlp16Sim::Config config = FaultyConfig(11);
  Vlp16Sim a(config, &scene.caster);
  Vlp16Sim b(config, &scene.caster);
  const std::vector<TrueScan> fine = RunParked(&a, 0.2, 0.001);
  const std::vector<TrueScan> coarse = RunParked(&b, 0.2, 0.01);
  ASSERT_EQ(fine.size(), 4u);
  ASSERT_EQ(coarse.size(), 4u);
  for (std::size_t k = 0; k < fine.size(); ++k) EXPECT_EQ(fine[k].points_S, coarse[k].points_S);
  config.seed = 12;
  Vlp16Sim c(config, &scene.caster);
  EXPECT_NE(RunParked(&c, 0.05, 0.005).at(0).points_S, fine[0].points_S);
}

// The firings of a scan may be cast in any order and on any threads (issue 19's spread ray cast):
// each draws its noise and faults from its own stream, so the scans are bit for bit the same.
TEST(Vlp16Test, TheSameScansWhateverThreadsCastTheFirings) {
  const Scene scene(RoughWorld());
  const Vlp16Sim::Config config = FaultyConfig(5);
  Vlp16Sim in_order(config, &scene.caster);
  Vlp16Sim spread(config, &scene.caster);
  std::size_t calls = 0;
  // Backwards, the upper half on another thread.
  spread.SetParallelFor([&calls](std::size_t n, const std::function<void(std::size_t)>& fn) {
    ++calls;
    std::thread other([&] {
      for (std::size_t i = n; i-- > n / 2;) fn(i);
    });
    for (std::size_t i = n / 2; i-- > 0;) fn(i);
    other.join();
  });
  const std::vector<TrueScan> a = RunParked(&in_order, 0.2, 0.005);
  const std::vector<TrueScan> b = RunParked(&spread, 0.2, 0.005);
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(calls, 4u) << "one call per scan";
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].points_S, b[k].points_S) << k;
    EXPECT_EQ(a[k].outliers, b[k].outliers);
    EXPECT_EQ(a[k].dropouts, b[k].dropouts);
    EXPECT_GT(a[k].outliers, 0u);
  }
}

TEST(Vlp16Test, InvalidConfigsNameTheField) {
  Vlp16Sim::Config config;
  config.dropout_fraction = 1.5;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config = Vlp16Sim::Config{};
  config.mount.min_range_m = 200.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

// --- The LiDAR in the simulator -------------------------------------------------------------------

TEST(SimulatorLidarTest, NeverHitsTheEgoVehicle) {
  Simulator::Config config;
  config.world.terrain.size_x_m = 30.0;
  config.world.terrain.size_y_m = 30.0;
  config.world.terrain.kind = TerrainConfig::Kind::kRough;
  config.world.terrain.rough.amplitude_m = 0.1;
  CarportObject carport;  // with the roof right over the vehicle's path
  carport.x_m = 3.0;
  config.world.carports.push_back(carport);
  Simulator sim(config);
  sim.SetCommand(0.1, 2.0);
  sim.StepFor(1.0);
  const std::vector<Simulator::SensorScan> scans = sim.TakeScans();
  ASSERT_EQ(scans.size(), 20u);
  const GatorParams& v = config.vehicle;
  std::size_t points = 0;
  for (const Simulator::SensorScan& s : scans) {
    EXPECT_EQ(s.rays, 905u * 16u);
    // B at the scan time, from the true sensor pose and the mount's clock.
    const Eigen::Isometry3d T_B_S = v.lidar.T_B_S(s.scan.time_s);
    for (const Vec3& p_S : s.scan.points_S) {
      const Vec3 p_B = T_B_S * p_S;
      ++points;
      const bool inside = p_B.x() > -v.rear_overhang_m - 0.05 &&
                          p_B.x() < v.length_m - v.rear_overhang_m + 0.05 &&
                          std::abs(p_B.y()) < 0.5 * v.width_m + 0.05 && p_B.z() > 0.4 &&
                          p_B.z() < v.rops_height_m + 0.05;
      EXPECT_FALSE(inside) << p_B.transpose();
      if (inside) return;
    }
  }
  EXPECT_GT(points, 100000u);
  EXPECT_TRUE(sim.Warnings().empty());
}

}  // namespace
}  // namespace ovpc::sim
