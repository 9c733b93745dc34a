// `ovpc family`: draws a scenario family's concrete scenarios into plain scenario files, without running them.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ovpc/scenarios/family.h"
#include "ovpc/suite/output_folder.h"

namespace ovpc::apps {
namespace {

struct FamilyOptions {
  std::vector<std::string> files;
  long long samples = 6;
  std::uint64_t seed = 1;
  std::string out = "out/family";
};

void PrintDraws(const scenarios::Family& family, const std::vector<scenarios::Draw>& draws, const std::vector<std::string>& paths,
                const FamilyOptions& o) {
  std::printf("%s: %zu draws (seed %llu, %lld per grid point) from %s\n%-5s %-7s %-34s %s\n", family.name.c_str(), draws.size(),
              static_cast<unsigned long long>(o.seed), o.samples, family.path.c_str(), "draw", "expect", "values", "file");
  for (std::size_t i = 0; i < draws.size(); ++i) {
    std::printf("%03zu   %-7s %-34s %s\n", draws[i].index, scenarios::ExpectationName(draws[i].expectation),
                scenarios::DrawValuesLabel(draws[i]).c_str(), paths[i].c_str());
  }
}

}  // namespace

Runner RegisterFamily(CLI::App& app) {
  using Options = FamilyOptions;
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("family", "Write a scenario family's draws as plain scenario files (without running them)");
  cmd->footer(
      "Writes DIR/<family>/draw_<iii>/scenario.yaml for each draw (a fresh DIR/<family>; a folder not made by ovpc is refused) and DIR/<family>/draws.csv,\n"
      "and prints a line per draw: its expectation, its drawn values and its file. `ovpc run FILE` runs one draw;\n"
      "`ovpc suite FAMILY --samples N --seed S` draws the same files and runs them all. Exit codes: 0 written,\n"
      "1 a file could not be written, 2 bad input (a malformed family file).");
  cmd->add_option("families", o->files, "Family files (scenario files with parameters: and expect:)")->required();
  cmd->add_option("--samples", o->samples, "Random draws per grid point")->capture_default_str();
  cmd->add_option("--seed", o->seed, "The seed the draws are made from")->capture_default_str();
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str()->check(NotEmpty());
  return [o]() {
    if (o->samples < 1 || o->samples > 100000) throw BadInput("--samples must be 1-100000, got " + std::to_string(o->samples));
    // Every family is read and drawn before anything is written.
    std::vector<std::pair<scenarios::Family, std::vector<scenarios::Draw>>> drawn;
    for (const std::string& file : o->files) {
      try {
        scenarios::Family family = scenarios::LoadFamily(file);
        std::vector<scenarios::Draw> draws = scenarios::DrawFamily(family, {static_cast<std::size_t>(o->samples), o->seed});
        drawn.emplace_back(std::move(family), std::move(draws));
      } catch (const scenarios::ScenarioError& e) {
        throw BadInput(e.what());
      }
      std::string why;
      const std::string& name = drawn.back().first.name;
      if (!suite::IsSafeComponent(name, &why)) throw BadInput(file + ": the name '" + name.substr(0, 80) + "' " + why);
    }
    const suite::FolderLock lock(o->out);
    std::map<std::string, std::string> folders;  // folder -> the file that has it
    for (const auto& [family, draws] : drawn) {
      // Two families with one name get folders of their own, as in `ovpc suite`.
      std::string folder = family.name;
      for (int k = 2; folders.count(folder); ++k) folder = family.name + "_" + std::to_string(k);
      folders[folder] = family.path;
      const std::filesystem::path dir = std::filesystem::path(o->out) / folder;
      suite::MakeFresh(dir);
      const std::vector<std::string> paths = scenarios::WriteDraws(family, draws, dir.string());
      PrintDraws(family, draws, paths, *o);
      std::printf("wrote %s/draws.csv\n", dir.string().c_str());
    }
    return kExitOk;
  };
}

}  // namespace ovpc::apps
