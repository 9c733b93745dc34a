// `ovpc compare`: two suites' results side by side (ovpc/suite/compare.h).
#include <memory>
#include <string>

#include "commands.h"
#include "ovpc/suite/compare.h"

namespace ovpc::apps {

Runner RegisterCompare(CLI::App& app) {
  auto old_path = std::make_shared<std::string>();
  auto new_path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("compare", "Compare two suites' results: verdict changes, pass rates and time to goal");
  cmd->footer(
      "Reads OLD/summary.json and NEW/summary.json (the folders of two `ovpc suite` or `ovpc merge` runs, or the\n"
      "files themselves), matches their runs by what they ran (scenario or family draw with its values, seed, map,\n"
      "settings) and prints, in Markdown: the runs that changed verdict, those that regressed (passed in OLD, not in\n"
      "NEW) first, then those fixed; and per scenario and family the pass rate in each and its change, and the mean\n"
      "time to the goal of the runs that reached it in both and its change. Writes the same to compare.md in --out,\n"
      "or in NEW's folder. Exit codes: 0 no run regressed, 1 a run regressed, 2 bad input (a missing or invalid\n"
      "summary.json, named).");
  cmd->add_option("old", *old_path, "The earlier suite's output folder (or its summary.json)")->required()->check(NotEmpty());
  cmd->add_option("new", *new_path, "The later suite's output folder (or its summary.json)")->required()->check(NotEmpty());
  cmd->add_option("--out", *out, "Folder for compare.md (default: NEW's folder)")->check(NotEmpty());
  return [old_path, new_path, out]() { return suite::CompareSuites(*old_path, *new_path, *out); };
}

}  // namespace ovpc::apps
