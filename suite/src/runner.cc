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
#include "results.h"
#include "scheduler.h"
#include "shard.h"

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
  if (o.shards < 1 || o.shards > kMaxShards || o.shard < 1 || o.shard > o.shards) {
    throw BadInput("--shard must be K/N with 1 <= K <= N <= " + std::to_string(kMaxShards));
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

// What the suite was asked to run, and by which build.
SuiteRecord Record(const Options& o, const std::vector<std::vector<std::string>>& combos, const scenarios::Preset& preset) {
  SuiteRecord s;
  s.inputs = o.inputs;
  s.seeds = o.seeds;
  s.first_seed = o.first_seed;
  s.sweeps = o.sweeps;
  s.combinations = combos;
  s.skip_labels = o.skip_labels;
  s.map = o.map_given ? o.map : "";
  s.samples = o.samples;
  s.family_seed = o.family_seed;
  s.preset_file = o.preset;
  s.preset_hash = ContentHash(preset.yaml);
  s.build = BuildId();
  s.shard = o.shard;
  s.shards = o.shards;
  return s;
}

// The planned runs numbered in order, fingerprinted, and this shard's part of them kept.
void TakeShard(std::vector<Job>& planned, const std::vector<std::string>& files, const Options& o, SuiteResults& results) {
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    planned[i].index = i;
    ids.push_back(RunIdentity(planned[i], results.families, o.out));
  }
  results.suite.planned = planned.size();
  results.suite.plan_fingerprint = PlanFingerprint(files, results.families, planned, ids);
  const std::vector<int> shard_of = AssignShards(planned, ids, o.shards);
  for (std::size_t i = 0; i < planned.size(); ++i) {
    if (shard_of[i] == o.shard) results.jobs.push_back(std::move(planned[i]));
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
  SuiteResults results{Record(o, combos, preset), {}, std::move(plan.families), std::move(plan.skipped)};
  results.suite.malformed = plan.malformed;
  TakeShard(plan.jobs, files, o, results);
  const int stop_signal = RunJobs(results.jobs, o, results.families);
  results.suite.stop_signal = stop_signal;
  std::size_t passed = 0;
  try {
    passed = WriteReport(results, o.out, {o.junit_absolute_paths});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc suite: %s\n", e.what());
    return stop_signal != 0 ? 128 + stop_signal : kExitFailure;
  }
  if (stop_signal != 0) return 128 + stop_signal;
  if (plan.malformed) return kExitBadInput;
  return passed == results.jobs.size() ? kExitOk : kExitFailure;
}

}  // namespace ovpc::suite