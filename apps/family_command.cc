// `ovpc family`: draws a scenario family's concrete scenarios into plain scenario files, without running them.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ovpc/scenarios/family.h"

namespace ovpc::apps {

Runner RegisterFamily(CLI::App& app) {
  struct Options {
    std::vector<std::string> files;
    std::size_t samples = 6;
    std::uint64_t seed = 1;
    std::string out = "out/family";
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("family", "Write a scenario family's draws as plain scenario files (without running them)");
  cmd->footer(
      "Writes DIR/<family>/draw_<iii>/scenario.yaml for each draw (a fresh DIR/<family>) and DIR/<family>/draws.csv,\n"
      "and prints a line per draw: its expectation, its drawn values and its file. `ovpc run FILE` runs one draw;\n"
      "`ovpc suite FAMILY --samples N --seed S` draws the same files and runs them all. Exit codes: 0 written,\n"
      "1 a file could not be written, 2 bad input (a malformed family file).");
  cmd->add_option("families", o->files, "Family files (scenario files with parameters: and expect:)")->required();
  cmd->add_option("--samples", o->samples, "Random draws per grid point")->capture_default_str();
  cmd->add_option("--seed", o->seed, "The seed the draws are made from")->capture_default_str();
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  return [o]() {
    if (o->samples < 1) throw BadInput("--samples must be >= 1");
    for (const std::string& file : o->files) {
      scenarios::Family family;
      std::vector<scenarios::Draw> draws;
      try {
        family = scenarios::LoadFamily(file);
        draws = scenarios::DrawFamily(family, {o->samples, o->seed});
      } catch (const scenarios::ScenarioError& e) {
        throw BadInput(e.what());
      }
      const std::filesystem::path dir = std::filesystem::path(o->out) / family.name;
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
      const std::vector<std::string> paths = scenarios::WriteDraws(family, draws, dir.string());
      std::printf("%s: %zu draws (seed %llu, %zu per grid point) from %s\n%-5s %-7s %-34s %s\n", family.name.c_str(),
                  draws.size(), static_cast<unsigned long long>(o->seed), o->samples, file.c_str(), "draw", "expect",
                  "values", "file");
      for (std::size_t i = 0; i < draws.size(); ++i) {
        std::printf("%03zu   %-7s %-34s %s\n", draws[i].index, scenarios::ExpectationName(draws[i].expectation),
                    scenarios::DrawValuesLabel(draws[i]).c_str(), paths[i].c_str());
      }
      std::printf("wrote %s/draws.csv\n", dir.string().c_str());
    }
    return kExitOk;
  };
}

}  // namespace ovpc::apps
