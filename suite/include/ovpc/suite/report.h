// A suite's runs and their reports: the tables, JUnit XML, summary.json and the families' pass rates.
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
  std::string dir;                 ///< OUT/<family>
};

/// A run of a family's draw: which, and what it had to do.
struct DrawRun {
  std::size_t family = 0;  ///< index into the suite's families
  std::size_t draw = 0;    ///< index into its draws
  scenarios::Verdict verdict = scenarios::Verdict::kError;
};

struct Job {
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

struct Report {
  const std::vector<Job>& jobs;
  const std::vector<FamilyInput>& families;
  std::string out;
  int seeds = 1;
  bool sweeps = false;
  std::vector<std::vector<std::string>> combos;
};

/// The summary table, the per-seed and sweep tables, the families' pass-rate tables (and their
/// files: OUT/<family>/pass_rate.csv, runs.csv, pass_rate_<parameter>.svg), junit.xml and
/// summary.json, each written whole or not at all. Returns the number of runs that passed.
/// @throws std::runtime_error naming the first file that could not be written whole.
std::size_t WriteReport(const Report& report);

}  // namespace ovpc::suite
