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
  CLI::App* cmd = app.add_subcommand("merge", "Merge the shards of a suite (ovpc suite --shard K/N) into the report of the whole");
  cmd->footer(
      "Reads OUT_k/summary.json of every shard and writes what the unsharded suite writes: the tables, OUT/junit.xml,\n"
      "OUT/summary.json and the families' pass rates (OUT/<family>/pass_rate.csv, runs.csv, pass_rate_<parameter>.svg),\n"
      "the runs in the suite's planned order; the runs' own folders stay in the shards' folders. Every shard must be\n"
      "there once, of the same build, inputs, settings, preset and planned runs, and must have finished (not stopped by\n"
      "a signal); otherwise nothing is written and the problem is named (exit code 2). Exit codes otherwise as ovpc\n"
      "suite's: 0 every run passed, 1 some run failed or had an error, 2 a malformed input among the runs.");
  cmd->add_option("shards", *folders, "The shards' output folders (each ovpc suite --shard K/N --out OUT_k)")->required()->check(NotEmpty());
  cmd->add_option("--out", *out, "Output folder of the merged report")->required()->check(NotEmpty());
  return [folders, out]() { return suite::MergeShards(*folders, *out); };
}

}  // namespace ovpc::apps
