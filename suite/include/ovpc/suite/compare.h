// Two suites' results side by side (their summary.json files), as a reviewer of a change wants them:
// the runs that changed verdict, and per scenario and family the pass rate and time to the goal.
#pragma once

#include <string>

#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// What CompareSuites found.
struct Comparison {
  std::string markdown;        ///< the comparison as Markdown (what is printed and written)
  std::size_t regressed = 0;   ///< runs that passed in the old results and do not in the new ones
  std::size_t fixed = 0;       ///< runs that did not pass in the old results and do in the new ones
  std::size_t matched = 0;     ///< runs in both (the same scenario or family draw, seed, map and settings)
};

/// Compares `old_results` with `new_results` (their names as given: `old_name`, `new_name`).
Comparison Compare(const SuiteResults& old_results, const std::string& old_name, const SuiteResults& new_results,
                   const std::string& new_name);

/// The summary.json of `path`: a suite's folder (PATH/summary.json) or the file itself.
/// @throws BadInput naming the file when it is missing or not a suite's result file.
SuiteResults LoadResults(const std::string& path);

/// `ovpc compare OLD NEW`: prints the comparison and writes it to compare.md in `out` (made when
/// missing), or in NEW's folder when `out` is "". Returns 1 when a run regressed (passed in OLD,
/// not in NEW), else 0.
/// @throws BadInput for a missing or invalid summary.json (naming it) or an output folder that
/// cannot be written.
int CompareSuites(const std::string& old_path, const std::string& new_path, const std::string& out);

}  // namespace ovpc::suite
