// `ovpc run`: one closed-loop scenario run, scored.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ovpc/suite/output_folder.h"
#include "ovpc/scenarios/closed_loop.h"
#include "ovpc/scenarios/recorder.h"
#include "ovpc/scenarios/report.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::apps {
namespace {

struct RunOptions {
  std::string scenario;
  std::uint64_t seed = 0;
  CLI::Option* seed_opt = nullptr;
  std::string out = "out/run";
  std::vector<std::string> settings;
  std::string preset;
  std::string map;
  bool map_given = false;
  bool print_config = false;
  bool frames = false;
  bool mcap = false;
  bool quiet = false;
  int threads = 2;
};

int RunScenario(const RunOptions& o) {
  std::vector<std::string> settings = o.settings;
  if (o.map_given) settings.push_back(MapSetting(o.map));
  if (o.mcap) settings.emplace_back("record.mcap=true");
  scenarios::Scenario scenario;
  try {
    const scenarios::Preset preset = o.preset.empty() ? scenarios::DefaultPreset() : scenarios::LoadPreset(o.preset);
    scenario = scenarios::LoadScenario(o.scenario, settings, preset);
  } catch (const scenarios::ScenarioError& e) {
    throw BadInput(e.what());
  }
  const std::uint64_t seed = o.seed_opt->count() ? o.seed : scenario.seed;
  if (o.print_config) {
    std::cout << scenarios::FormatRunConfig(scenario);
    return kExitOk;
  }
  scenarios::RunOptions options;
  options.out_dir = o.out;
  options.frames = o.frames;
  options.progress = !o.quiet;
  options.threads = o.threads;
  // The folder is made, writable and ours alone before the simulation starts.
  const suite::FolderLock lock(o.out);
  const std::filesystem::path dir(o.out);
  // result.json marks a complete run: gone while the run goes on, written last by a rename.
  std::filesystem::remove(dir / "result.json");
  const scenarios::RunResult result = scenarios::RunClosedLoop(scenario, seed, options);
  std::cout << scenarios::FormatScorecard(scenario, result);
  // The trajectory and result.json are the run's result: a failed write ends the run without a
  // result.json (the suite reports it as an error). The plan and cycle logs and the picture are
  // diagnostics: a failed write is a warning.
  scenarios::WriteTrajectoryCsv(result, (dir / "trajectory.csv").string());
  const auto diagnostic = [](const auto& write) {
    try {
      write();
    } catch (const std::exception& e) {
      std::cerr << "ovpc: warning: " << e.what() << "\n";
    }
  };
  diagnostic([&] { scenarios::WritePlansCsv(result, (dir / "plans.csv").string()); });
  diagnostic([&] { scenarios::WriteCyclesCsv(result, (dir / "cycles.csv").string()); });
  diagnostic([&] { scenarios::WriteTopdownPng(scenario, result, (dir / "topdown.png").string()); });
  scenarios::WriteResultJson(scenario, result, (dir / "result.json.part").string());
  std::filesystem::rename(dir / "result.json.part", dir / "result.json");
  std::cout << "wrote " << (dir / "result.json").string() << ", trajectory.csv, plans.csv, cycles.csv, topdown.png";
  if (std::filesystem::exists(dir / scenarios::kRunLogName)) std::cout << ", " << scenarios::kRunLogName;
  if (!result.files.empty()) std::cout << " and " << result.files.size() << " snapshot/frame files";
  std::cout << "\n";
  return result.passed ? kExitOk : kExitFailure;
}

}  // namespace

Runner RegisterRun(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run one scenario in closed loop (headless) and score it");
  cmd->footer(
      "Writes DIR/result.json, DIR/trajectory.csv, DIR/plans.csv, DIR/cycles.csv, DIR/topdown.png and DIR/mesh_*.ply (and frame_*.png with\n"
      "--frames, run.mcap with --mcap). Exit codes: 0 every criterion passed, 1 a criterion failed, 2 bad input (unreadable or\n"
      "malformed scenario, unknown key, bad --set or --map).");
  cmd->add_option("scenario", o->scenario, "Scenario file (scenarios/*.yaml)")->required();
  o->seed_opt = cmd->add_option("--seed", o->seed, "Seed for every random source (default: the scenario's)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str()->check(NotEmpty());
  cmd->add_option("--set", o->settings,
                  "Override a scenario value: dotted.key=value (repeatable), e.g. navigator.ovpc.mapper.ghpr.gamma=-0.02");
  cmd->add_option("--preset", o->preset,
                  "The robot's configuration to start from (default: the built-in navigation/presets/default.yaml)")
      ->check(NotEmpty());
  CLI::Option* map_opt = cmd->add_option("--map", o->map,
                  "The map backend: ovpc, octomap or elevation (sets navigator.map after every --set; default: the "
                  "configuration's, ovpc)");
  cmd->add_flag("--print-config", o->print_config,
                "Print the run's effective configuration (navigator and record, preset form) and exit");
  cmd->add_flag("--frames", o->frames, "Render chase-camera PNG frames (EGL, CPU; slow)");
  cmd->add_flag("--mcap", o->mcap,
                "Write DIR/run.mcap, a run log that Foxglove opens (sets record.mcap=true; docs/RUN_LOGS.md)");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress line");
  cmd->add_option("--threads", o->threads,
                  "Threads for the run: with 2 the robot maps and plans beside the simulation for "
                  "navigator.timing.latency_s (0.1 s in the preset) and the ray cast is shared; the trajectory is the same "
                  "with 1 or 2")
      ->check(CLI::Range(1, 2))
      ->capture_default_str();
  return [o, map_opt]() {
    o->map_given = map_opt->count() > 0;
    return RunScenario(*o);
  };
}

}  // namespace ovpc::apps
