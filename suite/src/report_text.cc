// What the suite's reports say of a run (report_text.h).
#include "report_text.h"

#include <algorithm>
#include <cstdio>

namespace ovpc::suite {

namespace fs = std::filesystem;
using scenarios::Verdict;

Outcome OutcomeOf(const Job& job) {
  if (!job.error.empty()) return Outcome::kError;
  if (job.draw && job.draw->verdict == Verdict::kNotCounted) return Outcome::kNotCounted;
  return Passed(job) ? Outcome::kPass : Outcome::kFail;
}

const char* OutcomeLabel(Outcome o) {
  switch (o) {
    case Outcome::kPass: return "pass";
    case Outcome::kFail: return "FAIL";
    case Outcome::kError: return "ERROR";
    case Outcome::kNotCounted: return "any";
  }
  return "?";
}

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

std::string RunSettings(const std::vector<FamilyInput>& families, const Job& job) {
  const std::string settings = SettingsLabel(job.settings);
  if (!job.draw) return settings;
  const std::string values = scenarios::DrawValuesLabel(DrawOf(families, job));
  return settings.empty() ? values : values + " " + settings;
}

std::string ExpectCell(const std::vector<FamilyInput>& families, const Job& job) {
  if (!job.draw) return "-";
  const scenarios::Draw& d = DrawOf(families, job);
  if (d.expectation == scenarios::Expectation::kAny) return "any";
  const Verdict v = job.draw->verdict;
  return std::string(scenarios::ExpectationName(d.expectation)) + ": " +
         (v == Verdict::kOk ? "ok" : v == Verdict::kViolated ? "VIOLATED" : "ERROR");
}

std::string FailureText(const Job& job) {
  const nlohmann::json& r = job.result;
  if (!r.contains("criteria")) {
    return "run failed with exit code " + std::to_string(job.exit_code) + " (see " + job.out_dir + "/run.log)\n";
  }
  std::string failures;
  for (const auto& c : r["criteria"]) {
    if (!c.value("passed", false)) {
      failures += c.value("name", std::string()) + ": expected " + c.value("expected", std::string()) + ", got " +
                  c.value("actual", std::string()) + "\n";
    }
  }
  if (r.contains("diagnosis")) failures += "diagnosis: " + r["diagnosis"].value("summary", std::string()) + "\n";
  return failures;
}

std::string DiagnosisVerdict(const Job& job) {
  const nlohmann::json& r = job.result;
  return r.contains("diagnosis") && r["diagnosis"].is_object() ? r["diagnosis"].value("verdict", std::string()) : "";
}

std::string RunName(const SuiteResults& results, const Job& job) {
  if (!job.draw) return job.scenario + " seed=" + std::to_string(job.seed);
  const scenarios::Draw& d = DrawOf(results.families, job);
  return GroupName(results.families, job) + " " + scenarios::DrawFolder(d.index) + " " + scenarios::DrawValuesLabel(d) +
         " seed=" + std::to_string(job.seed);
}

std::string GroupName(const std::vector<FamilyInput>& families, const Job& job) {
  return job.draw ? families[job.draw->family].family.name : job.scenario;
}

std::string RelativePath(const std::string& path, const fs::path& from) {
  const fs::path to = fs::absolute(path).lexically_normal();
  const fs::path rel = to.lexically_relative(fs::absolute(from).lexically_normal());
  return rel.empty() ? to.string() : rel.string();
}

std::string UrlPath(const std::string& path) {
  std::string out;
  for (char c : path) {
    const auto u = static_cast<unsigned char>(c);
    const bool plain = (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || c == '-' || c == '_' ||
                       c == '.' || c == '~' || c == '/';
    if (plain) {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "%%%02X", u);
      out += hex;
    }
  }
  return out;
}

std::vector<ScenarioGroup> ScenarioGroups(const SuiteResults& results) {
  std::vector<ScenarioGroup> groups;
  for (const Job& job : results.jobs) {
    if (job.draw) continue;
    const std::string settings = SettingsLabel(job.settings);
    auto g = std::find_if(groups.begin(), groups.end(), [&](const ScenarioGroup& x) {
      return x.scenario == job.scenario && x.map == job.map && x.settings == settings;
    });
    if (g == groups.end()) {
      ScenarioGroup fresh;
      fresh.scenario = job.scenario;
      fresh.map = job.map;
      fresh.settings = settings;
      fresh.time_limit_s = job.time_limit_s;
      g = groups.insert(groups.end(), fresh);
    }
    ++g->runs;
    if (!Passed(job)) {
      g->failed_seeds.push_back(job.seed);
      continue;
    }
    ++g->passed;
    const double t = job.result.value("sim_time_s", 0.0);
    g->goal_min_s = g->arrived == 0 ? t : std::min(g->goal_min_s, t);
    g->goal_max_s = g->arrived == 0 ? t : std::max(g->goal_max_s, t);
    g->goal_sum_s += t;
    ++g->arrived;
  }
  return groups;
}

std::vector<FamilyCounts> FamilyTotals(const SuiteResults& results) {
  std::vector<FamilyCounts> totals;
  for (const FamilyInput& in : results.families) totals.push_back({in.family.name});
  for (const Job& job : results.jobs) {
    if (!job.draw) continue;
    FamilyCounts& c = totals[job.draw->family];
    const bool ok = job.draw->verdict == Verdict::kOk;
    c.errors += !job.error.empty();
    switch (DrawOf(results.families, job).expectation) {
      case scenarios::Expectation::kPass: ++c.pass_runs; c.pass_ok += ok; break;
      case scenarios::Expectation::kRefuse: ++c.refuse_runs; c.refuse_ok += ok; break;
      case scenarios::Expectation::kAny: ++c.any_runs; break;
    }
  }
  return totals;
}

std::string Rate(std::size_t ok, std::size_t runs) {
  if (runs == 0) return "-";
  char text[64];
  std::snprintf(text, sizeof(text), "%zu/%zu (%.0f %%)", ok, runs, 100.0 * static_cast<double>(ok) / static_cast<double>(runs));
  return text;
}

}  // namespace ovpc::suite
