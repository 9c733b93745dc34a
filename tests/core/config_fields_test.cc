#include "ovpc/core/config_fields.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ovpc/core/ghpr.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/core/traversability.h"
#include "ovpc/core/vehicle_model.h"
#include "ovpc/core/vertex_cloud.h"
#include "../support/config_fields_check.h"

namespace ovpc {
namespace {

struct Inner {
  double a_m = 1.0;
  template <class C, class V>
  static void VisitFields(C& c, V& v) {
    v.Field(OVPC_FIELD(c, a_m), "m", "a");
  }
};

enum class Kind { kOne, kTwo };

struct Outer {
  int n = 2;
  std::vector<double> list_m;
  Kind kind = Kind::kOne;
  Inner inner;
  double forgotten = 0.0;  // not declared below
  void Validate() const {}
  template <class C, class V>
  static void VisitFields(C& c, V& v) {
    v.Field(OVPC_FIELD(c, n), "", "n");
    v.Field(OVPC_FIELD(c, list_m), "m", "a list");
    v.Choice(OVPC_FIELD(c, kind), Choices<Kind>{{"one", Kind::kOne}, {"two", Kind::kTwo}}, "a choice");
    v.Section(OVPC_FIELD(c, inner), "a section");
  }
};

// Collects the dotted keys, units and reasons.
struct KeyLister {
  std::string prefix;
  std::vector<std::string> keys;
  template <class T>
  void Field(const char* key, T&, const char* unit, const char*) {
    keys.push_back(prefix + key + "[" + unit + "]");
  }
  template <class E>
  void Choice(const char* key, const E&, Choices<E>, const char*) {
    keys.push_back(prefix + key);
  }
  template <class C>
  void Section(const char* key, C& config, const char*) {
    KeyLister sub;
    sub.prefix = prefix + key + ".";
    VisitFields(config, sub);
    keys.insert(keys.end(), sub.keys.begin(), sub.keys.end());
  }
};

TEST(ConfigFieldsTest, CountsTheMembersOfAnAggregate) {
  static_assert(CountMembers<Inner>() == 1);
  static_assert(CountMembers<Outer>() == 5, "vector, enum and nested aggregate members count once each");
  EXPECT_EQ(CountFields<Inner>(), 1u);
  EXPECT_EQ(CountFields<Outer>(), 4u) << "a member left out of VisitFields is seen";
  EXPECT_FALSE(testing::AllFieldsDeclared<Outer>());
  EXPECT_TRUE(testing::AllFieldsDeclared<Inner>());
}

TEST(ConfigFieldsTest, TheKeyIsTheFieldsOwnToken) {
  const Outer outer;
  KeyLister lister;
  VisitFields(outer, lister);
  EXPECT_EQ(lister.keys, (std::vector<std::string>{"n[]", "list_m[m]", "kind", "inner.a_m[m]"}));
}

TEST(ConfigFieldsTest, EveryCoreConfigDeclaresEveryMember) {
  EXPECT_TRUE(testing::AllFieldsDeclared<VehicleModel>());
  EXPECT_TRUE(testing::AllFieldsDeclared<PointCloudBuffer::Config>());
  EXPECT_TRUE(testing::AllFieldsDeclared<Ghpr::Config>());
  EXPECT_TRUE(testing::AllFieldsDeclared<Traversability::Config>());
  EXPECT_TRUE(testing::AllFieldsDeclared<VertexNormals::Config>());
  EXPECT_TRUE(testing::AllFieldsDeclared<OvpcMapper::Config>());
}

}  // namespace
}  // namespace ovpc
