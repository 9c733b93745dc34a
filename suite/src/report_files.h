// The report files a suite writes besides its tables and summary.json: junit.xml and summary.md
// for CI systems (junit.cc), report.html and its run pages for a browser (report_html.cc).
#pragma once

#include <string>

#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// junit.xml's text: a testcase per run (file, properties, failure, error or skipped, attachments
/// in system-out) and per scenario left out by --skip-label. `out` is junit.xml's folder.
std::string JunitXml(const SuiteResults& results, const std::string& out, bool absolute_paths);

/// summary.md's text: the counts, the runs that did not pass with their failed criteria and
/// diagnosis, the pass rate per scenario and per family.
std::string SummaryMarkdown(const SuiteResults& results);

/// OUT/report.html and OUT/runs/<index>.html, each whole or not at all.
/// @throws std::runtime_error naming the first file that could not be written whole.
void WriteHtmlReport(const SuiteResults& results, const std::string& out);

/// `text` for a Markdown table cell: '|' escaped, line breaks as <br> (GitHub shows them), none at its end.
std::string MarkdownCell(const std::string& text);

}  // namespace ovpc::suite
