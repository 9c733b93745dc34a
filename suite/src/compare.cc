// Two suites' results compared (ovpc/suite/compare.h): runs matched by what they ran (scenario or
// family draw, seed, map, settings), verdict changes first, then pass rate and time to the goal per
// scenario and family.
#include "ovpc/suite/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

#include "ovpc/suite/output_folder.h"
#include "ovpc/suite/runner.h"
#include "report_files.h"
#include "report_text.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

// What a run ran, the same in two suites of the same inputs: scenario or family draw (with its
// values), seed, map and settings.
std::string RunKey(const SuiteResults& r, const Job& job) {
  return RunName(r, job) + " map=" + job.map + (job.settings.empty() ? "" : " " + SettingsLabel(job.settings));
}

// The group a run is tabulated in: its scenario, or its family, with its map and settings.
using GroupId = std::tuple<std::string, std::string, std::string>;
GroupId GroupKey(const SuiteResults& r, const Job& job) {
  return {(job.draw ? "family " : "") + GroupName(r.families, job), job.map, SettingsLabel(job.settings)};
}

// Whether a run counts in its group's pass rate (a family's `any` draws do not), and whether it
// reached its goal (a passing run of a scenario or of a draw expected to pass).
bool Counted(const SuiteResults& r, const Job& job) {
  return !job.draw || DrawOf(r.families, job).expectation != scenarios::Expectation::kAny;
}
bool Arrived(const SuiteResults& r, const Job& job) {
  return Passed(job) && job.result.contains("sim_time_s") &&
         (!job.draw || DrawOf(r.families, job).expectation == scenarios::Expectation::kPass);
}

struct Group {
  std::size_t old_ok = 0, old_runs = 0, new_ok = 0, new_runs = 0;
  std::size_t paired = 0;  // runs that reached the goal in both
  double old_goal_s = 0.0, new_goal_s = 0.0;
};

struct Change {
  int rank;  // 0 regressed, 1 fixed, 2 another change of outcome
  std::string line;
};

std::string Signed(double v, const char* unit) {
  char text[48];
  std::snprintf(text, sizeof(text), "%+.1f%s", v, unit);
  return text;
}

std::string Why(const SuiteResults& r, const Job& job) {
  if (!job.error.empty()) return job.error.substr(0, job.error.find('\n'));
  if (Passed(job)) return "";
  const std::string verdict = DiagnosisVerdict(job);
  const std::string failures = FailureText(job);
  return (verdict.empty() ? "" : verdict + ": ") + failures.substr(0, failures.find('\n')) +
         (job.draw ? " (expected " + std::string(scenarios::ExpectationName(DrawOf(r.families, job).expectation)) + ")" : "");
}

class Comparer {
 public:
  Comparer(const SuiteResults& a, const SuiteResults& b) : a_(a), b_(b) {}

  Comparison Run(const std::string& old_name, const std::string& new_name) {
    std::map<std::string, const Job*> old_runs;
    for (const Job& job : a_.jobs) old_runs.emplace(RunKey(a_, job), &job);
    for (const Job& job : a_.jobs) AddSide(groups_[GroupKey(a_, job)], a_, job, true);
    for (const Job& job : b_.jobs) {
      AddSide(groups_[GroupKey(b_, job)], b_, job, false);
      const auto it = old_runs.find(RunKey(b_, job));
      if (it == old_runs.end()) {
        ++only_new_;
        continue;
      }
      Match(*it->second, job);
      old_runs.erase(it);
    }
    only_old_ = old_runs.size();
    result_.markdown = Header(old_name, new_name) + Changes() + Groups();
    return result_;
  }

 private:
  static void AddSide(Group& g, const SuiteResults& r, const Job& job, bool old_side) {
    if (!Counted(r, job)) return;
    (old_side ? g.old_runs : g.new_runs) += 1;
    (old_side ? g.old_ok : g.new_ok) += Passed(job);
  }

  void Match(const Job& o, const Job& n) {
    ++result_.matched;
    if (Arrived(a_, o) && Arrived(b_, n)) {
      Group& g = groups_[GroupKey(b_, n)];
      ++g.paired;
      g.old_goal_s += o.result.value("sim_time_s", 0.0);
      g.new_goal_s += n.result.value("sim_time_s", 0.0);
    }
    const Outcome before = OutcomeOf(o), after = OutcomeOf(n);
    if (before == after) return;
    const int rank = Passed(o) && !Passed(n) ? 0 : !Passed(o) && Passed(n) ? 1 : 2;
    result_.regressed += rank == 0;
    result_.fixed += rank == 1;
    static const char* const kWhat[] = {"regressed", "fixed", "changed"};
    changes_.push_back({rank, "| " + MarkdownCell(RunKey(b_, n)) + " | " + kWhat[rank] + " | " + OutcomeLabel(before) + " | " +
                                  OutcomeLabel(after) + " | " + MarkdownCell(Why(b_, n)) + " |\n"});
  }

