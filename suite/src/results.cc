// summary.json, the suite's result file: written from a suite's results, and read back into them, so
// that a report can be made again (or merged from shards) from the result files alone.
#include "results.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ovpc/suite/errors.h"
#include "ovpc/suite/output_folder.h"
#include "ovpc/suite/runner.h"

#ifndef OVPC_BUILD_ID
#define OVPC_BUILD_ID "unknown"
#endif

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The version of summary.json's layout: a file without it was written before the suite record.
constexpr int kSummaryFormat = 1;

json RecordJson(const SuiteRecord& s) {
  return {{"inputs", s.inputs},
          {"seeds", s.seeds},
          {"first_seed", s.first_seed},
          {"sweeps", s.sweeps},
          {"combinations", s.combinations},
          {"skip_labels", s.skip_labels},
          {"map", s.map},
          {"samples", s.samples},
          {"family_seed", s.family_seed},
          {"preset", {{"file", s.preset_file}, {"hash", s.preset_hash}}},
          {"build", s.build},
          {"shard", {{"index", s.shard}, {"count", s.shards}}},
          {"plan", {{"runs", s.planned}, {"fingerprint", s.plan_fingerprint}}},
          {"malformed_inputs", s.malformed},
          {"stop_signal", s.stop_signal},
          {"merged_shards", s.merged}};
}

SuiteRecord RecordFrom(const json& j) {
  SuiteRecord s;
  s.inputs = j.at("inputs").get<std::vector<std::string>>();
  s.seeds = j.at("seeds").get<int>();
  s.first_seed = j.at("first_seed").get<int>();
  s.sweeps = j.at("sweeps").get<std::vector<std::string>>();
  s.combinations = j.at("combinations").get<std::vector<std::vector<std::string>>>();
  s.skip_labels = j.at("skip_labels").get<std::vector<std::string>>();
  s.map = j.at("map").get<std::string>();
  s.samples = j.at("samples").get<long long>();
  s.family_seed = j.at("family_seed").get<std::uint64_t>();
  s.preset_file = j.at("preset").at("file").get<std::string>();
  s.preset_hash = j.at("preset").at("hash").get<std::string>();
  s.build = j.at("build").get<std::string>();
  s.shard = j.at("shard").at("index").get<int>();
  s.shards = j.at("shard").at("count").get<int>();
  s.planned = j.at("plan").at("runs").get<std::size_t>();
  s.plan_fingerprint = j.at("plan").at("fingerprint").get<std::string>();
  s.malformed = j.at("malformed_inputs").get<bool>();
  s.stop_signal = j.at("stop_signal").get<int>();
  s.merged = j.at("merged_shards").get<int>();
  if (s.shards < 1 || s.shard < 1 || s.shard > s.shards) throw BadInput("shard " + std::to_string(s.shard) + "/" + std::to_string(s.shards) + " is not a shard");
  return s;
}

json RunJson(const SuiteResults& r, const Job& job) {
  json run = {{"index", job.index},   {"scenario", job.scenario}, {"file", job.file},         {"seed", job.seed},
              {"map", job.map},       {"settings", job.settings}, {"passed", Passed(job)},    {"exit_code", job.exit_code},
              {"out", job.out_dir},   {"result", job.result},     {"time_limit_s", job.time_limit_s}};
  if (!job.error.empty()) run["error"] = job.error;
  if (job.draw) {
    run["family"] = DrawJson(r.families, *job.draw);
    run["family_index"] = job.draw->family;
    run["draw_position"] = job.draw->draw;
  }
  return run;
}

template <typename Enum>
Enum FromName(const std::string& name, std::initializer_list<Enum> all, const char* (*name_of)(Enum), const char* what) {
  for (Enum e : all) {
    if (name == name_of(e)) return e;
  }
  throw BadInput("unknown " + std::string(what) + " '" + name + "'");
}

