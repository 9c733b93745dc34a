// A vehicle standing on flat ground with a post ahead, and the Navigator settings it needs: shared
// by the navigation tests and the comparison backends' tests.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/navigation/navigator.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc::testing {

/// 25 scans (1.25 s) of a vehicle standing at the origin of flat ground, heading +x, with a post at
/// (9, 3).
inline std::vector<Scan> FlatGroundScans(std::uint64_t seed) {
  synth::Scene scene;
  scene.cylinders.push_back({Vec3(9.0, 3.0, 0.0), 0.2, 2.0});
  return synth::SimulateScans(scene, SpinningLidarMount{}, Eigen::Isometry3d::Identity(), 0.0, 25, 0.01, seed);
}

/// The settings a flat-ground run needs beyond the library defaults (as in the default preset).
inline navigation::Navigator::Config FlatConfig() {
  navigation::Navigator::Config config;
  config.ovpc.mapper.traversability.noise_floor_m = 0.05;
  config.ovpc.map.normal_neighbours = 32;
  config.planner.vehicle.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
  config.planner.range_m = 1.0;
  config.local_goal.min_distance_m = 2.5;
  return config;
}

/// Feeds the scans and runs the first map cycle (due at 1 / map_rate_hz).
inline void FirstCycle(navigation::Navigator* nav, std::vector<Scan> scans) {
  const Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
  for (Scan& s : scans) nav->AddScan(std::move(s));
  EXPECT_FALSE(nav->Update(0.1, T_O_B)) << "no map cycle before 1 / map_rate_hz";
  EXPECT_TRUE(nav->Update(0.2, T_O_B));
}

}  // namespace ovpc::testing
