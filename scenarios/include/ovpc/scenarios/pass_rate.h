// Pass rate of a scenario family's runs against each drawn parameter: tables, CSV and SVG plots
// (what `ovpc suite` prints and writes per family).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/scenarios/family.h"

namespace ovpc::scenarios {

/// One run of a draw (a draw runs once per seed), judged.
struct JudgedRun {
  std::vector<std::pair<std::string, Value>> values;  ///< the draw's
  Expectation expectation = Expectation::kPass;
  Verdict verdict = Verdict::kError;
};

/// Runs whose value of the parameter is one value, or falls in one bin. "ok" counts kOk verdicts;
/// runs with an error count as not ok.
struct PassRateRow {
  std::string label;        ///< "2.5", "ramp" or "[1.5, 1.9)"
  double lo = 0.0, hi = 0.0;  ///< the bin (lo == hi for one number; both 0 for a word)
  std::size_t pass_ok = 0, pass_runs = 0;      ///< runs expected to pass
  std::size_t refuse_ok = 0, refuse_runs = 0;  ///< runs expected to refuse
  std::size_t any_runs = 0;                    ///< not counted
};

struct PassRateTable {
  std::string parameter;
  std::string kind;     ///< the distribution's name
  bool binned = false;  ///< 5 equal-width bins over the range; else one row per value
  std::vector<PassRateRow> rows;
};

/// Rows per value for choice, grid and integer parameters with at most 10 values (and for words),
/// else 5 equal-width bins over the range (uniform, integer, clipped normal: their range; an
/// unclipped normal or a long numeric list: the values' span).
PassRateTable TabulatePassRate(const Parameter& parameter, const std::vector<JudgedRun>& runs);

/// The table as text: per row, ok/runs and the percentage for pass and refuse runs, and any runs.
std::string FormatPassRateTable(const std::string& family, const PassRateTable& table);
/// CSV of all tables: parameter,bin,lo,hi,pass_ok,pass_runs,refuse_ok,refuse_runs,any_runs.
std::string PassRateCsv(const std::vector<PassRateTable>& tables);
/// An SVG bar chart: pass rate per row (pass runs and refuse runs side by side), axis labels, ok/runs
/// above each bar.
std::string PassRateSvg(const std::string& family, const PassRateTable& table);

}  // namespace ovpc::scenarios
