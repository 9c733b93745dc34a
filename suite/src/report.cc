// A suite's reports: the tables it prints, junit.xml, summary.json and the families' pass rates.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ovpc/scenarios/pass_rate.h"
#include "ovpc/suite/output_folder.h"
#include "ovpc/suite/report.h"
#include "report_files.h"
#include "report_text.h"
#include "results.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;
using scenarios::Verdict;

struct Report {
  const SuiteResults& results;
  const std::vector<Job>& jobs;
  const std::vector<FamilyInput>& families;
  std::string out;
};

void PrintRuns(const Report& rep) {
  const bool families = !rep.families.empty();
  std::printf("%-22s %-5s %-9s %-34s %-6s %s%9s %9s %7s  %s\n", "scenario", "seed", "map", families ? "values, settings" : "settings",
              "result", families ? "expect: verdict  " : "", "sim [s]", "dist [m]", "RTF", "end");
  for (const Job& job : rep.jobs) {
    const nlohmann::json& r = job.result;
    const bool ok = job.exit_code == 0 && job.error.empty();
    std::string end = job.error.empty() ? r.value("end_reason", std::string("exit code ") + std::to_string(job.exit_code))
                                        : job.error;
    // Why a failed run did not arrive: stalled, rocking or still driving (scenarios/diagnosis.h).
    const std::string verdict = r.contains("diagnosis") ? r["diagnosis"].value("verdict", std::string()) : "";
    if (!ok && !verdict.empty() && verdict != "arrived") end += " (" + verdict + ")";
    char expect[40] = "";
    if (families) std::snprintf(expect, sizeof(expect), "%-16s ", ExpectCell(rep.families, job).c_str());
    std::printf("%-22s %-5llu %-9s %-34s %-6s %s%9.1f %9.1f %7.1f  %s\n", job.scenario.c_str(),
                static_cast<unsigned long long>(job.seed), job.map.c_str(), RunSettings(rep.families, job).c_str(),
                ok ? "pass" : job.error.empty() ? "FAIL" : "ERROR", expect, r.value("sim_time_s", 0.0),
                r.value("distance_m", 0.0), r.value("real_time_factor", 0.0), end.c_str());
  }
}

