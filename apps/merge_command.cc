// `ovpc merge`: the report of a sharded suite from its shards' result files (ovpc/suite/runner.h).
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ovpc/suite/runner.h"

namespace ovpc::apps {

Runner RegisterMerge(CLI::App& app) {
  auto folders = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto options = std::make_shared<suite::ReportOptions>();
  CLI::App* cmd = app.add_subcommand("merge", "Merge the shards of a suite (ovpc suite --shard K/N) into the report of the whole");
  cmd->footer(
      "Reads OUT_k/summary.json of every shard and writes what the unsharded suite writes: the tables, OUT/junit.xml,\n"
      "OUT/summary.md, OUT/report.html, OUT/summary.json and the families' pass rates (OUT/<family>/pass_rate.csv,\n"
      "runs.csv, pass_rate_<parameter>.svg), the runs in the suite's planned order; the runs' own folders stay in the\n"
      "shards' folders (report.html's run pages link to them there). Every shard must be\n"
      "there once, of the same build, inputs, settings, preset and planned runs, and must have finished (not stopped by\n"
      "a signal); otherwise nothing is written and the problem is named (exit code 2). Exit codes otherwise as ovpc\n"
      "suite's: 0 every run passed, 1 some run failed or had an error, 2 a malformed input among the runs.");
  cmd->add_option("shards", *folders, "The shards' output folders (each ovpc suite --shard K/N --out OUT_k)")->required()->check(NotEmpty());
  cmd->add_option("--out", *out, "Output folder of the merged report")->required()->check(NotEmpty());
  cmd->add_flag("--junit-absolute-paths", options->junit_absolute_paths,
                "junit.xml's attachments as absolute paths (Jenkins), not relative to OUT");
  return [folders, out, options]() { return suite::MergeShards(*folders, *out, *options); };
}

}  // namespace ovpc::apps
