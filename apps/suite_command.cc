// `ovpc suite`: the command line of the suite runner (ovpc/suite/runner.h).
#include <filesystem>
#include <memory>
#include <string>
#include <tuple>

#include "commands.h"
#include "ovpc/suite/runner.h"

namespace ovpc::apps {

Runner RegisterSuite(CLI::App& app) {
  auto o = std::make_shared<suite::Options>();
  CLI::App* cmd = app.add_subcommand("suite", "Run many scenarios (and seeds, parameter sweeps, scenario families) in parallel processes");
  cmd->footer(
      "Each run is `ovpc run` in its own process, writing to OUT/<scenario>[__<settings>]/seed_<k>; the runs with\n"
      "the longest time limits start first, and the reports keep the order of the inputs. Prints a\n"
      "summary table, and writes OUT/report.html (open it in a browser: the runs, failing first, and a page per run),\n"
      "OUT/junit.xml (a testcase per run, for a CI system's test page), OUT/summary.md (for a CI job's summary) and\n"
      "OUT/summary.json. A malformed scenario file, a run killed or\n"
      "crashed, or one that left no result.json is an error of that run (JUnit <error>); the others run and are\n"
      "reported. A scenario family (a file with `parameters:`) is drawn into OUT/<family>/draw_<iii>/scenario.yaml\n"
      "(--samples draws per grid point, from --family-seed), each draw run like a scenario into\n"
      "draw_<iii>/seed_<k>, judged against its expectation, and tabulated per parameter (OUT/<family>/pass_rate.csv,\n"
      "pass_rate_<parameter>.svg). Exit codes: 0 every run passed (a family run: its expectation held), 1 some run\n"
      "failed or had an error, 2 bad input (a malformed scenario or family file among them), 130 or 143 stopped by\n"
      "SIGINT or SIGTERM (the runs are stopped and the report of what finished is written). A folder under OUT is\n"
      "cleared only if ovpc made it; one suite writes OUT at a time. With --shard K/N only shard K of N of the planned\n"
      "runs is run (each run in exactly one shard, the shards balanced by the runs' time limits); `ovpc merge` makes\n"
      "the report of the whole from the shards' folders. OUT/summary.json holds everything the report is made from.");
  cmd->add_option("inputs", o->inputs, "Scenario or family folders (every *.yaml in them) or files")->required();
  cmd->add_option("-j,--jobs", o->jobs, "Runs at the same time")->capture_default_str();
  cmd->add_option("--seeds", o->seeds, "K seeds for every scenario: F..F+K-1 (F = --first-seed)")->capture_default_str();
  cmd->add_option("--first-seed", o->first_seed, "First seed F (e.g. 4 with --seeds 3: seeds 4, 5, 6)")->capture_default_str();
  cmd->add_option("--sweep", o->sweeps, "key=v1,v2,...: run every combination of values (repeatable)");
  cmd->add_option("--skip-label", o->skip_labels, "Leave out scenarios with this label (e.g. long)");
  cmd->add_option("--preset", o->preset, "The robot's configuration for every run (default: the built-in one)")->check(NotEmpty());
  CLI::Option* map_opt = cmd->add_option("--map", o->map,
                  "The map backend of every run: ovpc, octomap or elevation (default: each run's configuration; "
                  "--sweep navigator.map=ovpc,octomap,elevation compares them)");
  cmd->add_option("--threads", o->threads,
                  "Threads of each run (ovpc run --threads; default: 2 when twice --jobs fits in the cores, "
                  "else 1)")
      ->check(CLI::Range(1, 2));
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str()->check(NotEmpty());
  cmd->add_option("--samples", o->samples, "Families: random draws per grid point")->capture_default_str();
  cmd->add_option("--seed,--family-seed", o->family_seed, "Families: the seed the draws are made from (not the runs' seeds)")
      ->capture_default_str();
  cmd->add_flag("--junit-absolute-paths", o->junit_absolute_paths,
                "junit.xml's attachments ([[ATTACHMENT|path]]: topdown.png, run.mcap) as absolute paths (Jenkins), not "
                "relative to OUT");
  auto shard = std::make_shared<std::string>();
  CLI::Option* shard_opt = cmd->add_option("--shard", *shard,
                                           "K/N: run shard K of N (1 <= K <= N) of the planned runs; merge the shards' folders "
                                           "with ovpc merge");
  return [o, map_opt, shard, shard_opt]() {
    o->map_given = map_opt->count() > 0;
    if (shard_opt->count() > 0) std::tie(o->shard, o->shards) = suite::ParseShard(*shard);
    o->program = std::filesystem::read_symlink("/proc/self/exe").string();
    return suite::RunSuite(*o);
  };
}

}  // namespace ovpc::apps
