// junit.xml as CI systems render it (GitLab, Jenkins, Azure): a testcase per run with the scenario
// file, its properties, the failed criteria and diagnosis, attachments; and summary.md, a Markdown
// summary of the suite (a GitHub job summary).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "report_files.h"
#include "report_text.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;
using scenarios::Verdict;

std::string Attr(const std::string& name, const std::string& value) { return " " + name + "=\"" + XmlEscape(value) + "\""; }

std::string Property(const std::string& name, const std::string& value) {
  return "        <property" + Attr("name", name) + Attr("value", value) + "/>\n";
}

std::string CaseName(const SuiteResults& r, const Job& job) {
  const std::string settings = " map=" + job.map + (job.settings.empty() ? "" : " " + SettingsLabel(job.settings));
  if (!job.draw) return "seed=" + std::to_string(job.seed) + settings;
  const scenarios::Draw& d = DrawOf(r.families, job);
  return scenarios::DrawFolder(d.index) + " seed=" + std::to_string(job.seed) + " " + scenarios::DrawValuesLabel(d) + settings +
         " (expect " + scenarios::ExpectationName(d.expectation) + ")";
}

// The file a CI system links the testcase to: the scenario file, or a family run's family file.
std::string CaseFile(const SuiteResults& r, const Job& job) {
  return job.draw ? r.families[job.draw->family].family.path : job.file;
}

// seed, map, settings, commit; a family run's family, draw, drawn file, expectation and values.
std::string CaseProperties(const SuiteResults& r, const Job& job) {
  std::string p = Property("seed", std::to_string(job.seed)) + Property("map", job.map);
  if (!job.settings.empty()) p += Property("settings", SettingsLabel(job.settings));
  p += Property("commit", r.suite.build);
  p += Property("scenario_file", job.draw ? DrawFile(r.families, job) : job.file);
  if (job.draw) {
    const scenarios::Draw& d = DrawOf(r.families, job);
    p += Property("family", r.families[job.draw->family].family.name) + Property("draw", scenarios::DrawFolder(d.index)) +
         Property("expectation", scenarios::ExpectationName(d.expectation)) +
         Property("verdict", scenarios::VerdictName(job.draw->verdict));
    for (const auto& [name, v] : d.values) p += Property("value." + name, v.ToString());
  }
  if (!DiagnosisVerdict(job).empty()) p += Property("diagnosis", DiagnosisVerdict(job));
  return "      <properties>\n" + p + "      </properties>\n";
}

// One testcase's verdict element ("" when it passed).
std::string CaseOutcome(const SuiteResults& r, const Job& job) {
  std::ostringstream x;
  const Outcome o = OutcomeOf(job);
  if (o == Outcome::kError) {
    x << "      <error" << Attr("message", job.error.substr(0, job.error.find('\n'))) << Attr("type", "error") << ">"
      << XmlEscape(job.error) << "</error>\n";
  } else if (o == Outcome::kNotCounted) {
    x << "      <skipped" << Attr("message", "expect any: " + DrawOf(r.families, job).reason) << "/>\n";
  } else if (o == Outcome::kFail && job.draw) {
    const std::string& file = DrawFile(r.families, job);
    const scenarios::Expectation e = DrawOf(r.families, job).expectation;
    const std::string what = e == scenarios::Expectation::kPass ? "pass" : "refuse (no collision, no forbidden region entered)";
    x << "      <failure" << Attr("message", "expected " + what + ", violated: " + file) << Attr("type", "violated") << ">"
      << XmlEscape(FailureText(job) + "re-run: ovpc run " + file + " --seed " + std::to_string(job.seed) + "\n") << "</failure>\n";
  } else if (o == Outcome::kFail) {
    const std::string failures = FailureText(job);
    x << "      <failure" << Attr("message", failures.substr(0, failures.find('\n'))) << Attr("type", "failed") << ">"
      << XmlEscape(failures + "re-run: ovpc run " + job.file + " --seed " + std::to_string(job.seed) + "\n") << "</failure>\n";
  }
  return x.str();
}

// [[ATTACHMENT|path]] lines for the run's top-down picture and MCAP log, where they were written.
std::string CaseAttachments(const Job& job, const std::string& out, bool absolute) {
  std::string lines;
  for (const char* name : {"topdown.png", "run.mcap"}) {
    const fs::path file = fs::path(job.out_dir) / name;
    std::error_code ec;
    if (job.out_dir.empty() || !fs::is_regular_file(file, ec)) continue;
    const std::string path = absolute ? fs::absolute(file).lexically_normal().string() : RelativePath(file.string(), out);
    lines += "[[ATTACHMENT|" + path + "]]\n";
  }
  if (lines.empty()) return "";
  return "      <system-out>" + XmlEscape(lines) + "</system-out>\n";
}

std::string SkippedCase(const SuiteResults& r, const SkippedRun& s) {
  return "    <testcase" + Attr("classname", s.scenario) + Attr("name", "skipped (label " + s.label + ")") + Attr("file", s.file) +
         " time=\"0\">\n      <properties>\n" + Property("commit", r.suite.build) + Property("label", s.label) +
         "      </properties>\n      <skipped" + Attr("message", "left out by --skip-label " + s.label) + "/>\n    </testcase>\n";
}

}  // namespace

std::string JunitXml(const SuiteResults& r, const std::string& out, bool absolute_paths) {
  std::ostringstream cases;
  double total_wall = 0.0;
  std::size_t errors = 0, failures = 0, skipped = r.skipped.size();
  for (const Job& job : r.jobs) {
    const double wall = job.result.value("wall_time_s", 0.0);
    const Outcome o = OutcomeOf(job);
    total_wall += wall;
    errors += o == Outcome::kError;
    failures += o == Outcome::kFail;
    skipped += o == Outcome::kNotCounted;
    cases << "    <testcase" << Attr("classname", GroupName(r.families, job)) << Attr("name", CaseName(r, job))
          << Attr("file", CaseFile(r, job)) << " time=\"" << wall << "\">\n"
          << CaseProperties(r, job) << CaseOutcome(r, job) << CaseAttachments(job, out, absolute_paths) << "    </testcase>\n";
  }
  for (const SkippedRun& s : r.skipped) cases << SkippedCase(r, s);
  std::ostringstream junit;
  junit << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"ovpc scenarios\" tests=\""
        << r.jobs.size() + r.skipped.size() << "\" failures=\"" << failures << "\" errors=\"" << errors << "\" skipped=\""
        << skipped << "\" time=\"" << total_wall << "\">\n"
        << cases.str() << "  </testsuite>\n</testsuites>\n";
  return junit.str();
}

std::string MarkdownCell(const std::string& text) {
  std::string trimmed = text;
  while (!trimmed.empty() && (trimmed.back() == '\n' || trimmed.back() == '\r' || trimmed.back() == ' ')) trimmed.pop_back();
  std::string out;
  for (char c : trimmed) {
    if (c == '|') {
      out += "\\|";
    } else if (c == '\n') {
      out += "<br>";
    } else if (c != '\r') {
      out += c;
    }
  }
  return out;
}

}  // namespace ovpc::suite
