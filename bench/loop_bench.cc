// Closed-loop benchmark: what a simulated second of a scenario costs, in one process, side by side.
//
// For each scenario (default: carport_2p5, flat_posts, rough_ground, slope_20 at seed 1, with the
// default preset) it runs the closed loop with one thread and with two (the navigator's
// map-and-plan cycle beside the simulation for navigator.timing.latency_s, and the ray cast shared),
// alternating, and prints the medians over the repetitions of:
//   - the wall-clock real-time factor with 1 and with 2 threads, and their ratio;
//   - the CPU time per simulated second of the one-thread run (the whole process: every thread);
//   - each stage in ms of wall time per simulated second (one-thread run): physics + LiDAR, buffer,
//     map update, planning;
//   - the ray cast alone: the scenario's LiDAR (16 lasers, 905 firings per scan, 20 Hz) replayed
//     along the run's recorded trajectory against its world, ms of CPU per simulated second: the
//     floor under physics + LiDAR.
// The one- and two-thread runs must give the same trajectory; a difference is printed and the exit
// code is 1.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "ovpc/scenarios/closed_loop.h"
#include "ovpc/scenarios/scenario_yaml.h"
#include "ovpc/sim/ray_caster.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/vlp16.h"
#include "ovpc/sim/world.h"

namespace {

using ovpc::scenarios::RunClosedLoop;
using ovpc::scenarios::RunOptions;
using ovpc::scenarios::RunResult;
using ovpc::scenarios::Scenario;

double ProcessCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double ThreadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Timed {
  RunResult result;
  double wall_s = 0.0;
  double cpu_s = 0.0;
};

Timed Run(const Scenario& scenario, std::uint64_t seed, int threads) {
  RunOptions options;
  options.threads = threads;
  const double cpu0 = ProcessCpuS();
  const auto wall0 = std::chrono::steady_clock::now();
  Timed t;
  t.result = RunClosedLoop(scenario, seed, options);
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  t.cpu_s = ProcessCpuS() - cpu0;
  return t;
}

bool SameTrajectory(const RunResult& a, const RunResult& b) {
  if (a.trajectory.size() != b.trajectory.size()) return false;
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) {
    if (!a.trajectory[i].T_W_B.isApprox(b.trajectory[i].T_W_B, 0.0) ||
        a.trajectory[i].cmd_speed_mps != b.trajectory[i].cmd_speed_mps) {
      return false;
    }
  }
  return true;
}

