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

// Text for XML: the five special characters as entities, and the control characters XML 1.0
// cannot hold (all below 0x20 but tab, line feed and carriage return) as "\xNN".
std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        if ((u < 0x20 && c != '\t' && c != '\n' && c != '\r') || u == 0x7f) {
          char hex[8];
          std::snprintf(hex, sizeof(hex), "\\x%02X", u);
          out += hex;
        } else {
          out += c;
        }
    }
  }
  return out;
}

const scenarios::Draw& DrawOf(const std::vector<FamilyInput>& families, const Job& job) {
  return families[job.draw->family].draws[job.draw->draw];
}
const std::string& DrawFile(const std::vector<FamilyInput>& families, const Job& job) {
  return families[job.draw->family].files[job.draw->draw];
}

// The settings column: a family run's drawn values, then the sweep's settings.
std::string RunSettings(const Report& rep, const Job& job) {
  const std::string settings = SettingsLabel(job.settings);
  if (!job.draw) return settings;
  const std::string values = scenarios::DrawValuesLabel(DrawOf(rep.families, job));
  return settings.empty() ? values : values + " " + settings;
}

std::string ExpectCell(const Report& rep, const Job& job) {
  if (!job.draw) return "-";
  const scenarios::Draw& d = DrawOf(rep.families, job);
  if (d.expectation == scenarios::Expectation::kAny) return "any";
  const Verdict v = job.draw->verdict;
  return std::string(scenarios::ExpectationName(d.expectation)) + ": " +
         (v == Verdict::kOk ? "ok" : v == Verdict::kViolated ? "VIOLATED" : "ERROR");
}

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
    if (families) std::snprintf(expect, sizeof(expect), "%-16s ", ExpectCell(rep, job).c_str());
    std::printf("%-22s %-5llu %-9s %-34s %-6s %s%9.1f %9.1f %7.1f  %s\n", job.scenario.c_str(),
                static_cast<unsigned long long>(job.seed), job.map.c_str(), RunSettings(rep, job).c_str(),
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

std::string FailureText(const Job& job) {
  const nlohmann::json& r = job.result;
  std::string failures;
  if (!r.contains("criteria")) return "run failed with exit code " + std::to_string(job.exit_code) + " (see " + job.out_dir + "/run.log)\n";
  for (const auto& c : r["criteria"]) {
    if (!c.value("passed", false)) {
      failures += c.value("name", std::string()) + ": expected " + c.value("expected", std::string()) + ", got " +
                  c.value("actual", std::string()) + "\n";
    }
  }
  if (r.contains("diagnosis")) failures += "diagnosis: " + r["diagnosis"].value("summary", std::string()) + "\n";
  return failures;
}

// One testcase's verdict element ("" when it passed).
std::string CaseOutcome(const Report& rep, const Job& job) {
  std::ostringstream x;
  if (!job.error.empty()) {
    x << "      <error message=\"" << XmlEscape(job.error.substr(0, job.error.find('\n'))) << "\">" << XmlEscape(job.error)
      << "</error>\n";
  } else if (job.draw && job.draw->verdict == Verdict::kNotCounted) {
    x << "      <skipped message=\"" << XmlEscape("expect any: " + DrawOf(rep.families, job).reason) << "\"/>\n";
  } else if (job.draw && job.draw->verdict == Verdict::kViolated) {
    const std::string& file = DrawFile(rep.families, job);
    const scenarios::Expectation e = DrawOf(rep.families, job).expectation;
    const std::string what = e == scenarios::Expectation::kPass ? "pass" : "refuse (no collision, no forbidden region entered)";
    x << "      <failure message=\"" << XmlEscape("expected " + what + ", violated: " + file) << "\">"
      << XmlEscape(FailureText(job) + "re-run: ovpc run " + file + " --seed " + std::to_string(job.seed) + "\n") << "</failure>\n";
  } else if (!job.draw && job.exit_code != 0) {
    const std::string failures = FailureText(job);
    x << "      <failure message=\"" << XmlEscape(failures.substr(0, failures.find('\n'))) << "\">" << XmlEscape(failures)
      << "</failure>\n";
  }
  return x.str();
}

std::string CaseName(const Report& rep, const Job& job) {
  const std::string settings = " map=" + job.map + (job.settings.empty() ? "" : " " + SettingsLabel(job.settings));
  if (!job.draw) return "seed=" + std::to_string(job.seed) + settings;
  const scenarios::Draw& d = DrawOf(rep.families, job);
  return scenarios::DrawFolder(d.index) + " seed=" + std::to_string(job.seed) + " " + scenarios::DrawValuesLabel(d) + settings +
         " (expect " + scenarios::ExpectationName(d.expectation) + ")";
}

void WriteJunit(const Report& rep, std::size_t passed) {
  std::ostringstream cases;
  double total_wall = 0.0;
  std::size_t errors = 0, skipped = 0;
  for (const Job& job : rep.jobs) {
    const double wall = job.result.value("wall_time_s", 0.0);
    total_wall += wall;
    errors += !job.error.empty();
    skipped += job.draw && job.draw->verdict == Verdict::kNotCounted;
    const std::string classname = job.draw ? rep.families[job.draw->family].family.name : job.scenario;
    cases << "    <testcase classname=\"" << XmlEscape(classname) << "\" name=\"" << XmlEscape(CaseName(rep, job))
          << "\" time=\"" << wall << "\">\n"
          << CaseOutcome(rep, job) << "    </testcase>\n";
  }
  std::ostringstream junit;
  junit << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ovpc scenarios\" tests=\""
        << rep.jobs.size() << "\" failures=\"" << rep.jobs.size() - passed - errors << "\" errors=\"" << errors
        << "\" skipped=\"" << skipped << "\" time=\"" << total_wall << "\">\n"
        << cases.str() << "  </testsuite>\n</testsuites>\n";
  WriteFile(fs::path(rep.out) / "junit.xml", junit.str());
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

std::size_t WriteReport(const SuiteResults& results, const std::string& out) {
  const Report rep{results, results.jobs, results.families, out};
  PrintRuns(rep);
  if (results.suite.seeds > 1) PrintSeeds(rep);
  if (!results.suite.sweeps.empty()) PrintSweeps(rep);
  fs::create_directories(rep.out);
  FamilyReports(rep);
  const std::size_t passed = std::count_if(rep.jobs.begin(), rep.jobs.end(), Passed);
  WriteJunit(rep, passed);
  WriteSummary(rep, passed);
  std::size_t family_runs = 0, not_counted = 0;
  for (const Job& job : rep.jobs) {
    family_runs += job.draw.has_value();
    not_counted += job.draw && job.draw->verdict == Verdict::kNotCounted;
  }
  std::printf("\n%zu of %zu runs passed", passed, rep.jobs.size());
  if (family_runs > 0) std::printf(" (a family run passes when its expectation holds; %zu not counted)", not_counted);
  std::printf("; wrote %s/junit.xml and %s/summary.json\n", rep.out.c_str(), rep.out.c_str());
  return passed;
}

}  // namespace ovpc::suite
