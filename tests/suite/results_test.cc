// A suite's result file: the report written again from summary.json alone is the same report, and
// shards split the planned runs deterministically, each run in one shard, balanced by cost.
#include "results.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "../support/test_scenarios.h"
#include "ovpc/suite/errors.h"
#include "ovpc/suite/runner.h"
#include "shard.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The short flat scenario as a family: two goal distances (the farther one must be refused) and a
// post placed at random.
std::string FamilyText() {
  std::string family = testing::kShortFlatScenario;
  family.replace(family.find("name: short_flat"), 16, "name: short_family");
  family.replace(family.find("route: [[0, 0], [6, 0]]"), 23, "route: [[0, 0], [$goal_x, 0]]");
  family.replace(family.find("goal: {x_m: 6.0"), 15, "goal: {x_m: \"${goal_x}\"");
  return family +
         "parameters:\n  goal_x: {grid: [6, 7]}\n  post_y: {uniform: [4, 6]}\nobjects:\n  - cylinder: {x_m: 3, y_m: $post_y}\n"
         "expect:\n  - {when: \"goal_x < 6.5\", then: pass}\n  - {when: \"post_y < 5\", then: refuse, reason: near, forbidden: [{name: pit, min_m: [2, -8], max_m: [4, -6]}]}\n"
         "  - {then: any, reason: \"far & <odd>\"}\n";
}

nlohmann::json Result(bool passed, double sim_s) {
  return {{"passed", passed},
          {"sim_time_s", sim_s},
          {"distance_m", 6.25},
          {"real_time_factor", 3.5},
          {"wall_time_s", sim_s / 3.5},
          {"end_reason", passed ? "goal reached" : "time limit"},
          {"collision_steps", 0},
          {"criteria", {{{"name", "goal"}, {"expected", "within 1 m"}, {"actual", passed ? "0.2 m" : "3.1 m"}, {"passed", passed}}}},
          {"diagnosis", {{"verdict", passed ? "arrived" : "stalled"}, {"summary", "stood 4 s"}}}};
}

Job PlainJob(const std::string& out, std::uint64_t seed, const std::string& setting, bool passed) {
  Job job;
  job.file = "/inputs/short.yaml";
  job.scenario = "short_flat";
  job.seed = seed;
  job.settings = {setting};
  job.out_dir = out + "/short_flat__" + setting + "/seed_" + std::to_string(seed);
  job.map = "ovpc";
  job.time_limit_s = 8.0;
  job.exit_code = passed ? 0 : 1;
  job.result = Result(passed, 5.0 + static_cast<double>(seed) / 3.0);
  return job;
}

// Plain runs that passed and failed, a malformed file, and a family's runs with every verdict, on
// two seeds and a sweep of two values.
SuiteResults MadeUpSuite(const std::string& out) {
  SuiteResults r;
  r.suite.inputs = {"/inputs/short.yaml", "/inputs/broken.yaml", "/inputs/family.yaml"};
  r.suite.seeds = 2;
  r.suite.sweeps = {"navigator.x=1,2"};
  r.suite.combinations = {{"navigator.x=1"}, {"navigator.x=2"}};
  r.suite.samples = 2;
  r.suite.family_seed = 5;
  r.suite.preset_hash = ContentHash("navigator: {}\n");
  r.suite.build = "v1-test";
  r.suite.malformed = true;
  FamilyInput in;
  in.family = scenarios::ParseFamily(FamilyText(), "/inputs/family.yaml");
  in.draws = scenarios::DrawFamily(in.family, {2, 5});
  for (const auto& d : in.draws) in.files.push_back(out + "/short_family/" + scenarios::DrawFolder(d.index) + "/scenario.yaml");
  in.dir = out + "/short_family";
  in.folder = "short_family";
  r.families.push_back(in);
  for (std::uint64_t seed : {1, 2}) {
    r.jobs.push_back(PlainJob(out, seed, "navigator.x=1", true));
    r.jobs.push_back(PlainJob(out, seed, "navigator.x=2", seed == 1));
  }
  Job broken;
  broken.file = "/inputs/broken.yaml";
  broken.scenario = "broken";
  broken.exit_code = kExitBadInput;
  broken.error = "/inputs/broken.yaml:3: 'terrain' <must> be a map\nsecond line";
  r.jobs.push_back(broken);
  const scenarios::Verdict verdicts[] = {scenarios::Verdict::kOk, scenarios::Verdict::kViolated, scenarios::Verdict::kNotCounted,
                                         scenarios::Verdict::kError};
  for (std::size_t d = 0; d < in.draws.size(); ++d) {
    Job job = PlainJob(out, 1, "navigator.x=1", d % 2 == 0);
    job.file = in.files[d];
    job.scenario = in.draws[d].name;
    job.out_dir = in.dir + "/" + scenarios::DrawFolder(d) + "/navigator.x=1/seed_1";
    job.draw = DrawRun{0, d, verdicts[d % 4]};
    if (job.draw->verdict == scenarios::Verdict::kError) job.error = "killed by signal 9", job.result = nlohmann::json::object();
    r.jobs.push_back(job);
  }
  for (std::size_t i = 0; i < r.jobs.size(); ++i) r.jobs[i].index = i;
  r.skipped.push_back({"/inputs/long.yaml", "long_one", "long"});
  r.suite.skip_labels = {"long"};
  r.suite.planned = r.jobs.size();
  r.suite.plan_fingerprint = ContentHash("plan");
  return r;
}

class ResultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ovpc_results_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ResultsTest, TheReportWrittenFromItsSummaryIsTheSameReport) {
  const SuiteResults made = MadeUpSuite((dir_ / "runs").string());
  ASSERT_EQ(made.families[0].draws.size(), 4u) << "2 grid points x 2 samples";
  const std::size_t passed = WriteReport(made, (dir_ / "a").string());
  const SuiteResults loaded = LoadSuiteResults((dir_ / "a" / "summary.json").string());
  EXPECT_EQ(WriteReport(loaded, (dir_ / "b").string()), passed);
  for (const char* file : {"junit.xml", "summary.json", "summary.md", "report.html", "runs/0.html", "runs/8.html",
                           "short_family/pass_rate.csv", "short_family/runs.csv", "short_family/pass_rate_goal_x.svg",
                           "short_family/pass_rate_post_y.svg"}) {
    const std::string a = ReadBytes(dir_ / "a" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, ReadBytes(dir_ / "b" / file)) << file;
  }
  // What the report is made from came back: the family's parameters from its text, the draws'
  // values, the runs in their order, the suite record.
  ASSERT_EQ(loaded.families.size(), 1u);
  EXPECT_EQ(loaded.families[0].family.text, FamilyText());
  EXPECT_EQ(loaded.families[0].family.parameters.size(), 2u);
  EXPECT_EQ(loaded.families[0].draws[1].values, made.families[0].draws[1].values);
  ASSERT_EQ(loaded.jobs.size(), made.jobs.size());
  EXPECT_EQ(loaded.jobs[4].error, made.jobs[4].error);
  EXPECT_EQ(loaded.jobs[6].draw->verdict, scenarios::Verdict::kViolated);
  EXPECT_EQ(loaded.suite.combinations, made.suite.combinations);
  EXPECT_EQ(loaded.suite.build, "v1-test");
  EXPECT_TRUE(loaded.suite.malformed);
  ASSERT_EQ(loaded.skipped.size(), 1u) << "the scenarios --skip-label left out";
  EXPECT_EQ(loaded.skipped[0].scenario, "long_one");
  EXPECT_EQ(loaded.skipped[0].label, "long");
  const nlohmann::json summary = nlohmann::json::parse(ReadBytes(dir_ / "a" / "summary.json"));
  EXPECT_EQ(summary["families"][0]["pass_rate_csv"], "short_family/pass_rate.csv") << "relative to the report";
  EXPECT_EQ(summary["suite"]["preset"]["hash"], ContentHash("navigator: {}\n"));
}

// Shards' result files merged: the report of the whole, byte for byte, family runs included (each
// shard's file has only its own runs' draws).
TEST_F(ResultsTest, MergedShardsGiveTheWholeReport) {
  const SuiteResults whole = MadeUpSuite((dir_ / "runs").string());
  WriteReport(whole, (dir_ / "whole").string());
  std::vector<std::string> folders;
  for (int k = 3; k >= 1; --k) {
    SuiteResults part = whole;
    part.suite.shard = k;
    part.suite.shards = 3;
    part.jobs.clear();
    for (const Job& job : whole.jobs) {
      if (static_cast<int>(job.index % 3) == k - 1) part.jobs.push_back(job);
    }
    folders.push_back((dir_ / ("shard_" + std::to_string(k))).string());
    WriteReport(part, folders.back());
  }
  EXPECT_EQ(MergeShards(folders, (dir_ / "merged").string()), kExitBadInput) << "the whole suite's: a malformed input";
  for (const char* file : {"junit.xml", "short_family/pass_rate.csv", "short_family/runs.csv", "short_family/pass_rate_post_y.svg"}) {
    EXPECT_EQ(ReadBytes(dir_ / "merged" / file), ReadBytes(dir_ / "whole" / file)) << file;
  }
  nlohmann::json merged = nlohmann::json::parse(ReadBytes(dir_ / "merged" / "summary.json"));
  EXPECT_EQ(merged["suite"]["merged_shards"], 3);
  merged["suite"]["merged_shards"] = 0;
  EXPECT_EQ(merged, nlohmann::json::parse(ReadBytes(dir_ / "whole" / "summary.json"))) << "but for the shards it was merged from";
}

