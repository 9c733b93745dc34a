// Every Config of the robot's stack declares every member in its VisitFields (ovpc/core/config_fields.h).
#include "ovpc/core/config_fields.h"

#include <gtest/gtest.h>

#include "../support/config_fields_check.h"
#include "ovpc/navigation/navigator.h"

namespace ovpc::navigation {
namespace {

using ovpc::testing::AllFieldsDeclared;

TEST(ConfigFieldsTest, EveryConfigOfTheStackDeclaresEveryMember) {
  EXPECT_TRUE(AllFieldsDeclared<planner::VertexCloudMap::Config>());
  EXPECT_TRUE(AllFieldsDeclared<planner::LocalGoalSelection::Config>());
  EXPECT_TRUE(AllFieldsDeclared<planner::Replanning::Config>());
  EXPECT_TRUE(AllFieldsDeclared<MapPreparation::Config>());
  EXPECT_TRUE(AllFieldsDeclared<OvpcMapBackend::Config>());
  EXPECT_TRUE(AllFieldsDeclared<Navigator::Config>());
}

// These still hold geometry that Navigator::Config::Derived() fills in from the VehicleModel (the
// box's size, centre, wheelbase and track; the turning radius and the per-run seed; the follower's
// wheelbase and steering limit): every other member is declared.
TEST(ConfigFieldsTest, ConfigsWithDerivedGeometryDeclareEveryOtherMember) {
  EXPECT_EQ(CountMembers<planner::VehicleBox>(), CountFields<planner::VehicleBox>() + 6);
  EXPECT_EQ(CountMembers<planner::LocalPlanner::Config>(), CountFields<planner::LocalPlanner::Config>() + 2);
  EXPECT_EQ(CountMembers<controller::PurePursuit::Config>(), CountFields<controller::PurePursuit::Config>() + 2);
}

}  // namespace
}  // namespace ovpc::navigation
