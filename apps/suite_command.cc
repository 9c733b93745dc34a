// `ovpc suite`: many scenario runs in parallel processes, a summary table, JUnit XML and JSON. Scenario
// families among the inputs are drawn into plain scenario files first, and their runs judged against
// their expectation.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "ovpc/backends/map_selection.h"
#include "ovpc/scenarios/family.h"
#include "ovpc/scenarios/scenario_yaml.h"
#include "suite.h"

extern char** environ;

namespace ovpc::apps {
namespace {

namespace fs = std::filesystem;
using suite::DrawRun;
using suite::FamilyInput;
using suite::Job;

struct Options {
  std::vector<std::string> inputs;
  int jobs = 2;
  int seeds = 1;
  int first_seed = 1;
  std::vector<std::string> sweeps;
  std::vector<std::string> skip_labels;
  std::string preset;
  std::string map;  // --map: every run's backend ("" = each scenario's configuration)
  int threads = 0;  // --threads: each run's (ovpc run --threads); 0: 2 unless --jobs fill the cores
  std::string out = "out/suite";
  std::size_t samples = 6;
  std::uint64_t family_seed = 1;
};

// Cartesian product of the sweeps: each entry of the result is one list of key=value settings.
std::vector<std::vector<std::string>> SweepCombinations(const std::vector<std::string>& sweeps) {
  std::vector<std::vector<std::string>> combos = {{}};
  for (const std::string& sweep : sweeps) {
    const std::size_t eq = sweep.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 >= sweep.size()) {
      throw BadInput("--sweep '" + sweep + "' must be key=v1,v2,... (e.g. navigator.follower.lookahead_gain_s=0.3,0.5)");
    }
    const std::string key = sweep.substr(0, eq);
    std::vector<std::string> values;
    std::stringstream ss(sweep.substr(eq + 1));
    std::string v;
    while (std::getline(ss, v, ',')) values.push_back(v);
    std::vector<std::vector<std::string>> next;
    for (const auto& combo : combos) {
      for (const auto& value : values) {
        auto c = combo;
        c.push_back(key + "=" + value);
        next.push_back(c);
      }
    }
    combos = next;
  }
  return combos;
}

pid_t Spawn(const std::vector<std::string>& args, const std::string& log_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(rc));
  return pid;
}

std::vector<std::string> CollectFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<std::string> found;
      for (const auto& e : fs::directory_iterator(in)) {
        if (e.path().extension() == ".yaml") found.push_back(e.path().string());
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in)) {
      files.push_back(in);
    } else {
      throw BadInput(in + ": no such scenario file or folder");
    }
  }
  return files;
}

// Turns the input files into jobs: each scenario file and each draw of a family, per sweep
// combination and seed, with a run folder of its own.
class Planner {
 public:
  Planner(const Options& o, std::vector<std::vector<std::string>> combos, scenarios::Preset preset)
      : o_(o), combos_(std::move(combos)), preset_(std::move(preset)) {}

  void AddFile(const std::string& file) {
    if (scenarios::IsFamilyFile(file)) return AddFamily(file);
    scenarios::Scenario s;
    try {
      s = scenarios::LoadScenario(file, combos_.front(), preset_);
    } catch (const scenarios::ScenarioError& e) {
      return AddMalformed(file, e.what());
    }
    if (Skipped(s)) return;
    for (const auto& combo : combos_) {
      std::string tag = s.name + Tag(combo, "__");
      // Two files with one scenario name get folders of their own.
      const std::string suffix = tag.substr(s.name.size());
      for (int k = 2; tag_files_.count(tag) && tag_files_[tag] != file; ++k) tag = s.name + "_" + std::to_string(k) + suffix;
      tag_files_[tag] = file;
      AddSeeds(file, s.name, combo, fs::path(o_.out) / tag, std::nullopt, MapOf(file, combo), s.time_limit_s);
    }
  }

  std::vector<Job> jobs;
  std::vector<FamilyInput> families;
  bool malformed = false;

