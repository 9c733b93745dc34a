// What the suite's reports say of a run, shared by the printed tables, junit.xml, summary.md and
// report.html: its outcome, its settings, its failed criteria, and its files' places.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// A run's outcome as the reports show it.
enum class Outcome {
  kPass,        ///< passed (a family run: its expectation held)
  kFail,        ///< ran and failed (a family run: its expectation was violated)
  kError,       ///< no result: a malformed file, a crash, a signal, a cancelled run
  kNotCounted,  ///< a family run whose draw may pass or fail (`then: any`)
};
Outcome OutcomeOf(const Job& job);
/// "pass", "FAIL", "ERROR" or "any".
const char* OutcomeLabel(Outcome o);

/// Text for XML and HTML: & < > " as entities, and the control characters XML 1.0 cannot hold
/// (below 0x20 but tab, line feed and carriage return, and 0x7f) as "\xNN".
std::string XmlEscape(const std::string& text);

/// A family run's draw and its scenario file.
const scenarios::Draw& DrawOf(const std::vector<FamilyInput>& families, const Job& job);
const std::string& DrawFile(const std::vector<FamilyInput>& families, const Job& job);

/// A family run's drawn values, then the sweep's settings ("key=v key2=v2").
std::string RunSettings(const std::vector<FamilyInput>& families, const Job& job);

/// "-" for a plain run; "any", or "pass: ok", "refuse: VIOLATED", ... for a family run.
std::string ExpectCell(const std::vector<FamilyInput>& families, const Job& job);

/// The failed criteria ("name: expected E, got A" a line each) and the diagnosis line; for a run
/// without criteria, its exit code and where its log is.
std::string FailureText(const Job& job);

/// The diagnosis's verdict of a run ("stalled", "rocking", "arrived", ...; "" when none).
std::string DiagnosisVerdict(const Job& job);

/// "scenario seed=N", or for a family run "family draw_iii values seed=N".
std::string RunName(const SuiteResults& results, const Job& job);

/// The scenario, or for a family run its family's name.
std::string GroupName(const std::vector<FamilyInput>& families, const Job& job);

/// `path` as seen from the folder `from` (both made absolute, lexically; no file is read).
std::string RelativePath(const std::string& path, const std::filesystem::path& from);

/// A relative or absolute path as a URL path: every byte but unreserved ones and '/' %-encoded.
std::string UrlPath(const std::string& path);

/// The runs of one scenario (not a family's) with one map and settings, over the seeds.
struct ScenarioGroup {
  std::string scenario, map, settings;
  double time_limit_s = 0.0;
  std::size_t runs = 0, passed = 0;
  std::vector<std::uint64_t> failed_seeds;
  std::size_t arrived = 0;  ///< passing runs, whose simulated time is their time to the goal
  double goal_min_s = 0.0, goal_max_s = 0.0, goal_sum_s = 0.0;
};
/// The suite's plain runs grouped by scenario, map and settings, in the order of their first run.
std::vector<ScenarioGroup> ScenarioGroups(const SuiteResults& results);

/// A family's runs by expectation: ok of those expected to pass and to refuse, not counted, errors.
struct FamilyCounts {
  std::string family;
  std::size_t pass_ok = 0, pass_runs = 0, refuse_ok = 0, refuse_runs = 0, any_runs = 0, errors = 0;
};
std::vector<FamilyCounts> FamilyTotals(const SuiteResults& results);

/// "3/4 (75 %)", or "-" for no runs.
std::string Rate(std::size_t ok, std::size_t runs);

/// The files an `ovpc run` writes that a report links to, in this order (only those present).
inline constexpr const char* kRunFiles[] = {"result.json", "topdown.png", "run.mcap", "trajectory.csv",
                                            "plans.csv",   "cycles.csv",  "run.log"};

}  // namespace ovpc::suite