// A family run's draw, as its run record has it, put back into its family.
DrawRun DrawFrom(const json& run, const std::string& scenario, std::vector<FamilyInput>& families) {
  using scenarios::Expectation;
  using scenarios::Verdict;
  const json& f = run.at("family");
  const auto fi = run.at("family_index").get<std::size_t>();
  const auto di = run.at("draw_position").get<std::size_t>();
  if (fi >= families.size() || di >= families[fi].draws.size()) {
    throw BadInput("run " + std::to_string(run.at("index").get<std::size_t>()) + ": its family or draw is not among the families");
  }
  FamilyInput& in = families[fi];
  scenarios::Draw& d = in.draws[di];
  d.index = f.at("draw").get<std::size_t>();
  d.name = scenario;
  d.expectation = FromName(f.at("expectation").get<std::string>(), {Expectation::kPass, Expectation::kRefuse, Expectation::kAny},
                           scenarios::ExpectationName, "expectation");
  d.reason = f.at("reason").get<std::string>();
  d.values.clear();
  for (const scenarios::Parameter& p : in.family.parameters) {
    const json& v = f.at("values").at(p.name);
    d.values.emplace_back(p.name, v.is_number() ? scenarios::Value::Number(v.get<double>()) : scenarios::Value::Word(v.get<std::string>()));
  }
  in.files[di] = f.at("scenario_file").get<std::string>();
  return {fi, di,
          FromName(f.at("verdict").get<std::string>(), {Verdict::kOk, Verdict::kViolated, Verdict::kNotCounted, Verdict::kError},
                   scenarios::VerdictName, "verdict")};
}

Job JobFrom(const json& run, std::vector<FamilyInput>& families) {
  Job job;
  job.index = run.at("index").get<std::size_t>();
  job.scenario = run.at("scenario").get<std::string>();
  job.file = run.at("file").get<std::string>();
  job.seed = run.at("seed").get<std::uint64_t>();
  job.map = run.at("map").get<std::string>();
  job.settings = run.at("settings").get<std::vector<std::string>>();
  job.exit_code = run.at("exit_code").get<int>();
  job.out_dir = run.at("out").get<std::string>();
  job.result = run.at("result");
  job.time_limit_s = run.at("time_limit_s").get<double>();
  job.error = run.value("error", std::string());
  if (run.contains("family")) job.draw = DrawFrom(run, job.scenario, families);
  return job;
}

FamilyInput FamilyFrom(const json& j) {
  FamilyInput in;
  const std::string file = j.at("file").get<std::string>();
  try {
    in.family = scenarios::ParseFamily(j.at("text").get<std::string>(), file);
  } catch (const scenarios::ScenarioError& e) {
    throw BadInput("the family's text does not read: " + std::string(e.what()));
  }
  if (in.family.name != j.at("name").get<std::string>()) throw BadInput("family " + file + ": its text names another family");
  in.folder = j.at("folder").get<std::string>();
  std::string why;
  if (!IsSafeComponent(in.folder, &why)) throw BadInput("family " + file + ": its folder '" + in.folder + "' " + why);
  const auto draws = j.at("draws").get<std::size_t>();
  if (draws > kMaxRuns) throw BadInput("family " + file + ": " + std::to_string(draws) + " draws");
  in.draws.resize(draws);
  in.files.resize(draws);
  return in;
}