 private:
  static std::string Tag(const std::vector<std::string>& combo, const std::string& first) {
    std::string tag;
    for (const auto& kv : combo) tag += (tag.empty() ? first : "__") + kv;
    std::replace(tag.begin(), tag.end(), '/', '_');
    return tag;
  }
  bool Skipped(const scenarios::Scenario& s) const {
    bool skip = false;
    for (const auto& l : o_.skip_labels) skip = skip || std::count(s.labels.begin(), s.labels.end(), l) > 0;
    return skip;
  }
  // Reported as an error of this file; the other files still run.
  void AddMalformed(const std::string& file, const std::string& error) {
    std::fprintf(stderr, "ovpc suite: %s\n", error.c_str());
    Job job;
    job.file = file;
    job.scenario = fs::path(file).stem().string();
    job.exit_code = kExitBadInput;
    job.error = error;
    jobs.push_back(job);
    malformed = true;
  }
  // The map backend a run of `file` with `combo` (and --map) uses.
  std::string MapOf(const std::string& file, const std::vector<std::string>& combo) const {
    std::vector<std::string> settings = combo;
    if (!o_.map.empty()) settings.push_back(MapSetting(o_.map));
    try {
      return backends::MapKindName(scenarios::LoadScenario(file, settings, preset_).map_backends.map);
    } catch (const scenarios::ScenarioError&) {
      return "?";  // the run reports the error
    }
  }
  void AddSeeds(const std::string& file, const std::string& name, const std::vector<std::string>& combo, const fs::path& dir,
                const std::optional<DrawRun>& draw, const std::string& map, double time_limit_s) {
    for (int seed = o_.first_seed; seed < o_.first_seed + o_.seeds; ++seed) {
      Job job;
      job.file = file;
      job.scenario = name;
      job.seed = static_cast<std::uint64_t>(seed);
      job.settings = combo;
      job.out_dir = (dir / ("seed_" + std::to_string(seed))).string();
      job.draw = draw;
      job.map = map;
      job.time_limit_s = time_limit_s;
      jobs.push_back(job);
    }
  }
  void AddFamily(const std::string& file);

  const Options& o_;
  std::vector<std::vector<std::string>> combos_;
  scenarios::Preset preset_;
  std::map<std::string, std::string> tag_files_;  // run folder name -> the file that has it
};

// A family: drawn into OUT/<family>/draw_<iii>/scenario.yaml (a fresh folder), each draw then run like
// a scenario file into draw_<iii>[/<settings>]/seed_<k>.
void Planner::AddFamily(const std::string& file) {
  FamilyInput in;
  try {
    in.family = scenarios::LoadFamily(file);
    in.draws = scenarios::DrawFamily(in.family, {o_.samples, o_.family_seed}, preset_);
  } catch (const scenarios::ScenarioError& e) {
    return AddMalformed(file, e.what());
  }
  std::string folder = in.family.name;
  std::replace(folder.begin(), folder.end(), '/', '_');
  for (int k = 2; tag_files_.count(folder) && tag_files_[folder] != file; ++k) folder = in.family.name + "_" + std::to_string(k);
  tag_files_[folder] = file;
  in.dir = (fs::path(o_.out) / folder).string();
  std::error_code ec;
  fs::remove_all(in.dir, ec);
  in.files = scenarios::WriteDraws(in.family, in.draws, in.dir);
  const std::size_t first_job = jobs.size();
  for (std::size_t i = 0; i < in.draws.size(); ++i) {
    scenarios::Scenario s;
    try {
      s = scenarios::LoadScenario(in.files[i], combos_.front(), preset_);
    } catch (const scenarios::ScenarioError& e) {  // e.g. a --sweep key the scenario does not have
      jobs.resize(first_job);
      return AddMalformed(in.files[i], e.what());
    }
    if (Skipped(s)) continue;
    const fs::path draw_dir = fs::path(in.files[i]).parent_path();
    for (const auto& combo : combos_) {
      AddSeeds(in.files[i], s.name, combo, draw_dir / Tag(combo, ""), DrawRun{families.size(), i}, MapOf(in.files[i], combo),
               s.time_limit_s);
    }
  }
  families.push_back(std::move(in));
}

scenarios::RunOutcome OutcomeFromJson(const nlohmann::json& r) {
  std::vector<scenarios::CriterionResult> criteria;
  if (r.contains("criteria")) {
    for (const auto& c : r["criteria"]) {
      criteria.push_back({c.value("name", std::string()), c.value("expected", std::string()), c.value("actual", std::string()),
                          c.value("passed", false)});
    }
  }
  return scenarios::OutcomeOf(r.value("passed", false), r.value("collision_steps", std::size_t{0}), criteria);
}

// A family run: judged against its expectation, which result.json's `extra` records.
void JudgeDraw(Job& job, const std::vector<FamilyInput>& families) {
  const scenarios::Draw& d = families[job.draw->family].draws[job.draw->draw];
  job.draw->verdict = !job.error.empty() ? scenarios::Verdict::kError : scenarios::Judge(d.expectation, OutcomeFromJson(job.result));
  if (!job.error.empty()) return;
  job.result["extra"] = suite::DrawJson(families, *job.draw);
  const fs::path dir(job.out_dir);
  std::ofstream(dir / "result.json.part") << job.result.dump(2) << "\n";
  std::error_code ec;
  fs::rename(dir / "result.json.part", dir / "result.json", ec);
}

