// The pass-rate plot of one parameter as hand-written SVG (no plotting dependency).
#include <cstdio>
#include <sstream>

#include "ovpc/scenarios/pass_rate.h"

namespace ovpc::scenarios {
namespace {

constexpr double kWidth = 720, kHeight = 400, kLeft = 70, kRight = 20, kTop = 56, kBottom = 84;
constexpr const char* kPassColour = "#3b78c2";
constexpr const char* kRefuseColour = "#e08a2c";

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", v);
  return text;
}

void Text(std::ostream& out, double x, double y, const std::string& text, const char* anchor = "middle", int size = 11,
          const std::string& extra = "") {
  out << "<text x=\"" << Num(x) << "\" y=\"" << Num(y) << "\" font-size=\"" << size << "\" text-anchor=\"" << anchor << "\""
      << extra << ">" << Escape(text) << "</text>\n";
}

void Axes(std::ostream& out, const std::string& family, const PassRateTable& t) {
  const double plot_h = kHeight - kTop - kBottom, right = kWidth - kRight;
  Text(out, kWidth / 2, 22, family + ": pass rate against " + t.parameter, "middle", 14);
  for (int pct = 0; pct <= 100; pct += 25) {
    const double y = kTop + plot_h * (1.0 - pct / 100.0);
    out << "<line x1=\"" << kLeft << "\" y1=\"" << Num(y) << "\" x2=\"" << right << "\" y2=\"" << Num(y)
        << "\" stroke=\"#ddd\"/>\n";
    Text(out, kLeft - 6, y + 4, std::to_string(pct) + "%", "end");
  }
  out << "<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\"" << kTop + plot_h
      << "\" stroke=\"black\"/>\n<line x1=\"" << kLeft << "\" y1=\"" << kTop + plot_h << "\" x2=\"" << right << "\" y2=\""
      << kTop + plot_h << "\" stroke=\"black\"/>\n";
  Text(out, 18, kTop + plot_h / 2, "runs whose expectation held", "middle", 12,
       " transform=\"rotate(-90 18 " + Num(kTop + plot_h / 2) + ")\"");
  Text(out, kLeft + (right - kLeft) / 2, kHeight - 16,
       t.parameter + " (" + t.kind + (t.binned ? ", bins" : ", per value") + ")", "middle", 12);
  // Legend.
  const double lx = right - 210;
  out << "<rect x=\"" << lx << "\" y=\"32\" width=\"10\" height=\"10\" fill=\"" << kPassColour << "\"/>\n";
  Text(out, lx + 14, 41, "expected pass", "start");
  out << "<rect x=\"" << lx + 105 << "\" y=\"32\" width=\"10\" height=\"10\" fill=\"" << kRefuseColour << "\"/>\n";
  Text(out, lx + 119, 41, "expected refuse", "start");
}

void Bar(std::ostream& out, double x, double w, std::size_t ok, std::size_t n, const char* colour) {
  const double plot_h = kHeight - kTop - kBottom, base = kTop + plot_h;
  if (n == 0) {
    Text(out, x + w / 2, base - 4, "-", "middle", 10, " fill=\"#888\"");
    return;
  }
  const double h = plot_h * static_cast<double>(ok) / n;
  out << "<rect x=\"" << Num(x) << "\" y=\"" << Num(base - h) << "\" width=\"" << Num(w) << "\" height=\"" << Num(h)
      << "\" fill=\"" << colour << "\"/>\n";
  Text(out, x + w / 2, base - h - 4, std::to_string(ok) + "/" + std::to_string(n), "middle", 10);
}

}  // namespace

std::string PassRateSvg(const std::string& family, const PassRateTable& t) {
  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight << "\" viewBox=\"0 0 "
      << kWidth << " " << kHeight << "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  Axes(out, family, t);
  const double plot_w = kWidth - kLeft - kRight, base = kHeight - kBottom;
  const double group = plot_w / std::max<std::size_t>(t.rows.size(), 1), bar = group * 0.36;
  std::size_t any = 0;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const PassRateRow& r = t.rows[i];
    const double x = kLeft + group * i;
    Bar(out, x + group * 0.12, bar, r.pass_ok, r.pass_runs, kPassColour);
    Bar(out, x + group * 0.52, bar, r.refuse_ok, r.refuse_runs, kRefuseColour);
    Text(out, x + group / 2, base + 16, r.label);
    any += r.any_runs;
  }
  if (any > 0) Text(out, kWidth - kRight, kHeight - 34, std::to_string(any) + " runs expected 'any' (not counted)", "end", 10);
  out << "</svg>\n";
  return out.str();
}

}  // namespace ovpc::scenarios
