#include "ovpc/bench/stats.h"

#include <cmath>

#include <gtest/gtest.h>

#include "ovpc/bench/report.h"

namespace ovpc::bench {
namespace {

TEST(StatsTest, KnownSample) {
  const SampleStats s = Summarize({5.0, 1.0, 4.0, 2.0, 3.0});
  EXPECT_EQ(s.n, 5u);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt(2.5));  // sample sd, n - 1
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 5.0);
  EXPECT_DOUBLE_EQ(s.p90, 4.6);  // 1 + 0.9 (5 - 1) = position 4.6
  EXPECT_DOUBLE_EQ(s.p95, 4.8);
  EXPECT_NEAR(s.p99, 4.96, 1e-12);
}

TEST(StatsTest, EmptyAndSingleSamples) {
  const SampleStats empty = Summarize({});
  EXPECT_EQ(empty.n, 0u);
  EXPECT_EQ(empty.mean, 0.0);
  const SampleStats one = Summarize({7.5});
  EXPECT_EQ(one.n, 1u);
  EXPECT_EQ(one.mean, 7.5);
  EXPECT_EQ(one.sd, 0.0);
  EXPECT_EQ(one.median, 7.5);
  EXPECT_EQ(one.p95, 7.5);
}

TEST(StatsTest, PercentileInterpolatesBetweenRanks) {
  const std::vector<double> sorted = {0.0, 10.0};
  EXPECT_DOUBLE_EQ(Percentile(sorted, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(Percentile(sorted, 0.25), 2.5);
  EXPECT_DOUBLE_EQ(Percentile(sorted, 1.0), 10.0);
}

TEST(ReportTest, CsvAndJsonQuoting) {
  EXPECT_EQ(CsvField("ovpc"), "ovpc");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(JsonEscape("a\"b\\c\n"), "a\\\"b\\\\c\\u000a");
}

}  // namespace
}  // namespace ovpc::bench