// A run that ended: its result, or why there is none.
void Finish(Job& job, int status, const std::vector<FamilyInput>& families) {
  job.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  // `ovpc run` writes result.json last, by renaming a complete file: no file, no result.
  std::ifstream in(fs::path(job.out_dir) / "result.json");
  if (in) {
    try {
      in >> job.result;
    } catch (const std::exception&) {
      job.result = nlohmann::json::object();
    }
  }
  if (!job.result.is_object()) job.result = nlohmann::json::object();
  const std::string log = " (see " + (fs::path(job.out_dir) / "run.log").string() + ")";
  if (WIFSIGNALED(status)) {
    job.error = "killed by signal " + std::to_string(WTERMSIG(status)) + log;
  } else if (job.exit_code != 0 && job.exit_code != 1) {
    job.error = "exit code " + std::to_string(job.exit_code) + log;
  } else if (job.result.empty()) {
    job.error = "no result.json (exit code " + std::to_string(job.exit_code) + ")" + log;
  }
  if (!job.error.empty()) job.result = nlohmann::json::object();
  if (job.draw) JudgeDraw(job, families);
}

// Each run's threads: as asked, or 2 while the runs at a time leave a core for each second thread.
int RunThreads(const Options& o) {
  if (o.threads > 0) return o.threads;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  return 2 * static_cast<unsigned>(o.jobs) <= cores ? 2 : 1;
}

void Start(Job& job, const Options& o, const std::string& self) {
  // A fresh folder: a result left by an earlier suite is never taken for this run's.
  std::error_code ec;
  fs::remove_all(job.out_dir, ec);
  fs::create_directories(job.out_dir);
  std::vector<std::string> args = {self, "run", job.file, "--seed", std::to_string(job.seed), "--out", job.out_dir, "-q"};
  if (!o.preset.empty()) {
    args.push_back("--preset");
    args.push_back(o.preset);
  }
  for (const auto& kv : job.settings) {
    args.push_back("--set");
    args.push_back(kv);
  }
  if (!o.map.empty()) {
    args.push_back("--map");
    args.push_back(o.map);
  }
  args.push_back("--threads");
  args.push_back(std::to_string(RunThreads(o)));
  job.pid = Spawn(args, (fs::path(job.out_dir) / "run.log").string());
}

void RunAll(std::vector<Job>& jobs, const Options& o, const std::vector<FamilyInput>& families) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::size_t next = 0, done = 0, passed = 0, running = 0;
  const auto not_run = [](const Job& job) { return !job.error.empty() && job.pid == 0; };
  std::map<pid_t, std::size_t> by_pid;
  // On a terminal one line, rewritten in place; in a log (CI) one line per finished run, naming it.
  const bool tty = isatty(STDERR_FILENO) != 0;
  auto progress = [&](const Job* finished) {
    if (tty) {
      std::fprintf(stderr, "\r[%zu/%zu] done, %zu running, %zu passed, %zu failed   ", done, jobs.size(), running,
                   passed, done - passed);
    } else if (finished != nullptr) {
      std::string what = finished->scenario;
      if (!finished->settings.empty()) what += " [" + suite::SettingsLabel(finished->settings) + "]";
      std::fprintf(stderr, "[%zu/%zu] %s seed %llu: %s (%zu passed, %zu failed so far)\n", done, jobs.size(),
                   what.c_str(), static_cast<unsigned long long>(finished->seed),
                   !finished->error.empty() ? "ERROR" : suite::Passed(*finished) ? "pass" : "FAIL", passed,
                   done - passed);
    }
    std::fflush(stderr);
  };
  // The runs with the longest time limits start first, so that a long run (mixed_long's 1,500 s)
  // does not start last and leave the other jobs' cores idle while it finishes. The reports keep
  // the input order.
  std::vector<std::size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return jobs[a].time_limit_s > jobs[b].time_limit_s; });
  while (done < jobs.size()) {
    while (running < static_cast<std::size_t>(o.jobs) && next < jobs.size()) {
      Job& job = jobs[order[next]];
      if (not_run(job)) {  // a malformed file: nothing to run
        ++next;
        ++done;
        continue;
      }
      Start(job, o, self);
      by_pid[job.pid] = order[next++];
      ++running;
      progress(nullptr);
    }
    if (running == 0) break;  // every remaining job was a malformed file
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) break;
    auto it = by_pid.find(pid);
    if (it == by_pid.end()) continue;
    Job& job = jobs[it->second];
    Finish(job, status, families);
    passed += suite::Passed(job);
    ++done;
    --running;
    progress(&job);
  }
  if (tty) std::fprintf(stderr, "\n");
}

}  // namespace

