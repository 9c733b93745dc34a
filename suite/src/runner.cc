// A suite: many scenario runs in parallel processes, a summary table, JUnit XML and JSON. Scenario
// families among the inputs are drawn into plain scenario files first, and their runs judged against
// their expectation.
#include "ovpc/suite/runner.h"

#include <climits>
#include <cstdio>
#include <string>
#include <vector>

#include "ovpc/scenarios/scenario_yaml.h"
#include "ovpc/suite/output_folder.h"
#include "ovpc/suite/report.h"
#include "plan.h"
#include "scheduler.h"

namespace ovpc::suite {
namespace {

void CheckOptions(const Options& o) {
  if (o.jobs < 1 || o.jobs > 1024) throw BadInput("--jobs must be 1-1024, got " + std::to_string(o.jobs));
  if (o.seeds < 1 || static_cast<std::size_t>(o.seeds) > kMaxRuns) {
    throw BadInput("--seeds must be 1-" + std::to_string(kMaxRuns) + ", got " + std::to_string(o.seeds));
  }
  if (o.first_seed < 0) throw BadInput("--first-seed must be >= 0");
  if (static_cast<long long>(o.first_seed) + o.seeds - 1 > INT_MAX) {
    throw BadInput("--first-seed " + std::to_string(o.first_seed) + " with --seeds " + std::to_string(o.seeds) +
                   " goes past the largest seed, " + std::to_string(INT_MAX));
  }
  if (o.samples < 1 || o.samples > 100000) throw BadInput("--samples must be 1-100000, got " + std::to_string(o.samples));
  if (o.map_given) {
    MapSetting(o.map);  // a bad name is bad input
    for (const std::string& sweep : o.sweeps) {
      if (sweep.rfind("navigator.map=", 0) == 0) throw BadInput("--map and --sweep navigator.map=... both choose the map backend; give one");
    }
  }
}

scenarios::Preset LoadPresetOption(const Options& o) {
  try {
    return o.preset.empty() ? scenarios::DefaultPreset() : scenarios::LoadPreset(o.preset);
  } catch (const scenarios::ScenarioError& e) {
    throw BadInput(e.what());
  }
}

}  // namespace

std::string MapSetting(const std::string& name) {
  if (name != "ovpc" && name != "octomap" && name != "elevation") {
    throw BadInput("--map must be ovpc, octomap or elevation, got '" + name + "'");
  }
  return "navigator.map=" + name;
}

int RunSuite(const Options& o) {
  CheckOptions(o);
  const std::vector<std::string> files = CollectFiles(o.inputs);
  const auto combos = SweepCombinations(o.sweeps);
  if (files.size() * combos.size() * static_cast<std::size_t>(o.seeds) > kMaxRuns) {
    throw BadInput(std::to_string(files.size()) + " files x " + std::to_string(combos.size()) + " combinations x " +
                   std::to_string(o.seeds) + " seeds is more than " + std::to_string(kMaxRuns) + " runs in one suite");
  }
  const scenarios::Preset preset = LoadPresetOption(o);
  const FolderLock lock(o.out);  // one suite per folder
  Planner plan(o, combos, preset);
  for (const std::string& file : files) plan.AddFile(file);
  if (plan.jobs.empty()) throw BadInput("no scenario to run");
  const int stop_signal = RunJobs(plan.jobs, o, plan.families);
  std::size_t passed = 0;
  try {
    passed = WriteReport({plan.jobs, plan.families, o.out, o.seeds, !o.sweeps.empty(), combos});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc suite: %s\n", e.what());
    return stop_signal != 0 ? 128 + stop_signal : kExitFailure;
  }
  if (stop_signal != 0) return 128 + stop_signal;
  if (plan.malformed) return kExitBadInput;
  return passed == plan.jobs.size() ? kExitOk : kExitFailure;
}

}  // namespace ovpc::suite