// The suite runner: plans the runs of scenario files, scenario families, seeds and sweeps, runs
// each as `ovpc run` in a process of its own, judges them, and writes the reports (report.h).
// The `ovpc suite` command is this with a command line; a tool of your own can call it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/suite/errors.h"
#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// Exit codes of a suite (and of `ovpc run`, whose codes it reads).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   ///< a run failed or had an error, or a report could not be written
inline constexpr int kExitBadInput = 2;  ///< bad arguments or a malformed input file

/// A suite larger than this is split (fewer seeds or inputs): refused before anything is planned.
inline constexpr std::size_t kMaxRuns = 100000;
inline constexpr std::size_t kMaxCombinations = 10000;
inline constexpr int kMaxShards = 10000;

struct Options {
  std::string program;              ///< the `ovpc` executable that runs one scenario (`ovpc run`)
  std::vector<std::string> inputs;  ///< scenario or family files, or folders of them (every *.yaml)
  int jobs = 2;                     ///< runs at a time
  int seeds = 1;                    ///< seeds first_seed .. first_seed + seeds - 1 for every run
  int first_seed = 1;
  std::vector<std::string> sweeps;  ///< "key=v1,v2,...": every combination is run
  std::vector<std::string> skip_labels;
  std::string preset;               ///< the robot's configuration ("" = the built-in one)
  std::string map;                  ///< every run's map backend, when map_given
  bool map_given = false;
  int threads = 0;                  ///< each run's threads; 0: 2 unless --jobs fill the cores
  std::string out = "out/suite";
  long long samples = 6;            ///< families: random draws per grid point
  std::uint64_t family_seed = 1;    ///< families: the seed the draws are made from
  int shard = 1;                    ///< --shard K/N: run shard K of N of the planned runs (ShardOf)
  int shards = 1;
  bool junit_absolute_paths = false;  ///< junit.xml's attachments as absolute paths (ReportOptions)
};

/// Runs the suite: prints a progress line and the tables, writes the reports (WriteReport: junit.xml,
/// summary.md, report.html, summary.json, the families' files) in OUT. SIGINT and SIGTERM stop the runs; the report of what finished is
/// still written. Returns the exit code: kExitOk every run passed, kExitFailure a run failed or
/// had an error, kExitBadInput a malformed file among the inputs, 128 + the signal that stopped it.
/// @throws BadInput for bad options, inputs or an output folder that cannot be used (nothing run).
int RunSuite(const Options& options);

/// Merges the reports of a sharded suite's shards (their folders' summary.json files alone) into
/// `out`: the tables, junit.xml, summary.md, report.html, summary.json and the families' files of the whole suite, its runs in
/// the planned order, as the unsharded suite writes them. Returns the exit code the whole suite
/// would have had.
/// @throws BadInput naming the folder and what is wrong: no summary.json, a shard missing or given
/// twice, one of another build, inputs, settings, preset or planned run list, one that was stopped.
int MergeShards(const std::vector<std::string>& folders, const std::string& out, const ReportOptions& options = {});

/// "K/N" of --shard: 1 <= K <= N <= kMaxShards.
/// @throws BadInput otherwise.
std::pair<int, int> ParseShard(const std::string& text);

/// "navigator.map=NAME" for a map backend's name (ovpc, octomap or elevation).
/// @throws BadInput naming the allowed names.
std::string MapSetting(const std::string& name);

}  // namespace ovpc::suite