Runner RegisterSuite(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("suite", "Run many scenarios (and seeds, parameter sweeps, scenario families) in parallel processes");
  cmd->footer(
      "Each run is `ovpc run` in its own process, writing to OUT/<scenario>[__<settings>]/seed_<k>; the runs with\n"
      "the longest time limits start first, and the reports keep the order of the inputs. Prints a\n"
      "summary table, and writes OUT/junit.xml and OUT/summary.json. A malformed scenario file, a run killed or\n"
      "crashed, or one that left no result.json is an error of that run (JUnit <error>); the others run and are\n"
      "reported. A scenario family (a file with `parameters:`) is drawn into OUT/<family>/draw_<iii>/scenario.yaml\n"
      "(--samples draws per grid point, from --family-seed), each draw run like a scenario into\n"
      "draw_<iii>/seed_<k>, judged against its expectation, and tabulated per parameter (OUT/<family>/pass_rate.csv,\n"
      "pass_rate_<parameter>.svg). Exit codes: 0 every run passed (a family run: its expectation held), 1 some run\n"
      "failed or had an error, 2 bad input (a malformed scenario or family file among them).");
  cmd->add_option("inputs", o->inputs, "Scenario or family folders (every *.yaml in them) or files")->required();
  cmd->add_option("-j,--jobs", o->jobs, "Runs at the same time")->capture_default_str();
  cmd->add_option("--seeds", o->seeds, "K seeds for every scenario: F..F+K-1 (F = --first-seed)")->capture_default_str();
  cmd->add_option("--first-seed", o->first_seed, "First seed F (e.g. 4 with --seeds 3: seeds 4, 5, 6)")->capture_default_str();
  cmd->add_option("--sweep", o->sweeps, "key=v1,v2,...: run every combination of values (repeatable)");
  cmd->add_option("--skip-label", o->skip_labels, "Leave out scenarios with this label (e.g. long)");
  cmd->add_option("--preset", o->preset, "The robot's configuration for every run (default: the built-in one)");
  cmd->add_option("--map", o->map,
                  "The map backend of every run: ovpc, octomap or elevation (default: each run's configuration; "
                  "--sweep navigator.map=ovpc,octomap,elevation compares them)");
  cmd->add_option("--threads", o->threads,
                  "Threads of each run (ovpc run --threads; default: 2 when twice --jobs fits in the cores, "
                  "else 1)")
      ->check(CLI::Range(1, 2));
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_option("--samples", o->samples, "Families: random draws per grid point")->capture_default_str();
  cmd->add_option("--seed,--family-seed", o->family_seed, "Families: the seed the draws are made from (not the runs' seeds)")
      ->capture_default_str();
  return [o]() {
    if (o->jobs < 1) throw BadInput("--jobs must be >= 1");
    if (o->seeds < 1) throw BadInput("--seeds must be >= 1");
    if (o->first_seed < 0) throw BadInput("--first-seed must be >= 0");
    if (o->samples < 1) throw BadInput("--samples must be >= 1");
    if (!o->map.empty()) {
      MapSetting(o->map);  // a bad name is bad input
      for (const std::string& sweep : o->sweeps) {
        if (sweep.rfind("navigator.map=", 0) == 0) throw BadInput("--map and --sweep navigator.map=... both choose the map backend; give one");
      }
    }
    const std::vector<std::string> files = CollectFiles(o->inputs);
    const auto combos = SweepCombinations(o->sweeps);
    scenarios::Preset preset;
    try {
      preset = o->preset.empty() ? scenarios::DefaultPreset() : scenarios::LoadPreset(o->preset);
    } catch (const scenarios::ScenarioError& e) {
      throw BadInput(e.what());
    }
    Planner plan(*o, combos, preset);
    for (const std::string& file : files) plan.AddFile(file);
    if (plan.jobs.empty()) throw BadInput("no scenario to run");
    RunAll(plan.jobs, *o, plan.families);
    const std::size_t passed = suite::WriteReport({plan.jobs, plan.families, o->out, o->seeds, !o->sweeps.empty(), combos});
    if (plan.malformed) return kExitBadInput;
    return passed == plan.jobs.size() ? kExitOk : kExitFailure;
  };
}

}  // namespace ovpc::apps
