// Summary statistics of samples (timings, angular errors), shared by the benchmark programs.
#pragma once

#include <cstddef>
#include <vector>

namespace ovpc::bench {

/// Summary of a sample; all zero for an empty sample. Percentiles by linear interpolation between
/// the closest ranks (the "R-7" definition), so with few samples p99 is close to the maximum.
struct SampleStats {
  std::size_t n = 0;
  double mean = 0.0;
  double sd = 0.0;  ///< sample standard deviation (n - 1 in the denominator; 0 for one sample)
  double min = 0.0;
  double max = 0.0;
  double median = 0.0;
  double p90 = 0.0;
  double p95 = 0.0;
  double p99 = 0.0;
};

/// Percentile `p` in [0, 1] of an ascending, non-empty sample.
double Percentile(const std::vector<double>& sorted, double p);

/// Summarises `samples` (any order). Every sample must be finite.
SampleStats Summarize(std::vector<double> samples);

}  // namespace ovpc::bench
