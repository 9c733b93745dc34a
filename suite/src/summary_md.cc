// summary.md: the suite in Markdown, short enough for a CI job's summary page (GitHub's
// $GITHUB_STEP_SUMMARY): the counts, the runs that did not pass and why, the pass rates.
#include <cstdio>
#include <sstream>

#include "report_files.h"
#include "report_text.h"

namespace ovpc::suite {
namespace {

// At most this many runs that did not pass are listed (report.html has them all).
constexpr std::size_t kMaxListed = 50;

std::string MdSeconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", s);
  return text;
}

std::string MdCounts(const SuiteResults& r) {
  std::size_t passed = 0, failed = 0, errors = 0, any = 0;
  for (const Job& job : r.jobs) {
    const Outcome o = OutcomeOf(job);
    passed += o == Outcome::kPass || o == Outcome::kNotCounted;
    failed += o == Outcome::kFail;
    errors += o == Outcome::kError;
    any += o == Outcome::kNotCounted;
  }
  std::ostringstream md;
  md << "# ovpc suite: " << passed << " of " << r.jobs.size() << " runs passed\n\n"
     << failed << " failed, " << errors << " with an error";
  if (!r.families.empty()) md << ", " << any << " family runs not counted (expect any)";
  if (!r.skipped.empty()) md << ", " << r.skipped.size() << " left out by --skip-label";
  md << ". Build `" << r.suite.build << "`";
  if (r.suite.merged > 0) md << ", merged from " << r.suite.merged << " shards";
  md << ". The suite's folder has report.html (a page per run), junit.xml and summary.json.\n";
  return md.str();
}

std::string MdNotPassed(const SuiteResults& r) {
  std::ostringstream md;
  std::size_t listed = 0, total = 0;
  for (const Job& job : r.jobs) {
    const Outcome o = OutcomeOf(job);
    if (o != Outcome::kFail && o != Outcome::kError) continue;
    if (++total > kMaxListed) continue;
    if (listed++ == 0) md << "\n## Runs that did not pass\n\n| scenario | seed | map | settings | result | why |\n|---|---|---|---|---|---|\n";
    const std::string why = o == Outcome::kError ? job.error : FailureText(job);
    md << "| " << MarkdownCell(GroupName(r.families, job) + (job.draw ? " " + scenarios::DrawFolder(DrawOf(r.families, job).index) : ""))
       << " | " << job.seed << " | " << MarkdownCell(job.map) << " | " << MarkdownCell(RunSettings(r.families, job)) << " | "
       << OutcomeLabel(o) << " | " << MarkdownCell(why) << " |\n";
  }
  if (total > listed) md << "\n… and " << total - listed << " more (report.html lists them all).\n";
  return md.str();
}

std::string MdGroups(const SuiteResults& r) {
  const std::vector<ScenarioGroup> groups = ScenarioGroups(r);
  if (groups.empty()) return "";
  std::ostringstream md;
  md << "\n## Pass rate per scenario\n\n| scenario | map | settings | passed | failed seeds | time to goal [s] | allowed [s] |\n"
        "|---|---|---|---|---|---|---|\n";
  for (const ScenarioGroup& g : groups) {
    std::string seeds;
    for (std::uint64_t s : g.failed_seeds) seeds += (seeds.empty() ? "" : ", ") + std::to_string(s);
    const std::string goal = g.arrived == 0 ? "-" : MdSeconds(g.goal_min_s) + "-" + MdSeconds(g.goal_max_s);
    md << "| " << MarkdownCell(g.scenario) << " | " << MarkdownCell(g.map) << " | " << MarkdownCell(g.settings) << " | "
       << Rate(g.passed, g.runs) << " | " << (seeds.empty() ? "-" : seeds) << " | " << goal << " | " << MdSeconds(g.time_limit_s) << " |\n";
  }
  return md.str();
}

std::string MdFamilies(const SuiteResults& r) {
  if (r.families.empty()) return "";
  std::ostringstream md;
  md << "\n## Families\n\n| family | expected to pass: ok | expected to refuse: ok | not counted | errors |\n|---|---|---|---|---|\n";
  for (const FamilyCounts& c : FamilyTotals(r)) {
    md << "| " << MarkdownCell(c.family) << " | " << Rate(c.pass_ok, c.pass_runs) << " | " << Rate(c.refuse_ok, c.refuse_runs) << " | "
       << c.any_runs << " | " << c.errors << " |\n";
  }
  return md.str();
}

}  // namespace

std::string SummaryMarkdown(const SuiteResults& results) {
  return MdCounts(results) + MdNotPassed(results) + MdGroups(results) + MdFamilies(results);
}

}  // namespace ovpc::suite
