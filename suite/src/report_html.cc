// report.html: a suite's report for a browser, one file with no network access (its style, script
// and plots inline), and a page per run (runs/<index>.html) with its scorecard, diagnosis, top-down
// picture and links to its files. Written from the suite's results alone (summary.json's), so that
// `ovpc merge` writes the same report of a sharded suite.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <set>
#include <sstream>

#include "ovpc/scenarios/pass_rate.h"
#include "ovpc/suite/output_folder.h"
#include "report_files.h"
#include "report_text.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kStyle = R"css(
body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;color:#222;max-width:1400px}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0}th,td{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee}table.sortable th{cursor:pointer}table.sortable th[data-order=asc]::after{content:" \25B2"}
table.sortable th[data-order=desc]::after{content:" \25BC"}td.num{text-align:right}
td.pass,span.pass{color:#17692b}td.FAIL,td.ERROR,span.FAIL,span.ERROR,p.ERROR{color:#b00020;font-weight:bold}td.any{color:#777}
tr.FAIL td,tr.ERROR td{background:#fdecee}.bar{display:block;height:100%;background:#2e7d32}
.barbg{display:inline-block;width:80px;height:.8em;background:#e57373;vertical-align:middle}
pre{background:#f6f6f6;padding:.5em;white-space:pre-wrap}img.topdown{max-width:100%;border:1px solid #ccc}
dl{display:grid;grid-template-columns:max-content auto;gap:2px 12px}dt{font-weight:bold}dd{margin:0}
.plots svg{margin:4px;border:1px solid #ddd}
)css";

// Sorts a table.sortable by the column clicked: by each cell's data-v when it has one (numbers),
// else by its text; a second click reverses the order.
constexpr const char* kScript = R"js(
document.querySelectorAll("table.sortable").forEach((table) => {
  table.querySelectorAll("th").forEach((th, col) => th.addEventListener("click", () => {
    const asc = th.dataset.order !== "asc";
    table.querySelectorAll("th").forEach((h) => delete h.dataset.order);
    th.dataset.order = asc ? "asc" : "desc";
    const key = (row) => {
      const cell = row.cells[col];
      return cell.dataset.v !== undefined ? Number(cell.dataset.v) : cell.textContent;
    };
    const body = table.tBodies[0];
    const rows = Array.from(body.rows).sort((a, b) => {
      const x = key(a), y = key(b);
      const d = typeof x === "number" ? x - y : String(x).localeCompare(String(y));
      return asc ? d : -d;
    });
    rows.forEach((row) => body.appendChild(row));
  }));
});
)js";

std::string H(const std::string& text) { return XmlEscape(text); }

std::string Num(double v, int digits = 1) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

// A numeric table cell: its text, and its value for sorting.
std::string NumCell(double v, int digits = 1) {
  return "<td class=\"num\" data-v=\"" + (std::isfinite(v) ? Num(v, 6) : std::string("-1")) + "\">" + Num(v, digits) + "</td>";
}

std::string Page(const std::string& title, const std::string& body) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<link rel=\"icon\" href=\"data:,\">\n<title>" + H(title) +
         "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n" + body + "<script>" + kScript + "</script>\n</body>\n</html>\n";
}

// Failing runs first: errors, failures, passes, runs not counted; then in the planned order.
int OutcomeRank(Outcome o) {
  switch (o) {
    case Outcome::kError: return 0;
    case Outcome::kFail: return 1;
    case Outcome::kPass: return 2;
    case Outcome::kNotCounted: return 3;
  }
  return 4;
}

std::string RunTitle(const SuiteResults& r, const Job& job) {
  std::string title = GroupName(r.families, job);
  if (job.draw) title += " " + scenarios::DrawFolder(DrawOf(r.families, job).index);
  return title + " seed " + std::to_string(job.seed);
}

// The share of the route driven (NaN when the run has no figures).
double Completion(const Job& job) {
  const double length = job.result.value("route_length_m", 0.0);
  return length > 0.0 ? std::min(1.0, job.result.value("route_progress_m", 0.0) / length) : NAN;
}

double SimTime(const Job& job) { return job.result.contains("sim_time_s") ? job.result.value("sim_time_s", 0.0) : NAN; }

std::string Header(const SuiteResults& r, std::size_t passed) {
  const SuiteRecord& s = r.suite;
  std::string inputs;
  for (const std::string& in : s.inputs) inputs += (inputs.empty() ? "" : ", ") + in;
  std::ostringstream h;
  h << "<h1>ovpc suite: " << passed << " of " << r.jobs.size() << " runs passed</h1>\n<dl>\n<dt>inputs</dt><dd>" << H(inputs)
    << "</dd>\n<dt>seeds</dt><dd>" << s.first_seed << "-" << s.first_seed + s.seeds - 1 << "</dd>\n";
  for (const std::string& sweep : s.sweeps) h << "<dt>sweep</dt><dd>" << H(sweep) << "</dd>\n";
  if (!s.map.empty()) h << "<dt>map</dt><dd>" << H(s.map) << "</dd>\n";
  h << "<dt>preset</dt><dd>" << H(s.preset_file.empty() ? "built-in" : s.preset_file) << " (" << H(s.preset_hash) << ")</dd>\n"
    << "<dt>build</dt><dd>" << H(s.build) << "</dd>\n";
  if (s.merged > 0) h << "<dt>shards</dt><dd>merged from " << s.merged << "</dd>\n";
  if (s.stop_signal != 0) h << "<dt>stopped</dt><dd>by signal " << s.stop_signal << " before every run ended</dd>\n";
  h << "</dl>\n<p>Click a column's title to sort by it; a run's number opens its page.</p>\n";
  return h.str();
}

std::string RunRow(const SuiteResults& r, const Job& job) {
  const Outcome o = OutcomeOf(job);
  std::string end = job.error.empty() ? job.result.value("end_reason", std::string()) : job.error.substr(0, job.error.find('\n'));
  const std::string verdict = DiagnosisVerdict(job);
  if (!verdict.empty() && (o == Outcome::kFail || o == Outcome::kError)) end += " (" + verdict + ")";
  std::ostringstream row;
  row << "<tr class=\"" << OutcomeLabel(o) << "\"><td data-v=\"" << job.index << "\"><a href=\"runs/" << job.index << ".html\">"
      << job.index << "</a></td><td>" << H(GroupName(r.families, job)) << (job.draw ? " " + scenarios::DrawFolder(DrawOf(r.families, job).index) : "")
      << "</td><td class=\"num\" data-v=\"" << job.seed << "\">" << job.seed << "</td><td>" << H(job.map) << "</td><td>"
      << H(RunSettings(r.families, job)) << "</td><td class=\"" << OutcomeLabel(o) << "\" data-v=\"" << OutcomeRank(o) << "\">"
      << OutcomeLabel(o) << "</td>";
  if (!r.families.empty()) row << "<td>" << H(ExpectCell(r.families, job)) << "</td>";
  row << NumCell(SimTime(job)) << NumCell(job.time_limit_s) << NumCell(100.0 * Completion(job), 0)
      << NumCell(job.result.contains("distance_m") ? job.result.value("distance_m", 0.0) : NAN) << "<td>" << H(end) << "</td></tr>\n";
  return row.str();
}

std::string RunTable(const SuiteResults& r) {
  std::vector<std::size_t> order(r.jobs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return OutcomeRank(OutcomeOf(r.jobs[a])) < OutcomeRank(OutcomeOf(r.jobs[b])); });
  std::ostringstream t;
  t << "<h2>Runs</h2>\n<table id=\"runs\" class=\"sortable\">\n<thead><tr><th>run</th><th>scenario</th><th>seed</th><th>map</th>"
    << "<th>" << (r.families.empty() ? "settings" : "values, settings") << "</th><th>result</th>"
    << (r.families.empty() ? "" : "<th>expect: verdict</th>")
    << "<th>sim [s]</th><th>allowed [s]</th><th>route [%]</th><th>driven [m]</th><th>end</th></tr></thead>\n<tbody>\n";
  for (std::size_t i : order) t << RunRow(r, r.jobs[i]);
  t << "</tbody>\n</table>\n";
  return t.str();
}

std::string RateBar(std::size_t ok, std::size_t runs) {
  const double share = runs == 0 ? 0.0 : static_cast<double>(ok) / static_cast<double>(runs);
  return "<span class=\"barbg\"><span class=\"bar\" style=\"width:" + Num(100.0 * share, 0) + "%\"></span></span> " + Rate(ok, runs);
}

std::string ScenarioTable(const SuiteResults& r) {
  const std::vector<ScenarioGroup> groups = ScenarioGroups(r);
  if (groups.empty()) return "";
  std::ostringstream t;
  t << "<h2>Pass rate per scenario over seeds</h2>\n<table id=\"scenarios\" class=\"sortable\">\n<thead><tr><th>scenario</th><th>map</th>"
       "<th>settings</th><th>passed</th><th>failed seeds</th><th>time to goal [s]: min</th><th>mean</th><th>max</th>"
       "<th>allowed [s]</th></tr></thead>\n<tbody>\n";
  for (const ScenarioGroup& g : groups) {
    std::string seeds;
    for (std::uint64_t s : g.failed_seeds) seeds += (seeds.empty() ? "" : ", ") + std::to_string(s);
    const bool any = g.arrived > 0;
    t << "<tr><td>" << H(g.scenario) << "</td><td>" << H(g.map) << "</td><td>" << H(g.settings) << "</td><td data-v=\""
      << static_cast<double>(g.passed) / static_cast<double>(g.runs) << "\">" << RateBar(g.passed, g.runs) << "</td><td>"
      << (seeds.empty() ? "-" : seeds) << "</td>" << NumCell(any ? g.goal_min_s : NAN)
      << NumCell(any ? g.goal_sum_s / static_cast<double>(g.arrived) : NAN) << NumCell(any ? g.goal_max_s : NAN)
      << NumCell(g.time_limit_s) << "</tr>\n";
  }
  t << "</tbody>\n</table>\n";
  return t.str();
}

// Every run with figures as a point: the share of its allowed time it ran (x) against the share of
// its route it drove (y); a passing run sits at the top, left of 100 % by the time it had to spare.
std::string TimeChart(const SuiteResults& r) {
  constexpr int kW = 560, kH = 300, kL = 60, kT = 20, kPw = 460, kPh = 220;
  std::ostringstream svg;
  svg << "<h2>Time to goal and completion against the allowed time</h2>\n<svg id=\"time_chart\" xmlns=\"http://www.w3.org/2000/svg\" "
      << "width=\"" << kW << "\" height=\"" << kH << "\" viewBox=\"0 0 " << kW << " " << kH << "\" font-size=\"11\">\n";
  for (int k = 0; k <= 4; ++k) {
    const double x = kL + kPw * k / 4.0, y = kT + kPh - kPh * k / 4.0;
    svg << "<line x1=\"" << x << "\" y1=\"" << kT << "\" x2=\"" << x << "\" y2=\"" << kT + kPh << "\" stroke=\"#ddd\"/>"
        << "<line x1=\"" << kL << "\" y1=\"" << y << "\" x2=\"" << kL + kPw << "\" y2=\"" << y << "\" stroke=\"#ddd\"/>"
        << "<text x=\"" << x << "\" y=\"" << kT + kPh + 14 << "\" text-anchor=\"middle\">" << 25 * k << "</text>"
        << "<text x=\"" << kL - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">" << 25 * k << "</text>\n";
  }
  svg << "<text x=\"" << kL + kPw / 2 << "\" y=\"" << kH - 20 << "\" text-anchor=\"middle\">simulated time [% of the allowed time]</text>"
      << "<text transform=\"translate(14," << kT + kPh / 2 << ") rotate(-90)\" text-anchor=\"middle\">route driven [%]</text>\n";
  for (const Job& job : r.jobs) {
    const double t = SimTime(job), c = Completion(job);
    if (!std::isfinite(t) || !std::isfinite(c) || job.time_limit_s <= 0.0) continue;
    const Outcome o = OutcomeOf(job);
    const char* colour = o == Outcome::kPass ? "#2e7d32" : o == Outcome::kNotCounted ? "#888" : "#c62828";
    svg << "<a href=\"runs/" << job.index << ".html\"><circle cx=\"" << Num(kL + kPw * std::min(1.0, t / job.time_limit_s), 1)
        << "\" cy=\"" << Num(kT + kPh * (1.0 - c), 1) << "\" r=\"4\" fill=\"" << colour << "\" fill-opacity=\"0.7\"><title>"
        << H(RunTitle(r, job) + ": " + OutcomeLabel(o) + ", " + Num(t) + " of " + Num(job.time_limit_s) + " s, route " + Num(100.0 * c, 0) + " %")
        << "</title></circle></a>\n";
  }
  svg << "<text x=\"" << kL + kPw + 8 << "\" y=\"" << kT + 10 << "\" fill=\"#2e7d32\">pass</text><text x=\"" << kL + kPw + 8 << "\" y=\""
      << kT + 26 << "\" fill=\"#c62828\">fail</text><text x=\"" << kL + kPw + 8 << "\" y=\"" << kT + 42 << "\" fill=\"#888\">any</text>\n</svg>\n";
  return svg.str();
}

std::string FamilySection(const SuiteResults& r, std::size_t f, const FamilyCounts& c) {
  const FamilyInput& in = r.families[f];
  std::vector<scenarios::JudgedRun> runs;
  for (const Job& job : r.jobs) {
    if (job.draw && job.draw->family == f) {
      const scenarios::Draw& d = DrawOf(r.families, job);
      runs.push_back({d.values, d.expectation, job.draw->verdict});
    }
  }
  std::ostringstream s;
  s << "<h3 id=\"family_" << f << "\">" << H(in.family.name) << "</h3>\n<p>" << H(in.family.path) << ": expected to pass "
    << Rate(c.pass_ok, c.pass_runs) << " ok, expected to refuse " << Rate(c.refuse_ok, c.refuse_runs) << " ok, " << c.any_runs
    << " not counted, " << c.errors << " errors. <a href=\"" << UrlPath(in.folder) << "/pass_rate.csv\">pass_rate.csv</a>, <a href=\""
    << UrlPath(in.folder) << "/runs.csv\">runs.csv</a></p>\n<div class=\"plots\">\n";
  for (const scenarios::Parameter& p : in.family.parameters) {
    s << scenarios::PassRateSvg(in.family.name, scenarios::TabulatePassRate(p, runs)) << "\n";
  }
  s << "</div>\n";
  return s.str();
}

std::string Families(const SuiteResults& r) {
  if (r.families.empty()) return "";
  const std::vector<FamilyCounts> counts = FamilyTotals(r);
  std::string s = "<h2>Families: pass rate against each drawn parameter</h2>\n";
  for (std::size_t f = 0; f < r.families.size(); ++f) s += FamilySection(r, f, counts[f]);
  return s;
}

std::string Skipped(const SuiteResults& r) {
  if (r.skipped.empty()) return "";
  std::string s = "<h2>Left out by --skip-label</h2>\n<ul>\n";
  for (const SkippedRun& k : r.skipped) s += "<li>" + H(k.scenario) + " (" + H(k.file) + "): label " + H(k.label) + "</li>\n";
  return s + "</ul>\n";
}

std::string ReportPage(const SuiteResults& r) {
  const std::size_t passed = std::count_if(r.jobs.begin(), r.jobs.end(), Passed);
  return Page("ovpc suite: " + std::to_string(passed) + " of " + std::to_string(r.jobs.size()) + " runs passed",
              Header(r, passed) + RunTable(r) + ScenarioTable(r) + TimeChart(r) + Families(r) + Skipped(r));
}

// --- a run's page ---

std::string Fact(const std::string& name, const std::string& value) { return "<dt>" + H(name) + "</dt><dd>" + H(value) + "</dd>\n"; }

std::string RunFacts(const SuiteResults& r, const Job& job, const fs::path& from) {
  const json& res = job.result;
  std::ostringstream f;
  f << "<dl id=\"facts\">\n<dt>scenario file</dt><dd><a href=\"" << UrlPath(RelativePath(job.file, from)) << "\">" << H(job.file) << "</a></dd>\n"
    << Fact("seed", std::to_string(job.seed)) << Fact("map", job.map);
  if (!job.settings.empty()) f << Fact("settings", SettingsLabel(job.settings));
  if (job.draw) {
    const scenarios::Draw& d = DrawOf(r.families, job);
    f << Fact("family", r.families[job.draw->family].family.name + " (" + r.families[job.draw->family].family.path + ")")
      << Fact("drawn values", scenarios::DrawValuesLabel(d)) << Fact("expectation", ExpectCell(r.families, job))
      << (d.reason.empty() ? "" : Fact("reason", d.reason));
  }
  f << Fact("exit code", std::to_string(job.exit_code));
  if (res.contains("sim_time_s")) {
    f << Fact("end", res.value("end_reason", std::string())) << Fact("simulated", Num(SimTime(job)) + " s of " + Num(job.time_limit_s) + " s allowed")
      << Fact("route", Num(res.value("route_progress_m", 0.0)) + " of " + Num(res.value("route_length_m", 0.0)) + " m (" +
                           Num(100.0 * Completion(job), 0) + " %), driven " + Num(res.value("distance_m", 0.0)) + " m")
      << Fact("plans found", std::to_string(res.value("replans_found", 0)) + " of " + std::to_string(res.value("plans", 0)))
      << Fact("wall clock", Num(res.value("wall_time_s", 0.0)) + " s (" + Num(res.value("real_time_factor", 0.0)) + "x real time)");
  }
  f << "</dl>\n";
  return f.str();
}

std::string Scorecard(const Job& job) {
  if (!job.result.contains("criteria")) return "";
  std::ostringstream t;
  t << "<h2>Scorecard</h2>\n<table id=\"scorecard\">\n<thead><tr><th>criterion</th><th>expected</th><th>actual</th><th>result</th></tr></thead>\n<tbody>\n";
  for (const json& c : job.result["criteria"]) {
    const bool ok = c.value("passed", false);
    t << "<tr class=\"" << (ok ? "pass" : "FAIL") << "\"><td>" << H(c.value("name", std::string())) << "</td><td>"
      << H(c.value("expected", std::string())) << "</td><td>" << H(c.value("actual", std::string())) << "</td><td class=\""
      << (ok ? "pass" : "FAIL") << "\">" << (ok ? "pass" : "FAIL") << "</td></tr>\n";
  }
  t << "</tbody>\n</table>\n";
  return t.str();
}

std::string JsonText(const json& v) {
  if (v.is_number_float()) return Num(v.get<double>(), 2);
  return v.is_string() ? v.get<std::string>() : v.is_null() ? "-" : v.dump();
}

std::string Diagnosis(const Job& job) {
  std::ostringstream d;
  d << "<h2>Diagnosis</h2>\n<div id=\"diagnosis\">\n";
  if (!job.error.empty()) d << "<p class=\"ERROR\">error</p>\n<pre>" << H(job.error) << "</pre>\n";
  if (job.result.contains("diagnosis") && job.result["diagnosis"].is_object()) {
    const json& g = job.result["diagnosis"];
    d << "<p><b>" << H(g.value("verdict", std::string())) << "</b>: " << H(g.value("summary", std::string())) << "</p>\n<dl>\n";
    for (const char* key : {"map_ahead", "planner_lately", "stood_still_s", "still_at_end_s", "reversals", "reversals_last_30s",
                            "moved_last_30s_m", "last_plan_found_s", "commonest_rejection", "commonest_failure"}) {
      if (g.contains(key) && !(g[key].is_string() && g[key].get<std::string>().empty())) d << Fact(key, JsonText(g[key]));
    }
    d << "</dl>\n";
  }
  if (OutcomeOf(job) == Outcome::kFail) d << "<pre id=\"failure\">" << H(FailureText(job)) << "</pre>\n";
  d << "</div>\n";
  return d.str();
}

std::string RunFiles(const Job& job, const fs::path& from) {
  std::error_code ec;
  if (job.out_dir.empty() || !fs::is_directory(job.out_dir, ec)) return "<h2>Files</h2>\n<p>no run folder</p>\n";
  const std::string dir = RelativePath(job.out_dir, from);
  std::ostringstream f;
  if (fs::is_regular_file(fs::path(job.out_dir) / "topdown.png", ec)) {
    f << "<h2>Top-down</h2>\n<a href=\"" << UrlPath(dir + "/topdown.png") << "\"><img class=\"topdown\" alt=\"top-down picture of the run\" src=\""
      << UrlPath(dir + "/topdown.png") << "\"></a>\n";
  }
  f << "<h2>Files</h2>\n<p>Folder: <a href=\"" << UrlPath(dir) << "/\">" << H(job.out_dir) << "</a></p>\n<ul id=\"files\">\n";
  for (const char* name : kRunFiles) {
    if (!fs::is_regular_file(fs::path(job.out_dir) / name, ec)) continue;
    f << "<li><a href=\"" << UrlPath(dir + "/" + name) << "\">" << name << "</a>"
      << (std::string(name) == "run.mcap" ? " (the run log: open it in Foxglove)" : "") << "</li>\n";
  }
  if (job.result.contains("files")) {
    for (const json& file : job.result["files"]) {
      const std::string name = fs::path(JsonText(file)).filename().string();
      if (fs::is_regular_file(fs::path(job.out_dir) / name, ec)) f << "<li><a href=\"" << UrlPath(dir + "/" + name) << "\">" << H(name) << "</a></li>\n";
    }
  }
  f << "</ul>\n";
  return f.str();
}

std::string RunPage(const SuiteResults& r, const Job& job, const fs::path& from) {
  const Outcome o = OutcomeOf(job);
  const std::string title = RunTitle(r, job) + ": " + OutcomeLabel(o);
  return Page(title, "<p><a href=\"../report.html\">&larr; the suite's report</a></p>\n<h1>run " + std::to_string(job.index) + ": " +
                         H(RunTitle(r, job)) + " <span class=\"" + OutcomeLabel(o) + "\">" + OutcomeLabel(o) + "</span></h1>\n" +
                         RunFacts(r, job, from) + Scorecard(job) + Diagnosis(job) + RunFiles(job, from));
}

}  // namespace

void WriteHtmlReport(const SuiteResults& results, const std::string& out) {
  const fs::path runs = fs::path(out) / "runs";
  MakeFolder(runs);
  std::set<std::string> pages;
  for (const Job& job : results.jobs) {
    pages.insert(std::to_string(job.index) + ".html");
    WriteFileAtomic(runs / (std::to_string(job.index) + ".html"), RunPage(results, job, runs));
  }
  // An earlier suite's run pages that this report does not have (<number>.html only) go.
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(runs, ec)) {
    const std::string name = e.path().filename().string();
    const bool page = name.size() > 5 && name.compare(name.size() - 5, 5, ".html") == 0 &&
                      name.find_first_not_of("0123456789") == name.size() - 5;
    if (page && !pages.count(name) && e.is_regular_file(ec)) fs::remove(e.path(), ec);
  }
  WriteFileAtomic(fs::path(out) / "report.html", ReportPage(results));
}

}  // namespace ovpc::suite
