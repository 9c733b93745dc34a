// A suite's runs and their reports: the tables, JUnit XML, summary.json and the families' pass rates.
// summary.json is the suite's result file: it holds everything the report is made from, so that
// LoadSuiteResults gives back what WriteReport wrote (a shard's results are merged from it).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ovpc/scenarios/family.h"

namespace ovpc::suite {

/// A family given to the suite: its draws and where they were written.
struct FamilyInput {
  scenarios::Family family;
  std::vector<scenarios::Draw> draws;
  std::vector<std::string> files;  ///< the drawn scenario files, per draw
  std::string dir;                 ///< where it was drawn: OUT/<family>
  std::string folder;              ///< its folder's name under a report's folder: <family>[_k]
};

/// A run of a family's draw: which, and what it had to do.
struct DrawRun {
  std::size_t family = 0;  ///< index into the suite's families
  std::size_t draw = 0;    ///< index into its draws
  scenarios::Verdict verdict = scenarios::Verdict::kError;
};

struct Job {
  std::size_t index = 0;  ///< its place among the suite's planned runs (every shard's): the report's order
  std::string file;
  std::string scenario;
  std::uint64_t seed = 1;
  std::vector<std::string> settings;  // key=value
  std::string out_dir;
  std::string map;  // the map backend of the run (navigator.map with its settings and --map)
  double time_limit_s = 0.0;  // the scenario's simulated time limit: the longest runs start first
  pid_t pid = 0;
  int exit_code = -1;
  nlohmann::json result = nlohmann::json::object();
  std::string error;  // why there is no result: a malformed file, a killed or crashed run, ...
  std::optional<DrawRun> draw;
};

/// A plain run passed: exit code 0 and no error. A family run passed when its expectation held or
/// is not counted (and it had no error).
bool Passed(const Job& job);

/// What a family run was: family, file, draw, drawn values, expectation, reason and verdict (the
/// `extra` field of its result.json, the `family` field of its summary.json entry).
nlohmann::json DrawJson(const std::vector<FamilyInput>& families, const DrawRun& run);

/// "key=v key2=v2".
std::string SettingsLabel(const std::vector<std::string>& settings);

/// What a suite was asked to run, and by which build: the suite record of summary.json. Shards of one
/// suite have equal records but for `shard` (and `stop_signal`).
struct SuiteRecord {
  std::vector<std::string> inputs;  ///< as given
  int seeds = 1;
  int first_seed = 1;
  std::vector<std::string> sweeps;                                  ///< "key=v1,v2" as given
  std::vector<std::vector<std::string>> combinations = {{}};        ///< in the planned order
  std::vector<std::string> skip_labels;
  std::string map;                  ///< --map ("" when not given)
  long long samples = 6;            ///< families: draws per grid point
  std::uint64_t family_seed = 1;
  std::string preset_file;          ///< "" for the built-in preset
  std::string preset_hash;          ///< ContentHash of the preset's text
  std::string build;                ///< the ovpc build's identity (BuildId())
  int shard = 1;                    ///< this report's part of the planned runs: shard `shard` of `shards`
  int shards = 1;
  std::size_t planned = 0;          ///< runs in the whole suite (every shard)
  std::string plan_fingerprint;     ///< PlanFingerprint of the whole planned run list
  bool malformed = false;           ///< a malformed input among the planned runs (exit code 2)
  int stop_signal = 0;              ///< the signal that stopped the runs (0: every run ran)
  int merged = 0;                   ///< shards this report was merged from (0: the suite's own)
};

/// A scenario file (or a family's draw) that --skip-label left out: reported as skipped.
struct SkippedRun {
  std::string file;      ///< the scenario file (a family's drawn scenario file)
  std::string scenario;  ///< its name
  std::string label;     ///< the label it was left out for
};

/// A suite's results: what WriteReport reports and LoadSuiteResults reads back.
struct SuiteResults {
  SuiteRecord suite;
  std::vector<Job> jobs;             ///< in the planned order (Job::index ascending)
  std::vector<FamilyInput> families;
  std::vector<SkippedRun> skipped;   ///< in the order of the inputs
};

/// How the reports are written.
struct ReportOptions {
  /// junit.xml's attachments ([[ATTACHMENT|path]] in a testcase's system-out) as absolute paths
  /// (Jenkins' JUnit attachments), not relative to junit.xml's folder.
  bool junit_absolute_paths = false;
};

/// The summary table, the per-seed and sweep tables, the families' pass-rate tables (and their
/// files: OUT/<family>/pass_rate.csv, runs.csv, pass_rate_<parameter>.svg), junit.xml, summary.md
/// (a Markdown summary, e.g. for a CI job's page), report.html with a page per run
/// (runs/<index>.html) and summary.json in `out`, each written whole or not at all. Returns the
/// number of runs that passed.
/// @throws std::runtime_error naming the first file that could not be written whole.
std::size_t WriteReport(const SuiteResults& results, const std::string& out, const ReportOptions& options = {});

/// The results a summary.json holds (WriteReport's): the report written from them again is the same.
/// @throws BadInput, one line naming the file and the problem (unreadable, not JSON, no suite record,
/// a family file's text that no longer reads, an index out of range).
SuiteResults LoadSuiteResults(const std::string& summary_path);

/// The ovpc build's identity: `git describe` of the source tree when it was configured, or "unknown".
std::string BuildId();

/// A 64-bit FNV-1a hash of `text` as "fnv1a64:<16 hex digits>" (the preset's, the plan's).
std::string ContentHash(const std::string& text);

}  // namespace ovpc::suite
