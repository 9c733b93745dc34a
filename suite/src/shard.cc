// Shards of a suite: each planned run in exactly one shard, balanced by expected cost; and the
// merge of the shards' result files into the report of the whole suite.
#include "shard.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>

#include "ovpc/suite/output_folder.h"
#include "ovpc/suite/runner.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

// What makes `b` another suite than `a` ("" when it is the same one): the shards of one suite are
// one build's runs of the same inputs, settings and preset, with the same planned run list.
std::string Differs(const SuiteRecord& a, const SuiteRecord& b) {
  if (a.build != b.build) return "another build (" + b.build + ", not " + a.build + ")";
  if (a.inputs != b.inputs) return "other inputs";
  if (a.seeds != b.seeds || a.first_seed != b.first_seed) return "other seeds";
  if (a.sweeps != b.sweeps || a.combinations != b.combinations) return "other sweeps";
  if (a.skip_labels != b.skip_labels) return "other --skip-label";
  if (a.map != b.map) return "another --map ('" + b.map + "', not '" + a.map + "')";
  if (a.samples != b.samples || a.family_seed != b.family_seed) return "other family draws (--samples, --family-seed)";
  if (a.preset_hash != b.preset_hash) return "another preset (" + b.preset_hash + ", not " + a.preset_hash + ")";
  if (a.shards != b.shards) return "another shard count (" + std::to_string(b.shards) + ", not " + std::to_string(a.shards) + ")";
  if (a.planned != b.planned || a.plan_fingerprint != b.plan_fingerprint) {
    return "another planned run list (" + b.plan_fingerprint + ", not " + a.plan_fingerprint + ": the input files changed?)";
  }
  return "";
}

struct Shard {
  std::string folder;
  SuiteResults results;
};

// Every folder's result file, checked to be one shard each of one suite, all of them there.
std::vector<Shard> LoadShards(const std::vector<std::string>& folders, const std::string& out) {
  std::vector<Shard> shards;
  std::map<int, std::string> by_index;
  std::error_code ec;
  for (const std::string& folder : folders) {
    const fs::path summary = fs::path(folder) / "summary.json";
    if (!fs::exists(summary, ec)) throw BadInput(folder + ": no summary.json (the shard has not finished, or this is not a suite's folder)");
    if (fs::exists(out, ec) && fs::equivalent(folder, out, ec)) throw BadInput(folder + ": is --out; merge into another folder");
    shards.push_back({folder, LoadSuiteResults(summary.string())});
    const SuiteRecord& s = shards.back().results.suite;
    const std::string k = std::to_string(s.shard) + "/" + std::to_string(s.shards);
    const std::string differs = Differs(shards.front().results.suite, s);
    if (!differs.empty()) throw BadInput(folder + ": a shard of another suite than " + shards.front().folder + ": " + differs);
    if (s.stop_signal != 0) {
      throw BadInput(folder + ": shard " + k + " was stopped by signal " + std::to_string(s.stop_signal) + " before its runs ended; run it again");
    }
    if (!by_index.emplace(s.shard, folder).second) throw BadInput(folder + ": shard " + k + " again (also " + by_index[s.shard] + ")");
  }
  const int n = shards.front().results.suite.shards;
  for (int k = 1; k <= n; ++k) {
    if (!by_index.count(k)) {
      throw BadInput("shard " + std::to_string(k) + "/" + std::to_string(n) + " is missing (given: " + std::to_string(folders.size()) +
                     " of " + std::to_string(n) + " shards, the first " + folders.front() + ")");
    }
  }
  return shards;
}

// The whole suite's results: every shard's runs in the planned order, each family draw from the
// shard that ran it.
SuiteResults Combine(std::vector<Shard>& shards) {
  SuiteResults whole;
  whole.suite = shards.front().results.suite;
  whole.suite.shard = whole.suite.shards = 1;
  whole.suite.merged = static_cast<int>(shards.size());
  whole.families = shards.front().results.families;
  whole.skipped = shards.front().results.skipped;
  std::vector<const std::string*> folder_of(whole.suite.planned, nullptr);
  for (Shard& shard : shards) {
    for (Job& job : shard.results.jobs) {
      if (folder_of[job.index] != nullptr) {
        throw BadInput(shard.folder + ": run " + std::to_string(job.index) + " is also in " + *folder_of[job.index]);
      }
      folder_of[job.index] = &shard.folder;
      if (job.draw) {
        const FamilyInput& from = shard.results.families[job.draw->family];
        whole.families[job.draw->family].draws[job.draw->draw] = from.draws[job.draw->draw];
        whole.families[job.draw->family].files[job.draw->draw] = from.files[job.draw->draw];
      }
      whole.jobs.push_back(std::move(job));
    }
  }
  for (std::size_t i = 0; i < folder_of.size(); ++i) {
    if (folder_of[i] == nullptr) throw BadInput("run " + std::to_string(i) + " of the planned runs is in none of the shards");
  }
  std::sort(whole.jobs.begin(), whole.jobs.end(), [](const Job& a, const Job& b) { return a.index < b.index; });
  return whole;
}

}  // namespace

std::vector<int> AssignShards(const std::vector<Job>& jobs, const std::vector<std::string>& ids, int shards) {
  std::vector<std::size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (jobs[a].time_limit_s != jobs[b].time_limit_s) return jobs[a].time_limit_s > jobs[b].time_limit_s;
    if (ids[a] != ids[b]) return ids[a] < ids[b];
    return a < b;
  });
  std::vector<double> cost(static_cast<std::size_t>(shards), 0.0);
  std::vector<std::size_t> runs(static_cast<std::size_t>(shards), 0);
  std::vector<int> shard_of(jobs.size(), 1);
  for (std::size_t i : order) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < cost.size(); ++k) {
      if (cost[k] < cost[best] || (cost[k] == cost[best] && runs[k] < runs[best])) best = k;
    }
    cost[best] += jobs[i].time_limit_s;
    ++runs[best];
    shard_of[i] = static_cast<int>(best) + 1;
  }
  return shard_of;
}

std::pair<int, int> ParseShard(const std::string& text) {
  int k = 0, n = 0;
  char end = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &k, &n, &end) != 2 || text.find_first_not_of("0123456789/") != std::string::npos ||
      n < 1 || n > kMaxShards || k < 1 || k > n) {
    throw BadInput("--shard must be K/N with 1 <= K <= N <= " + std::to_string(kMaxShards) + ", got '" + text + "'");
  }
  return {k, n};
}

int MergeShards(const std::vector<std::string>& folders, const std::string& out, const ReportOptions& options) {
  if (folders.empty()) throw BadInput("no shard folders to merge");
  std::vector<Shard> shards = LoadShards(folders, out);
  const SuiteResults whole = Combine(shards);
  const FolderLock lock(out);
  std::size_t passed = 0;
  try {
    passed = WriteReport(whole, out, options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ovpc merge: %s\n", e.what());
    return kExitFailure;
  }
  if (whole.suite.malformed) return kExitBadInput;
  return passed == whole.jobs.size() ? kExitOk : kExitFailure;
}

}  // namespace ovpc::suite
