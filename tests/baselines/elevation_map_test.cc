#include "ovpc/baselines/elevation_map.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace ovpc::baselines {
namespace {

using Map = ElevationMap;

/// A small map: 0.1 m cells over 4 m, constant measurement noise (no range term) so that the
/// expected Kalman figures are simple.
Map::Config SmallConfig() {
  Map::Config config;
  config.resolution_m = 0.1;
  config.length_m = 4.0;
  config.sensor_sigma_m = 0.05;
  config.sensor_sigma_per_m = 0.0;
  return config;
}

constexpr double kSigma = 0.05;
constexpr double kR = kSigma * kSigma;
/// Sensor 1.88 m above the base, base at z = 0 (the paper's mount).
const Vec3 kSensor(0.0, 0.0, 1.88);
constexpr double kBase = 0.0;
/// The centre of the cell [1.0, 1.1) x [0.5, 0.6).
const Eigen::Vector2d kCellXY(1.05, 0.55);

Vec3 At(double z) { return Vec3(kCellXY.x(), kCellXY.y(), z); }

TEST(ElevationMapTest, FirstMeasurementInitialisesTheCell) {
  Map map(SmallConfig());
  EXPECT_FALSE(map.HeightAt(kCellXY).has_value());
  const Map::UpdateStats stats = map.Update({At(0.2)}, kSensor, kBase);
  EXPECT_EQ(stats.initialised, 1u);
  ASSERT_TRUE(map.HeightAt(kCellXY).has_value());
  EXPECT_NEAR(*map.HeightAt(kCellXY), 0.2, 1e-6);
  EXPECT_NEAR(*map.VarianceAt(kCellXY), kR, 1e-9);
  EXPECT_EQ(map.num_nonempty(), 1u);
}

TEST(ElevationMapTest, RepeatedMeasurementsReduceTheVariance) {
  Map map(SmallConfig());
  // Heights spread well inside the gate; the Kalman fusion of n equal-variance measurements is
  // their mean with variance R / n.
  const double heights[] = {0.10, 0.12, 0.08, 0.11, 0.09, 0.10, 0.13, 0.07};
  double previous = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  int n = 0;
  for (const double h : heights) {
    map.Update({At(h)}, kSensor, kBase);
    sum += h;
    ++n;
    const double variance = *map.VarianceAt(kCellXY);
    EXPECT_LT(variance, previous);
    EXPECT_NEAR(variance, kR / n, 1e-5 * kR);
    EXPECT_NEAR(*map.HeightAt(kCellXY), sum / n, 1e-6);
    previous = variance;
  }
  EXPECT_EQ(map.FindCell(kCellXY)->measurements, 8u);
}

TEST(ElevationMapTest, RangeDependentNoiseWeighsNearPointsMore) {
  Map::Config config = SmallConfig();
  config.sensor_sigma_per_m = 0.01;
  Map map(config);
  EXPECT_NEAR(map.MeasurementVariance(0.0), kR, 1e-12);
  EXPECT_NEAR(map.MeasurementVariance(10.0), (kSigma + 0.1) * (kSigma + 0.1), 1e-12);
  // Two heights 5 cm apart from different ranges: the near one (smaller variance) pulls harder.
  const Vec3 near_sensor(kCellXY.x(), kCellXY.y(), 1.0);
  const Vec3 far_sensor(kCellXY.x() + 1.0, kCellXY.y(), 20.0);
  map.Update({At(0.0)}, near_sensor, kBase);
  map.Update({At(0.05)}, far_sensor, kBase);
  EXPECT_LT(*map.HeightAt(kCellXY), 0.025);
  EXPECT_GT(*map.HeightAt(kCellXY), 0.0);
}

TEST(ElevationMapTest, LowerOutlierBeyondTheGateIsRejected) {
  Map map(SmallConfig());
  for (int i = 0; i < 4; ++i) map.Update({At(0.5)}, kSensor, kBase);
  const double variance = *map.VarianceAt(kCellXY);
  // Gate: 2.5 sqrt(P + R) = 2.5 sqrt(R/4 + R) = 0.14 m; 0.3 m lower is far outside.
  const Map::UpdateStats stats = map.Update({At(0.2)}, kSensor, kBase);
  EXPECT_EQ(stats.rejected, 1u);
  EXPECT_EQ(stats.fused + stats.replaced + stats.initialised, 0u);
  EXPECT_NEAR(*map.HeightAt(kCellXY), 0.5, 1e-6);
  EXPECT_NEAR(*map.VarianceAt(kCellXY), variance, 1e-12);
}

TEST(ElevationMapTest, HigherMeasurementBeyondTheGateReplacesTheCell) {
  Map map(SmallConfig());
  for (int i = 0; i < 4; ++i) map.Update({At(0.0)}, kSensor, kBase);
  const Map::UpdateStats stats = map.Update({At(0.4)}, kSensor, kBase);
  EXPECT_EQ(stats.replaced, 1u);
  EXPECT_NEAR(*map.HeightAt(kCellXY), 0.4, 1e-6);
  EXPECT_NEAR(*map.VarianceAt(kCellXY), kR, 1e-9);  // the new measurement's, not the fused one
}

TEST(ElevationMapTest, GateIsOnTheInnovationVarianceAtThreshold2p5) {
  Map map(SmallConfig());
  EXPECT_DOUBLE_EQ(map.config().mahalanobis_threshold, 2.5);
  map.Update({At(0.0)}, kSensor, kBase);  // P = R
  const double gate_m = 2.5 * std::sqrt(2.0 * kR);
  // Just inside the gate, higher: fused (the height moves half-way, P halves).
  Map::UpdateStats stats = map.Update({At(0.99 * gate_m)}, kSensor, kBase);
  EXPECT_EQ(stats.fused, 1u);
  EXPECT_NEAR(*map.HeightAt(kCellXY), 0.5 * 0.99 * gate_m, 1e-6);
  EXPECT_NEAR(*map.VarianceAt(kCellXY), 0.5 * kR, 1e-9);
  // Just outside the gate of the new state, lower: rejected.
  const double h = *map.HeightAt(kCellXY);
  const double gate_now_m = 2.5 * std::sqrt(0.5 * kR + kR);
  stats = map.Update({At(h - 1.01 * gate_now_m)}, kSensor, kBase);
  EXPECT_EQ(stats.rejected, 1u);
}

TEST(ElevationMapTest, RoofAboveTheSensorReplacesTheGroundUnderIt) {
  // A roof at 2.5 m over the robot (sensor at 1.88 m): in the cells under it, ground points and
  // roof points fall into the same cells. With the default crop (3 m above the base) both count,
  // and whichever order they come in, the roof wins: the ground under the roof is lost and the
  // cells read as a 2.5 m obstacle.
  Map map(SmallConfig());
  ASSERT_GT(map.config().max_height_above_base_m, 2.5);
  Points points;
  for (int i = 0; i < 5; ++i) points.push_back(At(0.0));
  points.push_back(At(2.5));
  for (int i = 0; i < 5; ++i) points.push_back(At(0.0));
  const Map::UpdateStats stats = map.Update(points, kSensor, kBase);
  EXPECT_NEAR(*map.HeightAt(kCellXY), 2.5, 1e-6);
  EXPECT_EQ(stats.replaced, 1u);
  EXPECT_EQ(stats.rejected, 5u);  // the ground after the roof is "lower beyond the gate"
}

TEST(ElevationMapTest, RoofAboveTheCropIsDroppedAndTheGroundKept) {
  // Cropping below the roof maps the ground under it, and then the roof is absent from the map:
  // a 2.5D map holds either the roof or the ground under it, never both.
  Map::Config config = SmallConfig();
  config.max_height_above_base_m = 2.0;
  Map map(config);
  const Map::UpdateStats stats =
      map.Update({At(0.0), At(2.5), At(2.6), At(0.01)}, kSensor, kBase);
  EXPECT_EQ(stats.cropped, 2u);
  EXPECT_NEAR(*map.HeightAt(kCellXY), 0.005, 1e-6);
}

TEST(ElevationMapTest, HeightCropIsRelativeToTheBase) {
  Map::Config config = SmallConfig();
  config.min_height_above_base_m = -0.5;
  config.max_height_above_base_m = 1.0;
  Map map(config);
  // Base at z = 10: only points with z in [9.5, 11] count.
  const Map::UpdateStats stats =
      map.Update({At(9.0), At(9.6), At(10.9), At(11.5)}, Vec3(0, 0, 11.88), 10.0);
  EXPECT_EQ(stats.cropped, 2u);
  EXPECT_EQ(stats.initialised, 1u);
  EXPECT_EQ(stats.replaced, 1u);  // 10.9 is far above 9.6
}

TEST(ElevationMapTest, CountsEveryPointOnce) {
  Map map(SmallConfig());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Map::UpdateStats stats = map.Update(
      {At(0.0), Vec3(nan, 0.0, 0.0), Vec3(5.0, 0.0, 0.0), Vec3(0.0, -2.01, 0.0), At(0.01), At(9.0)},
      kSensor, kBase);
  EXPECT_EQ(stats.input, 6u);
  EXPECT_EQ(stats.non_finite, 1u);
  EXPECT_EQ(stats.outside_map, 2u);
  EXPECT_EQ(stats.cropped, 1u);
  EXPECT_EQ(stats.initialised, 1u);
  EXPECT_EQ(stats.fused, 1u);
  EXPECT_EQ(stats.input, stats.non_finite + stats.cropped + stats.outside_map +
                             stats.initialised + stats.fused + stats.replaced + stats.rejected);
}

TEST(ElevationMapTest, MapExtentAndCellBoundaries) {
  Map map(SmallConfig());
  EXPECT_EQ(map.cells_per_side(), 40);
  EXPECT_NEAR((map.centre() - Eigen::Vector2d::Zero()).norm(), 0.0, 1e-12);
  EXPECT_NE(map.FindCell({-1.999, 1.999}), nullptr);
  EXPECT_EQ(map.FindCell({2.001, 0.0}), nullptr);
  EXPECT_EQ(map.FindCell({0.0, -2.001}), nullptr);
  // Two points in neighbouring cells do not mix.
  map.Update({Vec3(0.05, 0.05, 1.0), Vec3(0.15, 0.05, 0.0)}, kSensor, kBase);
  EXPECT_NEAR(*map.HeightAt({0.05, 0.05}), 1.0, 1e-6);
  EXPECT_NEAR(*map.HeightAt({0.15, 0.05}), 0.0, 1e-6);
}

TEST(ElevationMapTest, MovingKeepsCellsInPlaceAndClearsNewOnes) {
  Map map(SmallConfig());
  map.Update({Vec3(1.55, 0.25, 0.7), Vec3(-1.95, 0.0, 0.3)}, kSensor, kBase);
  map.Move({1.0, 0.0});  // robot-centric: the map follows the robot 1 m along +x
  EXPECT_NEAR((map.centre() - Eigen::Vector2d(1.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(*map.HeightAt({1.55, 0.25}), 0.7, 1e-6);  // same world place, same height
  EXPECT_EQ(map.FindCell({-1.95, 0.0}), nullptr);        // left the map
  EXPECT_FALSE(map.HeightAt({2.9, 0.0}).has_value());    // entered the map empty
  EXPECT_EQ(map.num_nonempty(), 1u);
  // Snapped to whole cells: a move of less than half a cell changes nothing.
  map.Move({1.04, 0.0});
  EXPECT_NEAR((map.centre() - Eigen::Vector2d(1.0, 0.0)).norm(), 0.0, 1e-12);
  map.Clear();
  EXPECT_EQ(map.num_nonempty(), 0u);
}

TEST(ElevationMapTest, InvalidConfigAndArgumentsThrow) {
  auto make = [](auto change) {
    Map::Config config = SmallConfig();
    change(config);
    return config;
  };
  EXPECT_THROW(Map(make([](Map::Config& c) { c.resolution_m = 0.0; })), std::invalid_argument);
  EXPECT_THROW(Map(make([](Map::Config& c) { c.length_m = 0.05; })), std::invalid_argument);
  EXPECT_THROW(Map(make([](Map::Config& c) { c.length_m = 1e6; })), std::invalid_argument);
  EXPECT_THROW(Map(make([](Map::Config& c) { c.mahalanobis_threshold = -1.0; })),
               std::invalid_argument);
  EXPECT_THROW(Map(make([](Map::Config& c) { c.sensor_sigma_m = 0.0; })), std::invalid_argument);
  EXPECT_THROW(Map(make([](Map::Config& c) {
                 c.min_height_above_base_m = 1.0;
                 c.max_height_above_base_m = 0.5;
               })),
               std::invalid_argument);
  try {
    Map(make([](Map::Config& c) { c.resolution_m = -1.0; }));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("resolution_m"), std::string::npos);
  }
  Map map(SmallConfig());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(map.Update({}, Vec3(nan, 0, 0), 0.0), std::invalid_argument);
  EXPECT_THROW(map.Update({}, kSensor, nan), std::invalid_argument);
  EXPECT_THROW(map.Move({nan, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::baselines
