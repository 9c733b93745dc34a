// A short scenario for tests that need a real closed-loop run that fits the unit label: flat ground,
// 6 m straight ahead, a few seconds of simulated time.
#pragma once

namespace ovpc::testing {

inline constexpr const char* kShortFlatScenario = R"(name: short_flat
time_limit_s: 8
terrain: {kind: flat, size_m: [40, 20]}
route: [[0, 0], [6, 0]]
criteria:
  goal: {x_m: 6.0, y_m: 0.0, radius_m: 1.0}
  no_collision: true
  max_time_s: 8
)";

}  // namespace ovpc::testing
