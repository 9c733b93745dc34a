// `ovpc suite`: many scenario runs in parallel processes, a summary table, JUnit XML and JSON. Scenario
// families among the inputs are drawn into plain scenario files first, and their runs judged against
// their expectation.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "ovpc/navigation/navigator.h"
#include "ovpc/scenarios/family.h"
#include "ovpc/scenarios/scenario_yaml.h"
#include "output_folder.h"
#include "suite.h"

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
  long long samples = 6;
  std::uint64_t family_seed = 1;
  bool map_given = false;  // --map was given (even empty)
};

// A suite larger than this is split (`--first-seed`, fewer inputs): it is refused before anything
// is planned, so that a typo in --seeds cannot build a billion jobs.
constexpr std::size_t kMaxRuns = 100000;
constexpr std::size_t kMaxCombinations = 10000;

struct Sweep {
  std::string key;
  std::vector<std::string> values;
};

Sweep ParseSweep(const std::string& sweep) {
  const std::size_t eq = sweep.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= sweep.size()) {
    throw BadInput("--sweep '" + sweep + "' must be key=v1,v2,... (e.g. navigator.follower.lookahead_gain_s=0.3,0.5)");
  }
  Sweep out{sweep.substr(0, eq), {}};
  std::stringstream ss(sweep.substr(eq + 1));
  std::string v;
  while (std::getline(ss, v, ',')) {
    if (v.empty()) throw BadInput("--sweep '" + sweep + "' has an empty value");
    out.values.push_back(v);
  }
  return out;
}

// Cartesian product of the sweeps: each entry of the result is one list of key=value settings.
// Refused (exit 2, with the count) when there are more than kMaxCombinations.
std::vector<std::vector<std::string>> SweepCombinations(const std::vector<std::string>& sweep_args) {
  std::vector<Sweep> sweeps;
  double count = 1.0;
  for (const std::string& arg : sweep_args) {
    sweeps.push_back(ParseSweep(arg));
    count *= static_cast<double>(sweeps.back().values.size());
  }
  if (count > static_cast<double>(kMaxCombinations)) {
    char n[64];
    std::snprintf(n, sizeof(n), "%.0f", count);
    throw BadInput("--sweep: " + std::string(n) + " combinations; at most " + std::to_string(kMaxCombinations) +
                   " in one suite");
  }
  std::vector<std::vector<std::string>> combos = {{}};
  for (const Sweep& sweep : sweeps) {
    std::vector<std::vector<std::string>> next;
    for (const auto& combo : combos) {
      for (const auto& value : sweep.values) {
        next.push_back(combo);
        next.back().push_back(sweep.key + "=" + value);
      }
    }
    combos = std::move(next);
  }
  return combos;
}

// Starts `args` in a process group of its own (so that the suite can stop it and what it starts),
// writing its output to `log_path`; it is killed if the suite dies.
pid_t Spawn(const std::vector<std::string>& args, const std::string& log_path) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(errno));
  if (pid == 0) {  // the child: async-signal-safe calls only
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) _exit(127);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
    execv(argv[0], argv.data());
    _exit(127);
  }
  setpgid(pid, pid);  // also here: whichever of the two calls comes first makes the group
  return pid;
}

