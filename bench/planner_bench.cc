// Local planner benchmark (Google Benchmark): planning time on the planner tests' generated scenes
// (tests/planner/planning_scenes.h: flat ground, a cluster of posts, a carport roof at 2.5 m, a
// slab at 1.6 m, a 35 deg slope), each map built once by the real OvpcMapper.
//
// Each benchmark iteration is one LocalPlanner::Plan call with the next seed (1, 2, 3, ...), so the
// counters describe the spread over seeds: median_ms and p90_ms of single plans (steady_clock around
// Plan only), found = the share of plans with a path, iters = mean planner iterations. Everything runs
// on one thread. The 35 deg scene has no path: it measures a plan that spends the whole budget.
// The `loop` variants use the closed loop's rule (scenario defaults: 1 m tree extensions, the wheels'
// footprint rule, the box on the plane fitted to 32 neighbours) instead of LocalPlanner::Config's
// and VertexCloudMap::Config's (the paper's box rule and vertex normal, OMPL's default range). Each
// loop plan gets a fresh map, as each map update does in the loop (its fitted planes are made during
// the plan); building it is not timed.
//
//   build/bench/ovpc_planner_bench [--benchmark_min_time=2]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include <benchmark/benchmark.h>

#include "../tests/planner/planning_scenes.h"
#include "ovpc/planner/local_planner.h"
#include "ovpc/planner/vertex_cloud_map.h"

namespace ovpc::bench {
namespace {

using Clock = std::chrono::steady_clock;

const testing::PlanningScene& Scene(int which) {
  static const std::vector<testing::PlanningScene> scenes = {
      testing::BuildScene(testing::FlatScene()),    testing::BuildScene(testing::PostsScene()),
      testing::BuildScene(testing::CarportScene()), testing::BuildScene(testing::LowRoofScene()),
      testing::BuildScene(testing::SlopeScene(35.0)),
  };
  return scenes.at(static_cast<std::size_t>(which));
}

void BM_Plan(benchmark::State& state) {
  const testing::PlanningScene& scene = Scene(static_cast<int>(state.range(0)));
  std::vector<double> ms;
  double found = 0.0, iterations = 0.0;
  std::uint32_t seed = 0;
  for (auto _ : state) {
    planner::LocalPlanner::Config config;
    if (state.range(1) > 0) config.max_iterations = static_cast<unsigned>(state.range(1));
    if (state.range(2) != 0) {
      config.range_m = 1.0;
      config.vehicle.footprint_check = planner::VehicleBox::FootprintCheck::kWheels;
    }
    const planner::LocalPlanner planner(config, VehicleModel{}, ++seed);
    std::optional<planner::VertexCloudMap> loop_map;
    if (state.range(2) != 0) {
      planner::VertexCloudMap::Config map_config = scene.map->config();
      map_config.normal_neighbours = 32;
      loop_map.emplace(scene.map->cloud(), map_config);
    }
    const planner::PlanningMap& map = loop_map ? static_cast<const planner::PlanningMap&>(*loop_map) : *scene.map;
    const auto start = Clock::now();
    const planner::PlanResult result = planner.Plan(map, scene.spec.start, scene.spec.goal);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    benchmark::DoNotOptimize(result.path.segments().data());
    found += result.found();
    iterations += result.iterations;
  }
  std::sort(ms.begin(), ms.end());
  const double n = static_cast<double>(ms.size());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p90_ms"] = ms[std::min(ms.size() - 1, static_cast<std::size_t>(0.9 * n))];
  state.counters["found"] = found / n;
  state.counters["iters"] = iterations / n;
  state.counters["points"] = static_cast<double>(scene.map->cloud().size());
}

// Arguments: scene, iteration budget (0: the default of LocalPlanner::Config), rule (0: the config's
// defaults, 1: the closed loop's).
BENCHMARK(BM_Plan)->ArgNames({"flat", "budget", "loop"})->Args({0, 0, 0})->Args({0, 0, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan)->ArgNames({"posts", "budget", "loop"})->Args({1, 0, 0})->Args({1, 0, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan)
    ->ArgNames({"carport_2p5m", "budget", "loop"})
    ->Args({2, 0, 0})
    ->Args({2, 0, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan)->ArgNames({"roof_1p6m", "budget", "loop"})->Args({3, 0, 0})->Args({3, 0, 1})->Unit(benchmark::kMillisecond);
// No path: the whole budget is spent. Its cost grows with the budget faster than linearly, as the
// trees grow.
BENCHMARK(BM_Plan)
    ->ArgNames({"slope_35deg_no_path", "budget", "loop"})
    ->Args({4, 0, 0})
    ->Args({4, 250, 0})
    ->Args({4, 1000, 0})
    ->Args({4, 0, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ovpc::bench

BENCHMARK_MAIN();
