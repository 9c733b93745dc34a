// The map preparation: the lone-outlier filter and the footprint prior.
#include "ovpc/navigation/map_preparation.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

namespace ovpc::navigation {
namespace {

TEST(MapPreparationTest, IsolatedPointsNearTheSensorAreDroppedOthersKept) {
  Points cloud;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) cloud.emplace_back(2.0 + 0.1 * i, -1.0 + 0.1 * j, -1.9);  // ground
  }
  for (int k = 0; k < 8; ++k) cloud.emplace_back(6.0, 1.0, -1.9 + 0.2 * k);  // a thin post, hit every 0.2 m
  const Vec3 floating(3.0, 0.5, 0.2), far_floating(20.0, 3.0, 1.0), pair_a(4.0, -2.0, 0.5), pair_b(4.1, -2.05, 0.55);
  cloud.insert(cloud.begin() + 5, floating);
  cloud.push_back(far_floating);
  cloud.push_back(pair_a);
  cloud.push_back(pair_b);
  Points out = cloud;
  DropIsolatedPoints(0.25, 12.0, &out);
  EXPECT_EQ(out.size(), cloud.size() - 1);  // only the lone point within 12 m
  EXPECT_EQ(std::count(out.begin(), out.end(), floating), 0);
  EXPECT_EQ(std::count(out.begin(), out.end(), far_floating), 1);  // beyond the reach
  EXPECT_EQ(std::count(out.begin(), out.end(), pair_a), 1);        // two together are not alone
  EXPECT_EQ(out[5], cloud[6]);                                      // order kept
  Points off = cloud;
  DropIsolatedPoints(0.0, 12.0, &off);
  EXPECT_EQ(off, cloud);
  Points empty;
  DropIsolatedPoints(0.25, 12.0, &empty);
  EXPECT_TRUE(empty.empty());
}

TEST(MapPreparationTest, IsolatedPointFilterAgreesWithABruteForceSearch) {
  // Clusters and scattered points, some beyond the reach, some on cell edges (multiples of 0.25).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-15.0, 15.0), near(-0.3, 0.3);
  Points cloud;
  for (int i = 0; i < 1500; ++i) cloud.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  for (int i = 0; i < 1500; ++i) {
    const Vec3& c = cloud[static_cast<std::size_t>(i) % 300];
    cloud.push_back(c + Vec3(near(rng), near(rng), near(rng)));
  }
  for (int i = 0; i < 40; ++i) cloud.emplace_back(0.25 * i, -0.25 * i, 0.25 * (i % 3));
  Points expected;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    bool neighbour = cloud[i].squaredNorm() > 12.0 * 12.0;
    for (std::size_t j = 0; j < cloud.size() && !neighbour; ++j) {
      neighbour = j != i && (cloud[j] - cloud[i]).squaredNorm() <= 0.25 * 0.25;
    }
    if (neighbour) expected.push_back(cloud[i]);
  }
  Points out = cloud;
  DropIsolatedPoints(0.25, 12.0, &out);
  EXPECT_EQ(out, expected);
  EXPECT_LT(out.size(), cloud.size());  // something was dropped
}

TEST(MapPreparationTest, IsolatedPointFilterTakesDuplicatesAndHugeCoordinates) {
  // An exact duplicate is a neighbour; coordinates far beyond any integer cell key are grouped at
  // the clamped key, and still judged by their distances.
  Points cloud = {{1.0, 1.0, 0.0}, {1.0, 1.0, 0.0}, {-3.0, 2.0, 0.0},
                  {1e200, 1e200, 0.0}, {1e200, 1e200, 0.1}, {-1e200, 5e199, 0.0}};
  DropIsolatedPoints(0.25, 1e300, &cloud);
  const Points expected = {{1.0, 1.0, 0.0}, {1.0, 1.0, 0.0}, {1e200, 1e200, 0.0}, {1e200, 1e200, 0.1}};
  EXPECT_EQ(cloud, expected);
}

