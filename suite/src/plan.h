// Planning a suite: the sweep's combinations, the input files, and the jobs (runs) they make.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ovpc/scenarios/scenario_yaml.h"
#include "ovpc/suite/report.h"
#include "ovpc/suite/runner.h"

namespace ovpc::suite {

/// Every combination of the sweeps' values ("key=v1,v2,..." each), as lists of key=value.
/// @throws BadInput for a malformed sweep or more than kMaxCombinations combinations.
std::vector<std::vector<std::string>> SweepCombinations(const std::vector<std::string>& sweeps);

/// The input files in order: every *.yaml of a folder (sorted), or the file itself.
/// @throws BadInput for a missing input, one that is not a file or folder, or a file given twice.
std::vector<std::string> CollectFiles(const std::vector<std::string>& inputs);

/// Turns the input files into jobs: each scenario file and each draw of a family (drawn into its
/// folder under OUT), per sweep combination and seed, with a run folder of its own inside OUT.
class Planner {
 public:
  Planner(const Options& o, std::vector<std::vector<std::string>> combos, scenarios::Preset preset)
      : o_(o), combos_(std::move(combos)), preset_(std::move(preset)) {}

  /// @throws BadInput past kMaxRuns, or for a run folder that may not be cleared.
  void AddFile(const std::string& file);

  std::vector<Job> jobs;
  std::vector<FamilyInput> families;
  std::vector<SkippedRun> skipped;  ///< the scenarios --skip-label left out
  bool malformed = false;  ///< a malformed input (or sweep value) is among the jobs, as an error

 private:
  std::string FolderOf(const std::string& file, const std::string& name, std::size_t k);
  bool Skipped(const scenarios::Scenario& s, const std::string& file);
  bool NameIsFolder(const std::string& file, const std::string& name);
  std::map<std::string, std::string> BadSweepValues(const std::string& file) const;
  bool Refused(const std::string& file, const std::string& name, const std::vector<std::string>& combo,
               const std::map<std::string, std::string>& bad);
  void AddMalformed(const std::string& file, const std::string& error);
  std::string MapOf(const std::string& file, const scenarios::Scenario& s, const std::vector<std::string>& combo) const;
  void AddSeeds(const std::string& file, const std::string& name, const std::vector<std::string>& combo,
                const std::filesystem::path& dir, const std::optional<DrawRun>& draw, const std::string& map,
                double time_limit_s);
  void AddFamily(const std::string& file);

  const Options& o_;
  std::vector<std::vector<std::string>> combos_;
  scenarios::Preset preset_;
  std::map<std::string, std::string> tag_files_;  // run folder name -> the file that has it
};

}  // namespace ovpc::suite
