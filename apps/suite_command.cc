// `ovpc suite`: many scenario runs in parallel processes, a summary table, JUnit XML and JSON.
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
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "ovpc/scenarios/scenario_yaml.h"

extern char** environ;

namespace ovpc::apps {
namespace {

namespace fs = std::filesystem;

struct Job {
  std::string file;
  std::string scenario;
  std::uint64_t seed = 1;
  std::vector<std::string> settings;  // key=value
  std::string out_dir;
  pid_t pid = 0;
  int exit_code = -1;
  nlohmann::json result = nlohmann::json::object();
  std::string error;  // why there is no result: a malformed file, a killed or crashed run, ...
};

std::string SettingsLabel(const std::vector<std::string>& settings) {
  std::string s;
  for (const auto& kv : settings) s += (s.empty() ? "" : " ") + kv;
  return s;
}

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

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

}  // namespace

Runner RegisterSuite(CLI::App& app) {
  struct Options {
    std::vector<std::string> inputs;
    int jobs = 2;
    int seeds = 1;
    int first_seed = 1;
    std::vector<std::string> sweeps;
    std::vector<std::string> skip_labels;
    std::string preset;
    std::string out = "out/suite";
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("suite", "Run many scenarios (and seeds, and parameter sweeps) in parallel processes");
  cmd->footer(
      "Each run is `ovpc run` in its own process, writing to OUT/<scenario>[__<settings>]/seed_<k>. Prints a\n"
      "summary table, and writes OUT/junit.xml and OUT/summary.json. A malformed scenario file, a run killed or\n"
      "crashed, or one that left no result.json is an error of that run (JUnit <error>); the others run and are\n"
      "reported. Exit codes: 0 every run passed, 1 some run failed or had an error, 2 bad input (a malformed\n"
      "scenario file among them).");
  cmd->add_option("inputs", o->inputs, "Scenario folders (every *.yaml in them) or files")->required();
  cmd->add_option("-j,--jobs", o->jobs, "Runs at the same time")->capture_default_str();
  cmd->add_option("--seeds", o->seeds, "K seeds for every scenario: F..F+K-1 (F = --first-seed)")->capture_default_str();
  cmd->add_option("--first-seed", o->first_seed, "First seed F (e.g. 4 with --seeds 3: seeds 4, 5, 6)")->capture_default_str();
  cmd->add_option("--sweep", o->sweeps, "key=v1,v2,...: run every combination of values (repeatable)");
  cmd->add_option("--skip-label", o->skip_labels, "Leave out scenarios with this label (e.g. long)");
  cmd->add_option("--preset", o->preset, "The robot's configuration for every run (default: the built-in one)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  return [o]() {
    if (o->jobs < 1) throw BadInput("--jobs must be >= 1");
    if (o->seeds < 1) throw BadInput("--seeds must be >= 1");
    if (o->first_seed < 0) throw BadInput("--first-seed must be >= 0");
    std::vector<std::string> files;
    for (const std::string& in : o->inputs) {
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
    const auto combos = SweepCombinations(o->sweeps);
    scenarios::Preset preset;
    try {
      preset = o->preset.empty() ? scenarios::DefaultPreset() : scenarios::LoadPreset(o->preset);
    } catch (const scenarios::ScenarioError& e) {
      throw BadInput(e.what());
    }
    std::vector<Job> jobs;
    std::map<std::string, std::string> tag_files;  // run folder name -> the file that has it
    bool malformed = false;
    for (const std::string& file : files) {
      scenarios::Scenario s;
      try {
        s = scenarios::LoadScenario(file, combos.front(), preset);
      } catch (const scenarios::ScenarioError& e) {
        // Reported as an error of this file; the other files still run.
        std::fprintf(stderr, "ovpc suite: %s\n", e.what());
        Job job;
        job.file = file;
        job.scenario = fs::path(file).stem().string();
        job.exit_code = kExitBadInput;
        job.error = e.what();
        jobs.push_back(job);
        malformed = true;
        continue;
      }
      bool skip = false;
      for (const auto& l : o->skip_labels) skip = skip || std::count(s.labels.begin(), s.labels.end(), l) > 0;
      if (skip) continue;
      for (const auto& combo : combos) {
        std::string tag = s.name;
        for (const auto& kv : combo) tag += "__" + kv;
        std::replace(tag.begin(), tag.end(), '/', '_');
        // Two files with one scenario name get folders of their own.
        const std::string suffix = tag.substr(s.name.size());
        for (int k = 2; tag_files.count(tag) && tag_files[tag] != file; ++k) tag = s.name + "_" + std::to_string(k) + suffix;
        tag_files[tag] = file;
        for (int seed = o->first_seed; seed < o->first_seed + o->seeds; ++seed) {
          Job job;
          job.file = file;
          job.scenario = s.name;
          job.seed = static_cast<std::uint64_t>(seed);
          job.settings = combo;
          job.out_dir = (fs::path(o->out) / tag / ("seed_" + std::to_string(seed))).string();
          jobs.push_back(job);
        }
      }
    }
    if (jobs.empty()) throw BadInput("no scenario to run");

    const std::string self = fs::read_symlink("/proc/self/exe").string();
    std::size_t next = 0, done = 0, passed = 0, running = 0;
    const auto not_run = [](const Job& job) { return !job.error.empty() && job.pid == 0; };
    std::map<pid_t, std::size_t> by_pid;
    auto progress = [&]() {
      std::fprintf(stderr, "\r[%zu/%zu] done, %zu running, %zu passed, %zu failed   ", done, jobs.size(), running, passed,
                   done - passed);
      std::fflush(stderr);
    };
    while (done < jobs.size()) {
      while (running < static_cast<std::size_t>(o->jobs) && next < jobs.size()) {
        Job& job = jobs[next];
        if (not_run(job)) {  // a malformed file: nothing to run
          ++next;
          ++done;
          continue;
        }
        // A fresh folder: a result left by an earlier suite is never taken for this run's.
        std::error_code ec;
        fs::remove_all(job.out_dir, ec);
        fs::create_directories(job.out_dir);
        std::vector<std::string> args = {self, "run", job.file, "--seed", std::to_string(job.seed), "--out", job.out_dir, "-q"};
        if (!o->preset.empty()) {
          args.push_back("--preset");
          args.push_back(o->preset);
        }
        for (const auto& kv : job.settings) {
          args.push_back("--set");
          args.push_back(kv);
        }
        job.pid = Spawn(args, (fs::path(job.out_dir) / "run.log").string());
        by_pid[job.pid] = next++;
        ++running;
        progress();
      }
      if (running == 0) break;  // every remaining job was a malformed file
      int status = 0;
      const pid_t pid = waitpid(-1, &status, 0);
      if (pid < 0) break;
      auto it = by_pid.find(pid);
      if (it == by_pid.end()) continue;
      Job& job = jobs[it->second];
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
      passed += job.exit_code == 0 && job.error.empty();
      ++done;
      --running;
      progress();
    }
    std::fprintf(stderr, "\n");

    // Summary table, JUnit XML and JSON.
    std::printf("%-22s %-5s %-34s %-6s %9s %9s %7s  %s\n", "scenario", "seed", "settings", "result", "sim [s]", "dist [m]",
                "RTF", "end");
    nlohmann::json summary = nlohmann::json::array();
    std::ostringstream cases;
    double total_wall = 0.0;
    std::size_t errors = 0;
    for (const Job& job : jobs) {
      const nlohmann::json& r = job.result;
      const bool ok = job.exit_code == 0 && job.error.empty();
      const double sim_s = r.value("sim_time_s", 0.0), dist = r.value("distance_m", 0.0), rtf = r.value("real_time_factor", 0.0);
      const double wall = r.value("wall_time_s", 0.0);
      total_wall += wall;
      std::string end = job.error.empty() ? r.value("end_reason", std::string("exit code ") + std::to_string(job.exit_code))
                                          : job.error;
      // Why a failed run did not arrive: stalled, rocking or still driving (scenarios/diagnosis.h).
      const std::string verdict = r.contains("diagnosis") ? r["diagnosis"].value("verdict", std::string()) : "";
      if (!ok && !verdict.empty() && verdict != "arrived") end += " (" + verdict + ")";
      std::printf("%-22s %-5llu %-34s %-6s %9.1f %9.1f %7.1f  %s\n", job.scenario.c_str(),
                  static_cast<unsigned long long>(job.seed), SettingsLabel(job.settings).c_str(),
                  ok ? "pass" : job.error.empty() ? "FAIL" : "ERROR",
                  sim_s, dist, rtf, end.c_str());
      summary.push_back({{"scenario", job.scenario}, {"file", job.file}, {"seed", job.seed}, {"settings", job.settings},
                         {"passed", ok}, {"exit_code", job.exit_code}, {"out", job.out_dir}, {"result", r}});
      if (!job.error.empty()) summary.back()["error"] = job.error;
      cases << "    <testcase classname=\"" << XmlEscape(job.scenario) << "\" name=\""
            << XmlEscape("seed=" + std::to_string(job.seed) + (job.settings.empty() ? "" : " " + SettingsLabel(job.settings)))
            << "\" time=\"" << wall << "\">\n";
      if (!job.error.empty()) {
        ++errors;
        cases << "      <error message=\"" << XmlEscape(job.error.substr(0, job.error.find('\n'))) << "\">"
              << XmlEscape(job.error) << "</error>\n";
      } else if (!ok) {
        std::string failures;
        if (r.contains("criteria")) {
          for (const auto& c : r["criteria"]) {
            if (!c.value("passed", false)) {
              failures += c.value("name", std::string()) + ": expected " + c.value("expected", std::string()) + ", got " +
                          c.value("actual", std::string()) + "\n";
            }
          }
          if (r.contains("diagnosis")) failures += "diagnosis: " + r["diagnosis"].value("summary", std::string()) + "\n";
        } else {
          failures = "run failed with exit code " + std::to_string(job.exit_code) + " (see " + job.out_dir + "/run.log)\n";
        }
        cases << "      <failure message=\"" << XmlEscape(failures.substr(0, failures.find('\n'))) << "\">"
              << XmlEscape(failures) << "</failure>\n";
      }
      cases << "    </testcase>\n";
    }
    // With several seeds: per scenario and settings, the pass rate, the failing seeds and the spread
    // of the passing runs' times (a single run is one sample of a chaotic closed loop).
    if (o->seeds > 1) {
      std::printf("\n%-22s %-34s %7s %-18s %17s %9s\n", "scenario", "settings", "passed", "failed seeds",
                  "passing sim [s]", "mean RTF");
      std::vector<std::pair<std::string, std::vector<std::string>>> groups;
      for (const Job& job : jobs) {
        const std::pair<std::string, std::vector<std::string>> g{job.scenario, job.settings};
        if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
      }
      for (const auto& g : groups) {
        int n = 0, ok = 0;
        double lo = 0.0, hi = 0.0, rtf = 0.0;
        std::string failed;
        for (const Job& job : jobs) {
          if (job.scenario != g.first || job.settings != g.second) continue;
          ++n;
          rtf += job.result.value("real_time_factor", 0.0);
          if (job.exit_code != 0 || !job.error.empty()) {
            failed += (failed.empty() ? "" : ",") + std::to_string(job.seed);
            continue;
          }
          const double t = job.result.value("sim_time_s", 0.0);
          lo = ok == 0 ? t : std::min(lo, t);
          hi = ok == 0 ? t : std::max(hi, t);
          ++ok;
        }
        char range[40] = "-";
        if (ok > 0) std::snprintf(range, sizeof(range), "%.1f-%.1f", lo, hi);
        std::printf("%-22s %-34s %3d/%-3d %-18s %17s %9.1f\n", g.first.c_str(), SettingsLabel(g.second).c_str(), ok, n,
                    failed.empty() ? "-" : failed.c_str(), range, rtf / n);
      }
    }
    // Sweep table: pass rate and mean figures per combination of values.
    if (!o->sweeps.empty()) {
      std::printf("\nsweep: %-40s %6s %12s %12s\n", "settings", "passed", "mean sim [s]", "mean dist [m]");
      for (const auto& combo : combos) {
        int n = 0, ok = 0;
        double sim_s = 0.0, dist = 0.0;
        for (const Job& job : jobs) {
          if (job.settings != combo) continue;
          ++n;
          ok += job.exit_code == 0 && job.error.empty();
          sim_s += job.result.value("sim_time_s", 0.0);
          dist += job.result.value("distance_m", 0.0);
        }
        if (n == 0) continue;
        std::printf("       %-40s %3d/%-3d %12.1f %12.1f\n", SettingsLabel(combo).c_str(), ok, n, sim_s / n, dist / n);
      }
    }
    fs::create_directories(o->out);
    std::ofstream junit(fs::path(o->out) / "junit.xml");
    junit << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ovpc scenarios\" tests=\""
          << jobs.size() << "\" failures=\"" << jobs.size() - passed - errors << "\" errors=\"" << errors << "\" time=\""
          << total_wall << "\">\n"
          << cases.str() << "  </testsuite>\n</testsuites>\n";
    std::ofstream(fs::path(o->out) / "summary.json") << nlohmann::json{{"runs", summary}, {"passed", passed}, {"errors", errors}, {"total", jobs.size()}}.dump(2)
                                                     << "\n";
    std::printf("\n%zu of %zu runs passed; wrote %s/junit.xml and %s/summary.json\n", passed, jobs.size(), o->out.c_str(),
                o->out.c_str());
    if (malformed) return kExitBadInput;
    return passed == jobs.size() ? kExitOk : kExitFailure;
  };
}

}  // namespace ovpc::apps
