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
  EXPECT_TRUE(AllFieldsDeclared<planner::BoxRules>());
  EXPECT_TRUE(AllFieldsDeclared<planner::LocalPlanner::Config>());
  EXPECT_TRUE(AllFieldsDeclared<controller::PurePursuit::Config>());
  EXPECT_TRUE(AllFieldsDeclared<Navigator::Timing>());
  EXPECT_TRUE(AllFieldsDeclared<Navigator::PathChoice>());
  EXPECT_TRUE(AllFieldsDeclared<planner::RouteTracker::Config>());
  EXPECT_TRUE(AllFieldsDeclared<Navigator::Config>());
}

}  // namespace
}  // namespace ovpc::navigation