// The scenario's LiDAR replayed along the recorded true trajectory: ms of CPU per simulated second.
double RayCastAloneMsPerS(const Scenario& scenario, std::uint64_t seed, const RunResult& run) {
  const ovpc::sim::Heightfield terrain = ovpc::sim::MakeHeightfield(scenario.sim.world.terrain);
  const std::vector<ovpc::sim::Solid> solids = ovpc::sim::ResolveSolids(scenario.sim.world, terrain);
  const ovpc::sim::RayCaster caster(terrain, solids, scenario.sim.ray_caster);
  ovpc::sim::Vlp16Sim::Config lidar = scenario.sim.lidar;
  lidar.mount = scenario.sim.vehicle.lidar;
  lidar.seed = seed;
  const auto& traj = run.trajectory;
  if (traj.size() < 2) return 0.0;
  ovpc::sim::Vlp16Sim sensor(lidar, &caster, traj.front().time_s);
  std::vector<ovpc::sim::TrueScan> scans;
  const double cpu0 = ThreadCpuS();
  for (std::size_t i = 1; i < traj.size(); ++i) {
    sensor.Advance({traj[i - 1].time_s, traj[i - 1].T_W_B}, {traj[i].time_s, traj[i].T_W_B}, &scans);
    scans.clear();
  }
  const double span_s = traj.back().time_s - traj.front().time_s;
  return 1000.0 * (ThreadCpuS() - cpu0) / span_s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Closed-loop benchmark: real-time factor with 1 and 2 threads, CPU per simulated second, each "
               "stage and the ray cast alone, per scenario"};
  std::vector<std::string> scenarios = {"carport_2p5", "flat_posts", "rough_ground", "slope_20"};
  std::string dir = OVPC_SCENARIO_DIR;
  std::uint64_t seed = 1;
  const int threads = 2;  // the navigator's worker, and the ray cast's second thread
  int reps = 3;
  std::vector<std::string> settings;
  app.add_option("--scenarios", scenarios, "Scenario names in --dir, or paths to scenario files")->delimiter(',')
      ->capture_default_str();
  app.add_option("--dir", dir, "Where scenario names are looked up")->capture_default_str();
  app.add_option("--seed", seed, "Run seed")->capture_default_str();
  app.add_option("--reps", reps, "Repetitions (medians are printed)")->check(CLI::Range(1, 100))->capture_default_str();
  app.add_option("--set", settings, "A scenario override for every run, dotted.key=value (repeatable)");
  CLI11_PARSE(app, argc, argv);

  // Every scenario is read before anything runs: a bad one is reported at once.
  std::vector<Scenario> loaded;
  for (const std::string& name : scenarios) {
    const std::string path = name.find('/') != std::string::npos || name.find(".yaml") != std::string::npos
                                 ? name
                                 : dir + "/" + name + ".yaml";
    try {
      loaded.push_back(ovpc::scenarios::LoadScenario(path, settings));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ovpc_loop_bench: %s\n", e.what());
      return 2;
    }
  }
  std::printf("%-14s %6s | %7s %7s %6s | %8s | %8s %7s %7s %8s | %9s\n", "scenario", "sim s", "RTF 1", "RTF 2",
              "2 / 1", "CPU ms/s", "phys+LiD", "buffer", "map", "planning", "ray cast");
  std::printf("%-14s %6s | %7s %7s %6s | %8s | %8s %7s %7s %8s | %9s\n", "", "", "", "", "", "(1 thr)",
              "ms/s", "ms/s", "ms/s", "ms/s", "ms/s alone");
  int status = 0;
  for (const Scenario& scenario : loaded) {
    std::vector<double> rtf1, rtfn, ratio, cpu, phys, buffer, map, plan, ray;
    double sim_s = 0.0;
    for (int r = 0; r < reps; ++r) {
      std::fprintf(stderr, "[%s] repetition %d/%d\n", scenario.name.c_str(), r + 1, reps);
      const Timed one = Run(scenario, seed, 1);
      const Timed many = Run(scenario, seed, threads);
      if (!SameTrajectory(one.result, many.result)) {
        std::fprintf(stderr, "ovpc_loop_bench: %s: the trajectory with %d threads differs from one thread's\n",
                     scenario.name.c_str(), threads);
        status = 1;
      }
      sim_s = one.result.sim_time_s;
      rtf1.push_back(sim_s / one.wall_s);
      rtfn.push_back(many.result.sim_time_s / many.wall_s);
      ratio.push_back(rtfn.back() / rtf1.back());
      cpu.push_back(1000.0 * one.cpu_s / sim_s);
      phys.push_back(one.result.physics_lidar.total_ms / sim_s);
      buffer.push_back(one.result.navigator.buffer.total_ms / sim_s);
      map.push_back(one.result.navigator.mapper.total_ms / sim_s);
      plan.push_back(one.result.navigator.planner.total_ms / sim_s);
      ray.push_back(RayCastAloneMsPerS(scenario, seed, one.result));
    }
    std::printf("%-14s %6.1f | %7.2f %7.2f %6.2f | %8.1f | %8.1f %7.1f %7.1f %8.1f | %9.1f\n", scenario.name.c_str(),
                sim_s, Median(rtf1), Median(rtfn), Median(ratio), Median(cpu), Median(phys), Median(buffer),
                Median(map), Median(plan), Median(ray));
    std::fflush(stdout);
  }
  std::printf("\nmedians of %d repetitions, seed %llu; RTF: simulated s per wall s, with 1 thread and with %d (the "
              "map-and-plan cycle beside the simulation for navigator.timing.latency_s); ms/s: per simulated second\n",
              reps, static_cast<unsigned long long>(seed), threads);
  return status;
}