// The Gator's footprint in B: x from -0.45 to 2.35 m, y within +-0.75 m.
FootprintBox GatorFootprint() {
  FootprintBox box;
  box.min_x_m = -0.45;
  box.max_x_m = 2.35;
  box.half_width_m = 0.75;
  box.ground_band_m = 0.2;
  box.top_m = 2.35;
  box.body_margin_m = 0.12;
  return box;
}

bool Near(const Points& points, const Vec3& p, double d) {
  return std::any_of(points.begin(), points.end(), [&](const Vec3& q) { return (q - p).norm() <= d; });
}

TEST(MapPreparationTest, FootprintPriorDropsTheBodyKeepsPostsAndLaysTheGround) {
  // The vehicle at (10, 5) heading +y, its ground 1.88 m below the map frame's origin.
  Eigen::Isometry3d T_L_B = Eigen::Isometry3d::Identity();
  T_L_B.translate(Vec3(10.0, 5.0, -1.88));
  T_L_B.rotate(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  const Vec3 on_body = T_L_B * Vec3(1.0, 0.2, 1.0);     // a return off the vehicle itself
  const Vec3 post = T_L_B * Vec3(1.0, 1.2, 1.0);        // a post 0.45 m beside the body: kept
  const Vec3 roof = T_L_B * Vec3(1.0, 0.0, 2.6);        // above the box: kept
  const Vec3 ground_under = T_L_B * Vec3(0.5, 0.0, 0.05);  // measured ground under the body
  const Vec3 ground_far = T_L_B * Vec3(6.0, 0.0, 0.0);     // ground well ahead: kept
  const Points cloud = {on_body, post, roof, ground_under, ground_far};

  MapPreparation::Config config;  // kReplace, 0.3 m margin
  Points out = cloud;
  AddFootprintPrior(T_L_B, GatorFootprint(), config, &out);
  EXPECT_FALSE(Near(out, on_body, 1e-9));
  EXPECT_TRUE(Near(out, post, 1e-9));
  EXPECT_TRUE(Near(out, roof, 1e-9));
  EXPECT_FALSE(Near(out, ground_under, 1e-9)) << "kReplace drops measured ground under the grid";
  EXPECT_TRUE(Near(out, ground_far, 1e-9));
  // The grid covers the footprint grown by the margin, on the vehicle's ground plane, every 0.25 m.
  for (double x = -0.75; x <= 2.65; x += 0.25) {
    for (double y = -1.05; y <= 1.05; y += 0.25) {
      EXPECT_TRUE(Near(out, T_L_B * Vec3(x, y, 0.0), 0.13)) << x << ", " << y;
    }
  }
  EXPECT_FALSE(Near(out, T_L_B * Vec3(3.2, 0.0, 0.0), 0.3)) << "no grid beyond the margin";

  config.footprint_prior_mode = MapPreparation::PriorMode::kFill;
  Points filled = cloud;
  AddFootprintPrior(T_L_B, GatorFootprint(), config, &filled);
  EXPECT_TRUE(Near(filled, ground_under, 1e-9)) << "kFill keeps measured ground";
  // ... and lays no grid point within the grid's spacing of it.
  EXPECT_FALSE(std::any_of(filled.begin(), filled.end(), [&](const Vec3& q) {
    const Vec3 d = T_L_B.inverse() * q - T_L_B.inverse() * ground_under;
    return q != ground_under && d.head<2>().norm() < 0.25 && std::abs(d.z()) < 0.2;
  }));
  EXPECT_FALSE(Near(filled, on_body, 1e-9));
}

TEST(MapPreparationTest, InvalidSettingsAreRejectedByName) {
  MapPreparation::Config config;
  config.footprint_prior_blend_m = -1.0;
  try {
    config.Validate();
    FAIL() << "accepted a negative blend";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("footprint_prior_blend_m"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ovpc::navigation
