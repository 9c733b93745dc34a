#include "ovpc/bench/stats.h"

#include <algorithm>
#include <cmath>

#include "ovpc/core/internal/percentile.h"

namespace ovpc::bench {

double Percentile(const std::vector<double>& sorted, double p) { return ovpc::internal::Percentile(sorted, p); }

SampleStats Summarize(std::vector<double> samples) {
  SampleStats s;
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  const double n = static_cast<double>(samples.size());
  s.n = samples.size();
  s.min = samples.front();
  s.max = samples.back();
  s.median = Percentile(samples, 0.5);
  s.p90 = Percentile(samples, 0.9);
  s.p95 = Percentile(samples, 0.95);
  s.p99 = Percentile(samples, 0.99);
  double sum = 0.0;
  for (const double x : samples) sum += x;
  s.mean = sum / n;
  double sum_sq = 0.0;
  for (const double x : samples) sum_sq += (x - s.mean) * (x - s.mean);
  s.sd = samples.size() > 1 ? std::sqrt(sum_sq / (n - 1.0)) : 0.0;
  return s;
}

}  // namespace ovpc::bench
