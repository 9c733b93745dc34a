#include "ovpc/scenarios/closed_loop.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <utility>

#include "ovpc/backends/map_selection.h"
#include "ovpc/core/internal/clock.h"
#include "ovpc/navigation/navigator.h"
#include "ovpc/navigation/task_thread.h"
#include "ovpc/scenarios/recorder.h"
#include "ovpc/scenarios/referee.h"

namespace ovpc::scenarios {
namespace {

using ovpc::internal::Clock;
using ovpc::internal::MsSince;

// A second thread for the LiDAR's ray cast (threads >= 2): a scan's firings are split between it and
// the simulation thread while the navigator's map-and-plan cycle is not running on its worker (the
// two cores are then free); while the cycle runs, the simulation thread casts them alone, so that
// the cycle, which the simulation will wait for, keeps its core. Which thread casts a firing never
// changes the scan (Vlp16Sim::SetParallelFor).
void CastOnTwoThreads(navigation::TaskThread* helper, std::size_t n, const std::function<void(std::size_t)>& fn) {
  helper->Start([&fn, n] {
    for (std::size_t i = n / 2; i < n; ++i) fn(i);
  });
  std::exception_ptr mine;
  try {
    for (std::size_t i = 0; i < n / 2; ++i) fn(i);
  } catch (...) {
    mine = std::current_exception();
  }
  helper->Wait();  // rethrows what the helper's half threw
  if (mine) std::rethrow_exception(mine);
}

double RouteLength(const std::vector<Eigen::Vector2d>& route) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < route.size(); ++i) s += (route[i + 1] - route[i]).norm();
  return s;
}

void CopyStats(const navigation::Navigator& nav, RunResult* result) {
  result->navigator = nav.stats();
  result->map_backend = nav.map_backend().name();
  result->cycles = nav.cycles();
}

// The user's plug-ins, and where they give no map backend, the comparison backend the scenario
// names (none for OVPC: the navigator's default).
navigation::Navigator::Plugins PluginsFor(const Scenario& scenario, const navigation::Navigator::Config& nav_config,
                                          const RunOptions& options) {
  navigation::Navigator::Plugins plugins = options.make_plugins ? options.make_plugins(nav_config)
                                                                : navigation::Navigator::Plugins{};
  if (!plugins.map) plugins.map = backends::MakeMapBackend(scenario.map_backends, nav_config.ovpc.mapper.traversability);
  return plugins;
}

}  // namespace

RunResult RunClosedLoop(const Scenario& scenario, std::uint64_t seed, const RunOptions& options) {
  scenario.Validate();
  const auto wall_start = Clock::now();
  RunResult result;
  result.scenario = scenario.name;
  result.seed = seed;
  result.route_length_m = RouteLength(scenario.route_m);
  result.route_m = scenario.route_m;

  // One seed feeds every random source.
  sim::Simulator::Config sim_config = scenario.sim;
  sim_config.lidar.seed = seed * 1000003ULL + 1;
  sim_config.odometry.seed = seed * 1000003ULL + 2;
  sim::Simulator sim(sim_config);
  // The route is given in the world frame, which is the odometry frame when the run starts.
  const navigation::Navigator::Config& nav_config = scenario.navigator;
  navigation::Navigator nav(nav_config, scenario.route_m, PluginsFor(scenario, nav_config, options),
                            static_cast<std::uint32_t>(seed));
  nav.RunCyclesOnAWorkerThread(options.threads >= 2);
  std::unique_ptr<navigation::TaskThread> ray_cast_helper;
  if (options.threads >= 2) {
    ray_cast_helper = std::make_unique<navigation::TaskThread>();
    sim.SetRayCastParallelFor([&nav, helper = ray_cast_helper.get()](std::size_t n, const std::function<void(std::size_t)>& fn) {
      if (nav.CycleRunning()) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
      } else {
        CastOnTwoThreads(helper, n, fn);
      }
    });
  }
  Referee referee(scenario, sim_config.vehicle, sim.T_W_B());
  Recorder recorder(scenario, options, sim, &result);
  navigation::StageTimer t_physics;

  const double step_s = sim.timestep_s();
  double next_progress_s = 5.0;
  result.end_reason = "time limit";
  while (sim.time_s() + 0.5 * step_s < scenario.time_limit_s) {
    const double now = sim.time_s();
    const controller::Command command = nav.Control(now, sim.T_O_B(), sim.forward_speed_mps());
    sim.SetCommand(command.steering_rad, command.speed_mps);

    const auto t = Clock::now();
    sim.Step();
    std::vector<sim::Simulator::SensorScan> scans = sim.TakeScans();
    t_physics.Add(MsSince(t));
    for (auto& s : scans) {
      recorder.Scan(s);
      nav.AddScan(std::move(s.scan));
    }
    const double time = sim.time_s();
    const Eigen::Isometry3d T_W_B = sim.T_W_B();
    referee.Observe(time, T_W_B, sim.BodyContacts());
    recorder.Trajectory(now, time, sim, command);
    const Eigen::Isometry3d T_O_B = sim.T_O_B();
    if (nav.Update(time, T_O_B)) recorder.MapCycle(time, T_W_B * T_O_B.inverse(), nav);
    recorder.Frame(time, sim, nav);

    if (options.progress && time >= next_progress_s) {
      next_progress_s += 5.0;
      std::fprintf(stderr, "\r%s: t=%5.1f / %.0f s, route progress %5.1f / %.1f m, re-plans %zu   ", scenario.name.c_str(),
                   time, scenario.time_limit_s, nav.route_progress_m(), result.route_length_m, nav.stats().replans_found);
      std::fflush(stderr);
    }
    // The run ends when the goal region is reached (by the true pose), or when the vehicle has left
    // the terrain (beyond its edge there is nothing to drive on: it falls).
    if (referee.OffTerrain()) {
      result.end_reason = "off the terrain";
      break;
    }
    if (referee.GoalReached(time, T_W_B)) {
      result.end_reason = "goal reached";
      break;
    }
    if (!scenario.criteria.goal_m && nav.route_end_reached()) {
      referee.RouteEndReached(time);
      result.end_reason = "route end reached";
      break;
    }
  }
  if (options.progress) std::fprintf(stderr, "\n");

  result.sim_time_s = sim.time_s();
  result.wall_time_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  result.real_time_factor = result.wall_time_s > 0 ? result.sim_time_s / result.wall_time_s : 0.0;
  result.physics_lidar = t_physics.Stats();
  CopyStats(nav, &result);
  referee.Score(&result);
  recorder.Finish(result);
  return result;
}

}  // namespace ovpc::scenarios