// With several seeds: per scenario and settings, the pass rate, the failing seeds and the spread
// of the passing runs' times (a single run is one sample of a chaotic closed loop).
void PrintSeeds(const Report& rep) {
  std::printf("\n%-22s %-9s %-34s %7s %-18s %17s %9s\n", "scenario", "map", "settings", "passed", "failed seeds",
              "passing sim [s]", "mean RTF");
  struct Group {
    std::string first, map;
    std::vector<std::string> second;
    bool operator==(const Group& o) const { return first == o.first && map == o.map && second == o.second; }
  };
  std::vector<Group> groups;
  for (const Job& job : rep.jobs) {
    const Group g{job.scenario, job.map, job.settings};
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  for (const auto& g : groups) {
    int n = 0, ok = 0;
    double lo = 0.0, hi = 0.0, rtf = 0.0;
    std::string failed;
    for (const Job& job : rep.jobs) {
      if (job.scenario != g.first || job.map != g.map || job.settings != g.second) continue;
      ++n;
      rtf += job.result.value("real_time_factor", 0.0);
      if (!Passed(job)) {
        failed += (failed.empty() ? "" : ",") + std::to_string(job.seed);
        continue;
      }
      const double t = job.result.value("sim_time_s", 0.0);
      lo = ok == 0 ? t : std::min(lo, t);
      hi = ok == 0 ? t : std::max(hi, t);
      ++ok;
    }
    char range[40] = "-";
    if (ok > 0) std::snprintf(range, sizeof(range), "%.1f-%.1f", lo, hi);
    std::printf("%-22s %-9s %-34s %3d/%-3d %-18s %17s %9.1f\n", g.first.c_str(), g.map.c_str(), SettingsLabel(g.second).c_str(), ok, n,
                failed.empty() ? "-" : failed.c_str(), range, rtf / n);
  }
}

// Sweep table: pass rate and mean figures per combination of values.
void PrintSweeps(const Report& rep) {
  std::printf("\nsweep: %-40s %6s %12s %12s\n", "settings", "passed", "mean sim [s]", "mean dist [m]");
  for (const auto& combo : rep.results.suite.combinations) {
    int n = 0, ok = 0;
    double sim_s = 0.0, dist = 0.0;
    for (const Job& job : rep.jobs) {
      if (job.settings != combo) continue;
      ++n;
      ok += Passed(job);
      sim_s += job.result.value("sim_time_s", 0.0);
      dist += job.result.value("distance_m", 0.0);
    }
    if (n == 0) continue;
    std::printf("       %-40s %3d/%-3d %12.1f %12.1f\n", SettingsLabel(combo).c_str(), ok, n, sim_s / n, dist / n);
  }
}

// Whole or not at all; a failure ends the report with exit 1 naming the file.
void WriteFile(const fs::path& path, const std::string& text) { WriteFileAtomic(path, text); }

std::string RunsCsv(const Report& rep, std::size_t f) {
  std::string csv = "draw,seed,settings,expectation,verdict,scenario_file,out";
  for (const scenarios::Parameter& p : rep.families[f].family.parameters) csv += "," + CsvField(p.name);
  csv += "\n";
  for (const Job& job : rep.jobs) {
    if (!job.draw || job.draw->family != f) continue;
    const scenarios::Draw& d = DrawOf(rep.families, job);
    csv += std::to_string(d.index) + "," + std::to_string(job.seed) + "," + CsvField(SettingsLabel(job.settings)) + "," +
           scenarios::ExpectationName(d.expectation) + "," + scenarios::VerdictName(job.draw->verdict) + "," +
           CsvField(DrawFile(rep.families, job)) + "," + CsvField(job.out_dir);
    for (const auto& [name, v] : d.values) csv += "," + CsvField(v.ToString());
    csv += "\n";
  }
  return csv;
}

// Per family: the pass-rate table of every parameter, printed and written with its plot.
void FamilyReports(const Report& rep) {
  for (std::size_t f = 0; f < rep.families.size(); ++f) {
    const FamilyInput& in = rep.families[f];
    const std::string dir = (fs::path(rep.out) / in.folder).string();
    MakeFolder(dir);
    std::vector<scenarios::JudgedRun> runs;
    for (const Job& job : rep.jobs) {
      if (job.draw && job.draw->family == f) {
        const scenarios::Draw& d = DrawOf(rep.families, job);
        runs.push_back({d.values, d.expectation, job.draw->verdict});
      }
    }
    std::vector<scenarios::PassRateTable> tables;
    for (const scenarios::Parameter& p : in.family.parameters) {
      tables.push_back(scenarios::TabulatePassRate(p, runs));
      std::printf("\n%s", scenarios::FormatPassRateTable(in.family.name, tables.back()).c_str());
      std::string name = p.name;
      std::replace(name.begin(), name.end(), '/', '_');
      WriteFile(fs::path(dir) / ("pass_rate_" + name + ".svg"), scenarios::PassRateSvg(in.family.name, tables.back()));
    }
    WriteFile(fs::path(dir) / "pass_rate.csv", scenarios::PassRateCsv(tables));
    WriteFile(fs::path(dir) / "runs.csv", RunsCsv(rep, f));
    std::printf("wrote %s/pass_rate.csv, runs.csv and pass_rate_<parameter>.svg\n", dir.c_str());
  }
}

void WriteCiFiles(const Report& rep, const ReportOptions& options) {
  WriteFile(fs::path(rep.out) / "junit.xml", JunitXml(rep.results, rep.out, options.junit_absolute_paths));
  WriteFile(fs::path(rep.out) / "summary.md", SummaryMarkdown(rep.results));
}

void WriteSummary(const Report& rep, std::size_t passed) {
  // Names are any bytes a file held: invalid UTF-8 is replaced, not thrown on.
  WriteFile(fs::path(rep.out) / "summary.json",
            SummaryJson(rep.results, passed).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace

bool Passed(const Job& job) {
  if (!job.error.empty()) return false;
  if (job.draw) return job.draw->verdict == Verdict::kOk || job.draw->verdict == Verdict::kNotCounted;
  return job.exit_code == 0;
}

std::string SettingsLabel(const std::vector<std::string>& settings) {
  std::string s;
  for (const auto& kv : settings) s += (s.empty() ? "" : " ") + kv;
  return s;
}

nlohmann::json DrawJson(const std::vector<FamilyInput>& families, const DrawRun& run) {
  const FamilyInput& in = families[run.family];
  const scenarios::Draw& d = in.draws[run.draw];
  nlohmann::json values = nlohmann::json::object();
  for (const auto& [name, v] : d.values) values[name] = v.is_number ? nlohmann::json(v.number) : nlohmann::json(v.word);
  return {{"family", in.family.name},
          {"family_file", in.family.path},
          {"draw", d.index},
          {"scenario_file", in.files[run.draw]},
          {"values", values},
          {"expectation", scenarios::ExpectationName(d.expectation)},
          {"reason", d.reason},
          {"verdict", scenarios::VerdictName(run.verdict)}};
}

std::size_t WriteReport(const SuiteResults& results, const std::string& out, const ReportOptions& options) {
  const Report rep{results, results.jobs, results.families, out};
  PrintRuns(rep);
  if (results.suite.seeds > 1) PrintSeeds(rep);
  if (!results.suite.sweeps.empty()) PrintSweeps(rep);
  fs::create_directories(rep.out);
  FamilyReports(rep);
  const std::size_t passed = std::count_if(rep.jobs.begin(), rep.jobs.end(), Passed);
  WriteCiFiles(rep, options);
  WriteHtmlReport(results, out);
  WriteSummary(rep, passed);
  std::size_t family_runs = 0, not_counted = 0;
  for (const Job& job : rep.jobs) {
    family_runs += job.draw.has_value();
    not_counted += job.draw && job.draw->verdict == Verdict::kNotCounted;
  }
  std::printf("\n%zu of %zu runs passed", passed, rep.jobs.size());
  if (family_runs > 0) std::printf(" (a family run passes when its expectation holds; %zu not counted)", not_counted);
  std::printf("; wrote %s/report.html, junit.xml, summary.md and summary.json\n", rep.out.c_str());
  return passed;
}

}  // namespace ovpc::suite