// The input files in order: every *.yaml of a folder (sorted), or the file itself. A file given
// twice (also through its folder) is refused: its runs would share their folders.
std::vector<std::string> CollectFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  std::map<std::string, std::string> seen;  // canonical path -> as given
  const auto add = [&](const std::string& file) {
    std::error_code ec;
    const std::string key = fs::weakly_canonical(file, ec).string();
    if (!seen.emplace(key, file).second) throw BadInput(file + ": given twice (also as " + seen[key] + ")");
    files.push_back(file);
  };
  for (const std::string& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<std::string> found;
      for (const auto& e : fs::directory_iterator(in)) {
        if (e.path().extension() == ".yaml") found.push_back(e.path().string());
      }
      std::sort(found.begin(), found.end());
      for (const auto& f : found) add(f);
    } else if (fs::is_regular_file(in)) {
      add(in);
    } else if (fs::exists(in)) {
      throw BadInput(in + ": not a regular file or a folder");
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
      s = scenarios::LoadScenario(file, {}, preset_);
    } catch (const scenarios::ScenarioError& e) {
      return AddMalformed(file, e.what());
    }
    if (Skipped(s) || !NameIsFolder(file, s.name)) return;
    const std::map<std::string, std::string> bad = BadSweepValues(file);
    for (std::size_t k = 0; k < combos_.size(); ++k) {
      if (Refused(file, s.name, combos_[k], bad)) continue;
      const std::string tag = FolderOf(file, s.name, k);
      AddSeeds(file, s.name, combos_[k], fs::path(o_.out) / tag, std::nullopt, MapOf(file, s, combos_[k]), s.time_limit_s);
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
  // The run folder of `name` with combination k: <name>[__<settings>], or <name>__combo_<k> when
  // that is too long for a file name; files sharing a scenario name get _2, _3, ...
  std::string FolderOf(const std::string& file, const std::string& name, std::size_t k) {
    std::string suffix = Tag(combos_[k], "__");
    if (name.size() + suffix.size() + 8 > output::kMaxComponentBytes) suffix = "__combo_" + std::to_string(k + 1);
    std::string tag = name + suffix;
    for (int n = 2; tag_files_.count(tag) && tag_files_[tag] != file; ++n) tag = name + "_" + std::to_string(n) + suffix;
    tag_files_[tag] = file;
    return tag;
  }
  bool Skipped(const scenarios::Scenario& s) const {
    bool skip = false;
    for (const auto& l : o_.skip_labels) skip = skip || std::count(s.labels.begin(), s.labels.end(), l) > 0;
    return skip;
  }
  // A name that cannot be a folder under --out is an error of its file (the loaders refuse such
  // names too; this keeps every run folder inside --out whatever they accept).
  bool NameIsFolder(const std::string& file, const std::string& name) {
    std::string why;
    if (output::IsSafeComponent(name, &why)) return true;
    AddMalformed(file, file + ": the name '" + name.substr(0, 80) + "' " + why);
    return false;
  }
  // Each sweep value checked once with this file (a sum of loads, not a product): "key=value" ->
  // the error it gives.
  std::map<std::string, std::string> BadSweepValues(const std::string& file) const {
    std::map<std::string, std::string> bad;
    if (combos_.size() == 1 && combos_.front().empty()) return bad;
    std::set<std::string> values;
    for (const auto& combo : combos_) values.insert(combo.begin(), combo.end());
    for (const std::string& kv : values) {
      try {
        scenarios::LoadScenario(file, {kv}, preset_);
      } catch (const scenarios::ScenarioError& e) {
        bad[kv] = e.what();
      }
    }
    return bad;
  }
  // A combination with a bad value is an error of its own; the other combinations run.
  bool Refused(const std::string& file, const std::string& name, const std::vector<std::string>& combo,
               const std::map<std::string, std::string>& bad) {
    for (const std::string& kv : combo) {
      auto it = bad.find(kv);
      if (it == bad.end()) continue;
      AddMalformed(file, it->second);
      jobs.back().scenario = name;
      jobs.back().settings = combo;
      return true;
    }
    return false;
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
  // The map backend a run of `s` with `combo` (and --map) uses; the file is read again only when
  // the combination sets the backend.
  std::string MapOf(const std::string& file, const scenarios::Scenario& s, const std::vector<std::string>& combo) const {
    if (o_.map_given) return o_.map;
    const bool sets_map = std::any_of(combo.begin(), combo.end(), [](const std::string& kv) { return kv.rfind("navigator.map=", 0) == 0; });
    if (!sets_map) return navigation::MapKindName(s.navigator.map);
    try {
      return navigation::MapKindName(scenarios::LoadScenario(file, combo, preset_).navigator.map);
    } catch (const scenarios::ScenarioError&) {
      return "?";  // the run reports the error
    }
  }
  void AddSeeds(const std::string& file, const std::string& name, const std::vector<std::string>& combo, const fs::path& dir,
                const std::optional<DrawRun>& draw, const std::string& map, double time_limit_s) {
    if (jobs.size() + static_cast<std::size_t>(o_.seeds) > kMaxRuns) {
      throw BadInput("more than " + std::to_string(kMaxRuns) + " runs in one suite (" + file +
                     " and the inputs before it); split it with --first-seed or fewer inputs");
    }
    for (int k = 0; k < o_.seeds; ++k) {
      const int seed = o_.first_seed + k;
      Job job;
      job.file = file;
      job.scenario = name;
      job.seed = static_cast<std::uint64_t>(seed);
      job.settings = combo;
      job.out_dir = (dir / ("seed_" + std::to_string(seed))).string();
      job.draw = draw;
      job.map = map;
      job.time_limit_s = time_limit_s;
      output::CheckClearable(job.out_dir);
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
    in.draws = scenarios::DrawFamily(in.family, {static_cast<std::size_t>(o_.samples), o_.family_seed}, preset_);
  } catch (const scenarios::ScenarioError& e) {
    return AddMalformed(file, e.what());
  }
  if (!NameIsFolder(file, in.family.name)) return;
  std::string folder = in.family.name;
  for (int k = 2; tag_files_.count(folder) && tag_files_[folder] != file; ++k) folder = in.family.name + "_" + std::to_string(k);
  tag_files_[folder] = file;
  in.dir = (fs::path(o_.out) / folder).string();
  output::MakeFresh(in.dir);
  in.files = scenarios::WriteDraws(in.family, in.draws, in.dir);
  const std::size_t first_job = jobs.size();
  for (std::size_t i = 0; i < in.draws.size(); ++i) {
    scenarios::Scenario s;
    try {
      s = scenarios::LoadScenario(in.files[i], {}, preset_);
    } catch (const scenarios::ScenarioError& e) {
      jobs.resize(first_job);
      return AddMalformed(in.files[i], e.what());
    }
    if (Skipped(s)) continue;
    const std::map<std::string, std::string> bad = BadSweepValues(in.files[i]);
    const fs::path draw_dir = fs::path(in.files[i]).parent_path();
    for (std::size_t k = 0; k < combos_.size(); ++k) {
      if (Refused(in.files[i], s.name, combos_[k], bad)) continue;
      std::string sub = Tag(combos_[k], "");
      if (sub.size() + 8 > output::kMaxComponentBytes) sub = "combo_" + std::to_string(k + 1);
      AddSeeds(in.files[i], s.name, combos_[k], draw_dir / sub, DrawRun{families.size(), i}, MapOf(in.files[i], s, combos_[k]),
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
  try {  // the run's own result.json stays in place unless the judged one is written whole
    output::WriteFileAtomic(fs::path(job.out_dir) / "result.json", job.result.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc suite: warning: %s (the run's own result.json is kept)\n", e.what());
  }
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
  output::MakeFresh(job.out_dir);
  std::vector<std::string> args = {self, "run", job.file, "--seed", std::to_string(job.seed), "--out", job.out_dir, "-q"};
  if (!o.preset.empty()) {
    args.push_back("--preset");
    args.push_back(o.preset);
  }
  for (const auto& kv : job.settings) {
    args.push_back("--set");
    args.push_back(kv);
  }
  if (o.map_given) {
    args.push_back("--map");
    args.push_back(o.map);
  }
  args.push_back("--threads");
  args.push_back(std::to_string(RunThreads(o)));
  job.pid = Spawn(args, (fs::path(job.out_dir) / "run.log").string());
}

// SIGINT, SIGTERM and SIGCHLD are taken by sigtimedwait from here on: a signal to the suite stops
// its runs and still gives the report.
sigset_t BlockSuiteSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGCHLD);
  sigprocmask(SIG_BLOCK, &set, nullptr);
  return set;
}

// The runs of a suite in flight: started up to --jobs at a time, the longest first, reaped as they
// end, and stopped with their process groups when the suite gets SIGINT or SIGTERM.
class Scheduler {
 public:
  Scheduler(std::vector<Job>& jobs, const Options& o, const std::vector<FamilyInput>& families)
      : jobs_(jobs), o_(o), families_(families), self_(fs::read_symlink("/proc/self/exe").string()),
        tty_(isatty(STDERR_FILENO) != 0) {
    // The runs with the longest time limits start first, so that a long run (mixed_long's 1,500 s)
    // does not start last and leave the other jobs' cores idle while it finishes. The reports
    // keep the input order.
    order_.resize(jobs.size());
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::stable_sort(order_.begin(), order_.end(),
                     [&](std::size_t a, std::size_t b) { return jobs[a].time_limit_s > jobs[b].time_limit_s; });
  }

  /// Runs every job; returns the signal that stopped the suite (0: none).
  int Run() {
    const sigset_t signals = BlockSuiteSignals();
    while (done_ < jobs_.size()) {
      if (stop_signal_ == 0) StartMore();
      if (by_pid_.empty()) break;
      siginfo_t info;
      const timespec tick{0, 200 * 1000 * 1000};
      const int sig = sigtimedwait(&signals, &info, &tick);
      if ((sig == SIGINT || sig == SIGTERM) && stop_signal_ == 0) Stop(sig);
      Reap();
      if (stop_signal_ != 0) KillIfSlow();
    }
    if (stop_signal_ != 0) CancelUnstarted();
    if (tty_) std::fprintf(stderr, "\n");
    return stop_signal_;
  }

 private:
  void StartMore() {
    while (by_pid_.size() < static_cast<std::size_t>(o_.jobs) && next_ < jobs_.size()) {
      Job& job = jobs_[order_[next_]];
      if (!job.error.empty() && job.pid == 0) {  // a malformed file: nothing to run
        ++next_;
        ++done_;
        continue;
      }
      try {
        Start(job, o_, self_);
        by_pid_[job.pid] = order_[next_];
      } catch (const std::exception& e) {  // its folder could not be made: an error of this run
        job.error = e.what();
        ++done_;
        Progress(&job);
      }
      ++next_;
      Progress(nullptr);
    }
  }
  void Stop(int sig) {
    stop_signal_ = sig;
    stop_time_ = std::chrono::steady_clock::now();
    std::fprintf(stderr, "%sovpc suite: %s: stopping %zu running runs; the report covers what finished\n", tty_ ? "\n" : "",
                 sig == SIGINT ? "SIGINT" : "SIGTERM", by_pid_.size());
    for (const auto& [pid, index] : by_pid_) kill(-pid, SIGTERM);
  }
  // A run that ignores SIGTERM for 10 s is killed.
  void KillIfSlow() {
    if (killed_ || std::chrono::steady_clock::now() - stop_time_ < std::chrono::seconds(10)) return;
    for (const auto& [pid, index] : by_pid_) kill(-pid, SIGKILL);
    killed_ = true;
  }
  void Reap() {
    int status = 0;
    pid_t pid = 0;
    while ((pid = waitpid(-1, &status, WNOHANG)) > 0) {
      auto it = by_pid_.find(pid);
      if (it == by_pid_.end()) continue;
      Job& job = jobs_[it->second];
      by_pid_.erase(it);
      Finish(job, status, families_);
      if (stop_signal_ != 0 && !job.error.empty()) job.error = "cancelled: the suite got " + SignalName() + " while it ran";
      passed_ += suite::Passed(job);
      ++done_;
      Progress(&job);
    }
  }
  void CancelUnstarted() {
    for (Job& job : jobs_) {
      if (job.pid == 0 && job.error.empty()) job.error = "cancelled: the suite got " + SignalName() + " before it started";
    }
  }
  std::string SignalName() const { return stop_signal_ == SIGINT ? "SIGINT" : "SIGTERM"; }
  // On a terminal one line, rewritten in place; in a log (CI) one line per finished run, naming it.
  void Progress(const Job* finished) const {
    const std::size_t running = by_pid_.size(), failed = done_ - passed_;
    if (tty_) {
      std::fprintf(stderr, "\r[%zu/%zu] done, %zu running, %zu passed, %zu failed   ", done_, jobs_.size(), running, passed_, failed);
    } else if (finished != nullptr) {
      std::string what = finished->scenario;
      if (!finished->settings.empty()) what += " [" + suite::SettingsLabel(finished->settings) + "]";
      std::fprintf(stderr, "[%zu/%zu] %s seed %llu: %s (%zu passed, %zu failed so far)\n", done_, jobs_.size(), what.c_str(),
                   static_cast<unsigned long long>(finished->seed),
                   !finished->error.empty() ? "ERROR" : suite::Passed(*finished) ? "pass" : "FAIL", passed_, failed);
    }
    std::fflush(stderr);
  }

  std::vector<Job>& jobs_;
  const Options& o_;
  const std::vector<FamilyInput>& families_;
  const std::string self_;
  const bool tty_;
  std::vector<std::size_t> order_;
  std::map<pid_t, std::size_t> by_pid_;  // running runs: pid -> job
  std::size_t next_ = 0, done_ = 0, passed_ = 0;
  int stop_signal_ = 0;
  bool killed_ = false;
  std::chrono::steady_clock::time_point stop_time_;
};

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

int RunSuite(const Options& o) {
  CheckOptions(o);
  const std::vector<std::string> files = CollectFiles(o.inputs);
  const auto combos = SweepCombinations(o.sweeps);
  if (files.size() * combos.size() * static_cast<std::size_t>(o.seeds) > kMaxRuns) {
    throw BadInput(std::to_string(files.size()) + " files x " + std::to_string(combos.size()) + " combinations x " +
                   std::to_string(o.seeds) + " seeds is more than " + std::to_string(kMaxRuns) + " runs in one suite");
  }
  const scenarios::Preset preset = LoadPresetOption(o);
  const output::FolderLock lock(o.out);  // one suite per folder
  Planner plan(o, combos, preset);
  for (const std::string& file : files) plan.AddFile(file);
  if (plan.jobs.empty()) throw BadInput("no scenario to run");
  const int stop_signal = Scheduler(plan.jobs, o, plan.families).Run();
  std::size_t passed = 0;
  try {
    passed = suite::WriteReport({plan.jobs, plan.families, o.out, o.seeds, !o.sweeps.empty(), combos});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc suite: %s\n", e.what());
    return stop_signal != 0 ? 128 + stop_signal : kExitFailure;
  }
  if (stop_signal != 0) return 128 + stop_signal;
  if (plan.malformed) return kExitBadInput;
  return passed == plan.jobs.size() ? kExitOk : kExitFailure;
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
  CLI::Option* map_opt = cmd->add_option("--map", o->map,
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
  return [o, map_opt]() {
    o->map_given = map_opt->count() > 0;
    return RunSuite(*o);
  };
}

}  // namespace ovpc::apps