SuiteResults ResultsFrom(const json& j) {
  if (!j.is_object() || !j.contains("suite") || j.value("format", 0) != kSummaryFormat) {
    throw BadInput("not a suite's result file of this ovpc (no suite record of format " + std::to_string(kSummaryFormat) +
                   "): run the suite again with this ovpc");
  }
  SuiteResults r;
  r.suite = RecordFrom(j.at("suite"));
  if (j.contains("families")) {
    for (const json& f : j.at("families")) r.families.push_back(FamilyFrom(f));
  }
  for (const json& run : j.at("runs")) r.jobs.push_back(JobFrom(run, r.families));
  if (j.contains("skipped")) {
    for (const json& s : j.at("skipped")) {
      r.skipped.push_back({s.at("file").get<std::string>(), s.at("scenario").get<std::string>(), s.at("label").get<std::string>()});
    }
  }
  for (std::size_t i = 1; i < r.jobs.size(); ++i) {
    if (r.jobs[i].index <= r.jobs[i - 1].index) throw BadInput("the runs are not in the planned order");
  }
  if (!r.jobs.empty() && r.jobs.back().index >= r.suite.planned) throw BadInput("a run's index is past the planned runs");
  return r;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// `path` relative to the suite's folder when it lies inside (OUT/...): the same in every shard.
std::string UnderOut(const std::string& path, const std::string& out) {
  const std::string prefix = (fs::path(out) / "").string();
  return path.compare(0, prefix.size(), prefix) == 0 ? "OUT/" + path.substr(prefix.size()) : path;
}

}  // namespace

json SummaryJson(const SuiteResults& r, std::size_t passed) {
  json runs = json::array();
  std::size_t errors = 0;
  for (const Job& job : r.jobs) {
    runs.push_back(RunJson(r, job));
    errors += !job.error.empty();
  }
  json families = json::array();
  for (const FamilyInput& in : r.families) {
    families.push_back({{"name", in.family.name}, {"file", in.family.path}, {"text", in.family.text}, {"draws", in.draws.size()},
                        {"folder", in.folder}, {"pass_rate_csv", in.folder + "/pass_rate.csv"}});
  }
  json summary = {{"format", kSummaryFormat}, {"suite", RecordJson(r.suite)}, {"runs", runs},
                  {"passed", passed},         {"errors", errors},             {"total", r.jobs.size()}};
  if (!r.families.empty()) summary["families"] = families;
  if (!r.skipped.empty()) {
    json skipped = json::array();
    for (const SkippedRun& s : r.skipped) skipped.push_back({{"file", s.file}, {"scenario", s.scenario}, {"label", s.label}});
    summary["skipped"] = skipped;
  }
  return summary;
}

SuiteResults LoadSuiteResults(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path)) throw BadInput(path + ": cannot read it");
  try {
    return ResultsFrom(json::parse(in));
  } catch (const BadInput& e) {
    throw BadInput(path + ": " + e.what());
  } catch (const json::exception& e) {
    throw BadInput(path + ": not a suite's result file: " + std::string(e.what()));
  }
}

std::string BuildId() { return OVPC_BUILD_ID; }

std::string ContentHash(const std::string& text) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (unsigned char c : text) h = (h ^ c) * 0x100000001B3ULL;
  char hex[32];
  std::snprintf(hex, sizeof(hex), "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return hex;
}

std::string RunIdentity(const Job& job, const std::vector<FamilyInput>& families, const std::string& out) {
  std::string what = UnderOut(job.file, out);
  if (job.draw) {
    const FamilyInput& in = families[job.draw->family];
    what = in.family.path + "#" + scenarios::DrawFolder(in.draws[job.draw->draw].index);
  }
  return what + "|" + job.scenario + "|seed=" + std::to_string(job.seed) + "|" + SettingsLabel(job.settings) + "|map=" + job.map +
         "|" + UnderOut(job.out_dir, out);
}

std::string PlanFingerprint(const std::vector<std::string>& files, const std::vector<FamilyInput>& families,
                            const std::vector<Job>& jobs, const std::vector<std::string>& ids) {
  std::string text;
  for (const std::string& f : files) text += "file " + f + " " + ContentHash(ReadText(f)) + "\n";
  for (const FamilyInput& in : families) text += "family " + in.family.path + " " + ContentHash(in.family.text) + "\n";
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    char limit[40];
    std::snprintf(limit, sizeof(limit), "%.17g", jobs[i].time_limit_s);
    text += "run " + ids[i] + " " + limit + (jobs[i].error.empty() ? "" : " malformed") + "\n";
  }
  return ContentHash(text);
}

}  // namespace ovpc::suite
