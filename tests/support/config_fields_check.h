// A Config holds settings only, each declared once in its VisitFields (ovpc/core/config_fields.h):
// the aggregate's member count equals the number of fields it visits.
#pragma once

#include <gtest/gtest.h>

#include "ovpc/core/config_fields.h"

namespace ovpc::testing {

template <class T>
::testing::AssertionResult AllFieldsDeclared() {
  const std::size_t members = CountMembers<T>(), fields = CountFields<T>();
  if (members == fields) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the Config has " << members << " members and declares " << fields
                                       << " in its VisitFields: declare every member there (key, unit, reason)";
}

}  // namespace ovpc::testing