  std::string Header(const std::string& old_name, const std::string& new_name) const {
    std::ostringstream md;
    md << "# ovpc compare\n\nold: " << old_name << " (build `" << a_.suite.build << "`, " << a_.jobs.size() << " runs)  \nnew: " << new_name
       << " (build `" << b_.suite.build << "`, " << b_.jobs.size() << " runs)\n\n**" << result_.regressed
       << " runs regressed (passed, now do not), " << result_.fixed << " fixed**; " << result_.matched << " runs in both, " << only_old_
       << " only in old, " << only_new_ << " only in new.\n";
    return md.str();
  }

  std::string Changes() {
    if (changes_.empty()) return "\nNo run changed verdict.\n";
    std::stable_sort(changes_.begin(), changes_.end(), [](const Change& x, const Change& y) { return x.rank < y.rank; });
    std::string md = "\n## Runs that changed verdict\n\n| run | change | old | new | new: why |\n|---|---|---|---|---|\n";
    for (const Change& c : changes_) md += c.line;
    return md;
  }

  std::string Groups() const {
    std::ostringstream md;
    md << "\n## Pass rate and time to goal per scenario and family\n\nTime to goal: the mean over the runs that reached the goal in both.\n\n"
          "| scenario or family | map | settings | old passed | new passed | change | time to goal old [s] | new [s] | change |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [key, g] : groups_) {
      const auto& [name, map, settings] = key;
      const double old_rate = g.old_runs ? 100.0 * g.old_ok / g.old_runs : NAN, new_rate = g.new_runs ? 100.0 * g.new_ok / g.new_runs : NAN;
      md << "| " << MarkdownCell(name) << " | " << MarkdownCell(map) << " | " << MarkdownCell(settings) << " | " << Rate(g.old_ok, g.old_runs) << " | " << Rate(g.new_ok, g.new_runs) << " | "
         << (std::isfinite(old_rate) && std::isfinite(new_rate) ? Signed(new_rate - old_rate, " pp") : "-") << " | ";
      if (g.paired == 0) {
        md << "- | - | - |\n";
        continue;
      }
      const double o = g.old_goal_s / g.paired, n = g.new_goal_s / g.paired;
      char text[96];
      std::snprintf(text, sizeof(text), "%.1f | %.1f | %s (%s)", o, n, Signed(n - o, " s").c_str(),
                    o > 0 ? Signed(100.0 * (n - o) / o, " %").c_str() : "-");
      md << text << " |\n";
    }
    return md.str();
  }

  const SuiteResults& a_;
  const SuiteResults& b_;
  std::map<GroupId, Group> groups_;
  std::vector<Change> changes_;
  Comparison result_;
  std::size_t only_old_ = 0, only_new_ = 0;
};

}  // namespace

Comparison Compare(const SuiteResults& old_results, const std::string& old_name, const SuiteResults& new_results,
                   const std::string& new_name) {
  return Comparer(old_results, new_results).Run(old_name, new_name);
}

SuiteResults LoadResults(const std::string& path) {
  std::error_code ec;
  const fs::path file = fs::is_directory(path, ec) ? fs::path(path) / "summary.json" : fs::path(path);
  if (!fs::exists(file, ec)) throw BadInput(file.string() + ": no such file (give a suite's output folder or its summary.json)");
  return LoadSuiteResults(file.string());
}

int CompareSuites(const std::string& old_path, const std::string& new_path, const std::string& out) {
  const SuiteResults a = LoadResults(old_path), b = LoadResults(new_path);
  std::error_code ec;
  fs::path dir = out;
  if (dir.empty()) dir = fs::is_directory(new_path, ec) ? fs::path(new_path) : fs::path(new_path).parent_path();
  if (dir.empty()) dir = ".";
  if (!out.empty()) MakeFolder(dir);
  const Comparison c = Compare(a, old_path, b, new_path);
  std::fputs(c.markdown.c_str(), stdout);
  try {
    WriteFileAtomic(dir / "compare.md", c.markdown);
  } catch (const std::runtime_error& e) {
    throw BadInput(e.what());
  }
  std::printf("\nwrote %s\n", (dir / "compare.md").string().c_str());
  return c.regressed > 0 ? kExitFailure : kExitOk;
}

}  // namespace ovpc::suite
