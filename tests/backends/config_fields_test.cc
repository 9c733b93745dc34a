// Every Config of the comparison backends declares every member in its VisitFields.
#include "ovpc/core/config_fields.h"

#include <gtest/gtest.h>

#include "../support/config_fields_check.h"
#include "ovpc/backends/map_selection.h"

namespace ovpc::backends {
namespace {

using ovpc::testing::AllFieldsDeclared;

TEST(ConfigFieldsTest, EveryBackendConfigDeclaresEveryMember) {
  EXPECT_TRUE(AllFieldsDeclared<ColumnMap::Config>());
  EXPECT_TRUE(AllFieldsDeclared<OctoMapBackend::Config>());
  EXPECT_TRUE(AllFieldsDeclared<baselines::ElevationMap::Config>());
  EXPECT_TRUE(AllFieldsDeclared<ElevationMapBackend::Config>());
  EXPECT_TRUE(AllFieldsDeclared<MapSelection>());
}

}  // namespace
}  // namespace ovpc::backends
