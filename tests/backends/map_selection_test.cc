// The comparison backends behind the navigator's seam, made by name (MapSelection): each maps the
// flat ground ahead with the post in the way, plans on it and times its stages, judging slopes and
// steps with the OVPC face test's thresholds; bad settings are refused naming the field, before
// anything is allocated.
#include "ovpc/backends/map_selection.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../support/test_navigation.h"
#include "ovpc/navigation/navigator.h"

namespace ovpc::backends {
namespace {

using navigation::Navigator;
using planner::Pose2;

std::unique_ptr<Navigator> NavigatorWith(MapSelection::Kind kind) {
  MapSelection selection;
  selection.map = kind;
  const Navigator::Config config = testing::FlatConfig();
  Navigator::Plugins plugins;
  plugins.map = MakeMapBackend(selection, config.ovpc.mapper.traversability);
  return std::make_unique<Navigator>(config, std::vector<Eigen::Vector2d>{{0.0, 0.0}, {20.0, 0.0}},
                                     std::move(plugins));
}

TEST(MapSelectionTest, EachComparisonBackendMapsPlansAndTimesItsStages) {
  const struct {
    MapSelection::Kind kind;
    const char* name;
    std::vector<std::string> stages;
  } cases[] = {
      {MapSelection::Kind::kOctoMap, "octomap", {"insert", "columns", "traversability"}},
      {MapSelection::Kind::kElevation, "elevation", {"fuse", "columns", "traversability"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::unique_ptr<Navigator> nav = NavigatorWith(c.kind);
    EXPECT_STREQ(nav->map_backend().name(), c.name);
    EXPECT_STREQ(MapKindName(c.kind), c.name);
    testing::FirstCycle(nav.get(), testing::FlatGroundScans(1));
    ASSERT_EQ(nav->cycles().size(), 1u);
    EXPECT_TRUE(nav->cycles()[0].map_ok);
    EXPECT_FALSE(nav->plan_log().empty()) << "a plan was tried on the map";
    // The map it planned on: free ground ahead of the vehicle, the post at (9, 3) in the way.
    ASSERT_NE(nav->map(), nullptr);
    const planner::VehicleBox& box = nav->box();
    EXPECT_EQ(planner::CheckPose(*nav->map(), box, Pose2{3.0, 0.0, 0.0}), planner::PoseCheck::kValid);
    EXPECT_NE(planner::CheckPose(*nav->map(), box, Pose2{7.5, 3.0, 0.0}), planner::PoseCheck::kValid);
    EXPECT_EQ(planner::CheckPose(*nav->map(), box, Pose2{7.5, -3.0, 0.0}), planner::PoseCheck::kValid) << "no post there";
    const navigation::NavigatorStats stats = nav->stats();
    ASSERT_EQ(stats.map_stages.size(), c.stages.size());
    for (std::size_t i = 0; i < c.stages.size(); ++i) {
      EXPECT_EQ(stats.map_stages[i].first, c.stages[i]);
      EXPECT_EQ(stats.map_stages[i].second.calls, 1u);
    }
    const navigation::MapView view = nav->map_backend().View();
    ASSERT_NE(view.points_L, nullptr);
    EXPECT_GT(view.points_L->size(), 100u);
  }
}

TEST(MapSelectionTest, OvpcIsTheNavigatorsOwnAndTheOthersTakeItsFaceThresholds) {
  Traversability::Config faces;
  faces.alpha_max_rad = DegToRad(25.0);
  faces.delta_h_max_m = 0.2;
  MapSelection selection;
  EXPECT_EQ(MakeMapBackend(selection, faces), nullptr) << "kOvpc: the navigator's default backend";
  EXPECT_STREQ(MapKindName(selection.map), "ovpc");
  selection.map = MapSelection::Kind::kOctoMap;
  const auto octomap = MakeMapBackend(selection, faces);
  ASSERT_NE(octomap, nullptr);
  EXPECT_DOUBLE_EQ(dynamic_cast<const OctoMapBackend&>(*octomap).faces().alpha_max_rad, DegToRad(25.0));
  selection.map = MapSelection::Kind::kElevation;
  const auto elevation = MakeMapBackend(selection, faces);
  ASSERT_NE(elevation, nullptr);
  EXPECT_DOUBLE_EQ(dynamic_cast<const ElevationMapBackend&>(*elevation).faces().delta_h_max_m, 0.2);
}

// The message of the std::invalid_argument `validate` throws ("" when it throws none).
template <class F>
std::string Refusal(F validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(MapSelectionTest, BadSettingsAreRefusedNamingTheField) {
  MapSelection s;
  EXPECT_EQ(Refusal([&] { s.Validate(); }), "");
  s.octomap.resolution_m = 0.0;
  EXPECT_NE(Refusal([&] { s.Validate(); }).find("octomap.resolution_m"), std::string::npos) << "checked whichever runs";
  s = MapSelection{};
  s.elevation.map.normal_radius_m = -1.0;
  EXPECT_NE(Refusal([&] { s.Validate(); }).find("normal_radius_m"), std::string::npos);
}

// A grid rebuilt every update is bounded in cells a side, and the plane fit's radius in cells: the
// library's limits (25,000 cells a side, any radius) let one update take minutes or all memory.
TEST(MapSelectionTest, GridSizeAndNormalRadiusAreBounded) {
  ElevationMapBackend::Config elevation;
  elevation.grid.length_m = 200.0;  // 2,000 cells of 0.1 m: the most
  EXPECT_EQ(Refusal([&] { elevation.Validate(); }), "");
  elevation.grid.length_m = 2500.0;  // 25,000 cells: baselines' own limit
  EXPECT_NO_THROW(elevation.grid.Validate());
  EXPECT_NE(Refusal([&] { elevation.Validate(); }).find("elevation.grid.length_m / resolution_m must be at most 2000"),
            std::string::npos)
      << Refusal([&] { elevation.Validate(); });
  EXPECT_THROW(ElevationMapBackend{elevation}, std::invalid_argument) << "refused before the grid is allocated";

  elevation = ElevationMapBackend::Config{};
  elevation.map.normal_radius_m = 2.0;  // 20 cells of 0.1 m: the most
  EXPECT_EQ(Refusal([&] { elevation.Validate(); }), "");
  elevation.map.normal_radius_m = 1e6;
  EXPECT_NE(Refusal([&] { elevation.Validate(); }).find("elevation.map.normal_radius_m must be at most 20"),
            std::string::npos)
      << Refusal([&] { elevation.Validate(); });

  OctoMapBackend::Config octomap;
  octomap.map.normal_radius_m = 4.0;  // 20 voxels of 0.2 m
  EXPECT_EQ(Refusal([&] { octomap.Validate(); }), "");
  octomap.map.normal_radius_m = 4.5;
  EXPECT_NE(Refusal([&] { octomap.Validate(); }).find("octomap.map.normal_radius_m must be at most 20"),
            std::string::npos)
      << Refusal([&] { octomap.Validate(); });
}

}  // namespace
}  // namespace ovpc::backends
