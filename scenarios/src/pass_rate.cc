#include "ovpc/scenarios/pass_rate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "format.h"

namespace ovpc::scenarios {
namespace {

using internal::FormatNumber;

constexpr std::size_t kMaxValues = 10, kBins = 5;

const Value* ValueOf(const JudgedRun& run, const std::string& name) {
  for (const auto& [n, v] : run.values) {
    if (n == name) return &v;
  }
  return nullptr;
}

void Count(const JudgedRun& run, PassRateRow* row) {
  const bool ok = run.verdict == Verdict::kOk;
  if (run.expectation == Expectation::kPass) row->pass_ok += ok, ++row->pass_runs;
  else if (run.expectation == Expectation::kRefuse) row->refuse_ok += ok, ++row->refuse_runs;
  else ++row->any_runs;
}

// The values a parameter can take, if they are few: its list, or the integers of its range.
std::vector<Value> FewValues(const Distribution& d) {
  using Kind = Distribution::Kind;
  const bool words = std::any_of(d.values.begin(), d.values.end(), [](const Value& v) { return !v.is_number; });
  if ((d.kind == Kind::kChoice || d.kind == Kind::kGrid) && (words || d.values.size() <= kMaxValues)) {
    std::vector<Value> unique;
    for (const Value& v : d.values) {
      if (std::find(unique.begin(), unique.end(), v) == unique.end()) unique.push_back(v);
    }
    return unique;
  }
  std::vector<Value> values;
  if (d.kind == Kind::kInteger && d.hi - d.lo < kMaxValues) {
    for (double v = d.lo; v <= d.hi; v += 1.0) values.push_back(Value::Number(v));
  }
  return values;
}

// The binned range: the distribution's own where it has one, else the span of the values.
std::pair<double, double> BinRange(const Parameter& p, const std::vector<JudgedRun>& runs) {
  const Distribution& d = p.distribution;
  if (d.kind == Distribution::Kind::kUniform || d.kind == Distribution::Kind::kInteger || d.clipped) return {d.lo, d.hi};
  double lo = INFINITY, hi = -INFINITY;
  for (const Value& v : d.values) lo = std::min(lo, v.number), hi = std::max(hi, v.number);
  for (const JudgedRun& run : runs) {
    if (const Value* v = ValueOf(run, p.name)) lo = std::min(lo, v->number), hi = std::max(hi, v->number);
  }
  if (!(lo <= hi)) return {0.0, 0.0};
  return {lo, hi};
}

std::vector<PassRateRow> Bins(double lo, double hi) {
  std::vector<PassRateRow> rows(hi > lo ? kBins : 1);
  const double width = (hi - lo) / rows.size();
  for (std::size_t b = 0; b < rows.size(); ++b) {
    rows[b].lo = lo + width * b;
    rows[b].hi = b + 1 == rows.size() ? hi : lo + width * (b + 1);
    rows[b].label = "[" + FormatNumber(RoundSignificant(rows[b].lo, 4)) + ", " + FormatNumber(RoundSignificant(rows[b].hi, 4)) +
                    (b + 1 == rows.size() ? "]" : ")");
  }
  return rows;
}

std::string Rate(std::size_t ok, std::size_t n) {
  if (n == 0) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%zu/%zu (%.0f%%)", ok, n, 100.0 * ok / n);
  return text;
}

}  // namespace

PassRateTable TabulatePassRate(const Parameter& p, const std::vector<JudgedRun>& runs) {
  PassRateTable t;
  t.parameter = p.name;
  t.kind = DistributionName(p.distribution.kind);
  const std::vector<Value> values = FewValues(p.distribution);
  if (!values.empty()) {
    for (const Value& v : values) {
      PassRateRow row;
      row.label = v.ToString();
      row.lo = row.hi = v.is_number ? v.number : 0.0;
      for (const JudgedRun& run : runs) {
        if (const Value* x = ValueOf(run, p.name); x && *x == v) Count(run, &row);
      }
      t.rows.push_back(row);
    }
    return t;
  }
  t.binned = true;
  const auto [lo, hi] = BinRange(p, runs);
  t.rows = Bins(lo, hi);
  for (const JudgedRun& run : runs) {
    const Value* x = ValueOf(run, p.name);
    if (!x || !x->is_number) continue;
    const double width = (hi - lo) / t.rows.size();
    // A value on an edge (2.3 of [1.5, 3.5]) goes to the bin above, whatever the rounding of the division.
    const auto b = width > 0 ? static_cast<std::size_t>(std::max(0.0, std::floor((x->number - lo) / width + 1e-9))) : 0;
    Count(run, &t.rows[std::min(b, t.rows.size() - 1)]);
  }
  return t;
}

std::string FormatPassRateTable(const std::string& family, const PassRateTable& t) {
  std::ostringstream out;
  out << family << ": pass rate against " << t.parameter << " (" << t.kind
      << (t.binned ? ", " + std::to_string(t.rows.size()) + " bins" : std::string(", per value")) << ")\n";
  char line[160];
  std::snprintf(line, sizeof(line), "  %-22s %-18s %-18s %s\n", t.parameter.substr(0, 22).c_str(), "pass runs ok",
                "refuse runs ok", "any runs");
  out << line;
  for (const PassRateRow& r : t.rows) {
    std::snprintf(line, sizeof(line), "  %-22s %-18s %-18s %zu\n", r.label.c_str(), Rate(r.pass_ok, r.pass_runs).c_str(),
                  Rate(r.refuse_ok, r.refuse_runs).c_str(), r.any_runs);
    out << line;
  }
  return out.str();
}

std::string PassRateCsv(const std::vector<PassRateTable>& tables) {
  std::ostringstream out;
  out << "parameter,bin,lo,hi,pass_ok,pass_runs,refuse_ok,refuse_runs,any_runs\n";
  for (const PassRateTable& t : tables) {
    for (const PassRateRow& r : t.rows) {
      const bool comma = r.label.find(',') != std::string::npos;
      out << t.parameter << "," << (comma ? "\"" + r.label + "\"" : r.label) << "," << FormatNumber(r.lo) << ","
          << FormatNumber(r.hi) << "," << r.pass_ok << "," << r.pass_runs << "," << r.refuse_ok << "," << r.refuse_runs << ","
          << r.any_runs << "\n";
    }
  }
  return out.str();
}

}  // namespace ovpc::scenarios
