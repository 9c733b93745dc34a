#include "scheduler.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "ovpc/scenarios/family.h"
#include "ovpc/suite/output_folder.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

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
  job.result["extra"] = DrawJson(families, *job.draw);
  try {  // the run's own result.json stays in place unless the judged one is written whole
    WriteFileAtomic(fs::path(job.out_dir) / "result.json", job.result.dump(2) + "\n");
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
  MakeFresh(job.out_dir);
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
      : jobs_(jobs), o_(o), families_(families), self_(o.program),
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
      passed_ += Passed(job);
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
      if (!finished->settings.empty()) what += " [" + SettingsLabel(finished->settings) + "]";
      std::fprintf(stderr, "[%zu/%zu] %s seed %llu: %s (%zu passed, %zu failed so far)\n", done_, jobs_.size(), what.c_str(),
                   static_cast<unsigned long long>(finished->seed),
                   !finished->error.empty() ? "ERROR" : Passed(*finished) ? "pass" : "FAIL", passed_, failed);
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

}  // namespace

int RunJobs(std::vector<Job>& jobs, const Options& options, const std::vector<FamilyInput>& families) {
  return Scheduler(jobs, options, families).Run();
}

}  // namespace ovpc::suite