TEST_F(ResultsTest, AResultFileThatCannotBeReadBackIsRefusedNamingIt) {
  const fs::path path = dir_ / "summary.json";
  const auto refusal = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      LoadSuiteResults(path.string());
    } catch (const BadInput& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(refusal("{\"runs\": [], \"passed\": 0}").find(path.string() + ": not a suite's result file of this ovpc"), std::string::npos);
  EXPECT_NE(refusal("{not json").find(path.string() + ": not a suite's result file"), std::string::npos);
  WriteReport(MadeUpSuite("runs"), dir_.string());
  nlohmann::json summary = nlohmann::json::parse(ReadBytes(path));
  summary["families"][0]["folder"] = "../elsewhere";
  EXPECT_NE(refusal(summary.dump()).find("its folder '../elsewhere' holds a '/'"), std::string::npos) << "nothing outside --out";
  summary["families"][0]["folder"] = "short_family";
  summary["families"][0]["text"] = "name: x\nparameters: [\n";
  EXPECT_NE(refusal(summary.dump()).find("the family's text does not read"), std::string::npos);
  EXPECT_THROW(LoadSuiteResults((dir_ / "missing.json").string()), BadInput);
}

std::vector<Job> JobsWithLimits(const std::vector<double>& limits) {
  std::vector<Job> jobs(limits.size());
  for (std::size_t i = 0; i < limits.size(); ++i) jobs[i].time_limit_s = limits[i];
  return jobs;
}

TEST(ShardTest, EveryRunInOneShardBalancedByTimeLimitWhateverTheListOrder) {
  const std::vector<double> limits = {8, 8, 8, 30, 3, 3, 1, 12, 8, 0};
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < limits.size(); ++i) ids.push_back("run_" + std::to_string(i));
  const std::vector<int> shard = AssignShards(JobsWithLimits(limits), ids, 3);
  std::vector<double> cost(3, 0.0);
  for (std::size_t i = 0; i < limits.size(); ++i) {
    ASSERT_GE(shard[i], 1);
    ASSERT_LE(shard[i], 3);
    cost[shard[i] - 1] += limits[i];
  }
  EXPECT_EQ(shard[3], 1) << "the longest run first, into the first shard";
  EXPECT_EQ(cost, (std::vector<double>{30, 26, 25})) << "longest first, each into the least loaded shard";
  // The same runs listed in another order land in the same shards: ties go by identity.
  std::vector<std::size_t> order(limits.size());
  std::iota(order.rbegin(), order.rend(), std::size_t{0});
  std::vector<double> reversed_limits;
  std::vector<std::string> reversed_ids;
  for (std::size_t i : order) reversed_limits.push_back(limits[i]), reversed_ids.push_back(ids[i]);
  const std::vector<int> reversed = AssignShards(JobsWithLimits(reversed_limits), reversed_ids, 3);
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(reversed[k], shard[order[k]]) << ids[order[k]];
  // Equal costs: the runs are dealt out evenly, even when the time limits are all zero.
  const std::vector<int> zero = AssignShards(JobsWithLimits(std::vector<double>(7, 0.0)), std::vector<std::string>(7, "same"), 3);
  EXPECT_EQ(std::count(zero.begin(), zero.end(), 1), 3);
  EXPECT_EQ(std::count(zero.begin(), zero.end(), 2), 2);
  EXPECT_EQ(std::count(zero.begin(), zero.end(), 3), 2);
}

TEST(ShardTest, ShardOptionIsKOfN) {
  EXPECT_EQ(ParseShard("2/3"), std::make_pair(2, 3));
  EXPECT_EQ(ParseShard("1/1"), std::make_pair(1, 1));
  for (const char* bad : {"0/3", "4/3", "3", "1/0", "-1/2", "1/2x", "a/b", "1/20000", ""}) EXPECT_THROW(ParseShard(bad), BadInput) << bad;
}

}  // namespace
}  // namespace ovpc::suite
