#include "plan.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "ovpc/backends/map_selection.h"
#include "ovpc/scenarios/family.h"
#include "ovpc/suite/output_folder.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

struct Sweep {
  std::string key;
  std::vector<std::string> values;
};

Sweep ParseSweep(const std::string& sweep) {
  const std::size_t eq = sweep.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= sweep.size()) {
    throw BadInput("--sweep '" + sweep + "' must be key=v1,v2,... (e.g. navigator.follower.lookahead_gain_s=0.3,0.5)");
  }
  Sweep out{sweep.substr(0, eq), {}};
  std::stringstream ss(sweep.substr(eq + 1));
  std::string v;
  while (std::getline(ss, v, ',')) {
    if (v.empty()) throw BadInput("--sweep '" + sweep + "' has an empty value");
    out.values.push_back(v);
  }
  return out;
}

// The settings of a combination as a folder name: "k=v__k2=v2" (with `first` before it).
std::string Tag(const std::vector<std::string>& combo, const std::string& first) {
  std::string tag;
  for (const auto& kv : combo) tag += (tag.empty() ? first : "__") + kv;
  std::replace(tag.begin(), tag.end(), '/', '_');
  return tag;
}

}  // namespace

// Cartesian product of the sweeps: each entry of the result is one list of key=value settings.
// Refused (exit 2, with the count) when there are more than kMaxCombinations.
std::vector<std::vector<std::string>> SweepCombinations(const std::vector<std::string>& sweep_args) {
  std::vector<Sweep> sweeps;
  double count = 1.0;
  for (const std::string& arg : sweep_args) {
    sweeps.push_back(ParseSweep(arg));
    for (std::size_t i = 0; i + 1 < sweeps.size(); ++i) {
      if (sweeps[i].key == sweeps.back().key) throw BadInput("--sweep " + sweeps.back().key + " is given twice; give its values once");
    }
    count *= static_cast<double>(sweeps.back().values.size());
  }
  if (count > static_cast<double>(kMaxCombinations)) {
    char n[64];
    std::snprintf(n, sizeof(n), "%.0f", count);
    throw BadInput("--sweep: " + std::string(n) + " combinations; at most " + std::to_string(kMaxCombinations) +
                   " in one suite");
  }
  std::vector<std::vector<std::string>> combos = {{}};
  for (const Sweep& sweep : sweeps) {
    std::vector<std::vector<std::string>> next;
    for (const auto& combo : combos) {
      for (const auto& value : sweep.values) {
        next.push_back(combo);
        next.back().push_back(sweep.key + "=" + value);
      }
    }
    combos = std::move(next);
  }
  return combos;
}

// The input files in order: every *.yaml of a folder (sorted), or the file itself. A file given
// twice (also through its folder) is refused: its runs would share their folders.
std::vector<std::string> CollectFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  std::map<std::string, std::string> seen;  // canonical path -> as given
  const auto add = [&](const std::string& file) {
    std::error_code ec;
    const std::string key = fs::weakly_canonical(file, ec).string();
    if (!seen.emplace(key, file).second) throw BadInput(file + ": given twice (also as " + seen[key] + ")");
    files.push_back(file);
  };
  for (const std::string& in : inputs) {
    if (fs::is_directory(in)) {
      std::vector<std::string> found;
      for (const auto& e : fs::directory_iterator(in)) {
        if (e.path().extension() == ".yaml") found.push_back(e.path().string());
      }
      std::sort(found.begin(), found.end());
      for (const auto& f : found) add(f);
    } else if (fs::is_regular_file(in)) {
      add(in);
    } else if (fs::exists(in)) {
      throw BadInput(in + ": not a regular file or a folder");
    } else {
      throw BadInput(in + ": no such scenario file or folder");
    }
  }
  return files;
}

void Planner::AddFile(const std::string& file) {
  if (scenarios::IsFamilyFile(file)) return AddFamily(file);
  scenarios::Scenario s;
  try {
    s = scenarios::LoadScenario(file, {}, preset_);
  } catch (const scenarios::ScenarioError& e) {
    return AddMalformed(file, e.what());
  }
  if (!NameIsFolder(file, s.name) || Skipped(s, file)) return;
  const std::map<std::string, std::string> bad = BadSweepValues(file);
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    if (Refused(file, s.name, combos_[k], bad)) continue;
    const std::string tag = FolderOf(file, s.name, k);
    AddSeeds(file, s.name, combos_[k], fs::path(o_.out) / tag, std::nullopt, MapOf(file, s, combos_[k]), s.time_limit_s);
  }
}

// The run folder of `name` with combination k: <name>[__<settings>], or <name>__combo_<k> when
// that is too long for a file name; files sharing a scenario name get _2, _3, ...
std::string Planner::FolderOf(const std::string& file, const std::string& name, std::size_t k) {
  std::string suffix = Tag(combos_[k], "__");
  if (name.size() + suffix.size() + 8 > kMaxComponentBytes) suffix = "__combo_" + std::to_string(k + 1);
  std::string tag = name + suffix;
  for (int n = 2; tag_files_.count(tag) && tag_files_[tag] != file; ++n) tag = name + "_" + std::to_string(n) + suffix;
  tag_files_[tag] = file;
  return tag;
}

bool Planner::Skipped(const scenarios::Scenario& s, const std::string& file) {
  for (const auto& l : o_.skip_labels) {
    if (std::count(s.labels.begin(), s.labels.end(), l) > 0) {
      skipped.push_back({file, s.name, l});
      return true;
    }
  }
  return false;
}

// A name that cannot be a folder under --out is an error of its file (the loaders refuse such
// names too; this keeps every run folder inside --out whatever they accept).
bool Planner::NameIsFolder(const std::string& file, const std::string& name) {
  std::string why;
  if (IsSafeComponent(name, &why)) return true;
  AddMalformed(file, file + ": the name '" + name.substr(0, 80) + "' " + why);
  return false;
}

// Each sweep value checked once with this file (a sum of loads, not a product): "key=value" ->
// the error it gives.
std::map<std::string, std::string> Planner::BadSweepValues(const std::string& file) const {
  std::map<std::string, std::string> bad;
  if (combos_.size() == 1 && combos_.front().empty()) return bad;
  std::set<std::string> values;
  for (const auto& combo : combos_) values.insert(combo.begin(), combo.end());
  for (const std::string& kv : values) {
    try {
      scenarios::LoadScenario(file, {kv}, preset_);
    } catch (const scenarios::ScenarioError& e) {
      bad[kv] = e.what();
    }
  }
  return bad;
}

// A combination with a bad value is an error of its own; the other combinations run.
bool Planner::Refused(const std::string& file, const std::string& name, const std::vector<std::string>& combo,
             const std::map<std::string, std::string>& bad) {
  for (const std::string& kv : combo) {
    auto it = bad.find(kv);
    if (it == bad.end()) continue;
    AddMalformed(file, it->second);
    jobs.back().scenario = name;
    jobs.back().settings = combo;
    return true;
  }
  return false;
}

// Reported as an error of this file; the other files still run.
void Planner::AddMalformed(const std::string& file, const std::string& error) {
  std::fprintf(stderr, "ovpc suite: %s\n", error.c_str());
  Job job;
  job.file = file;
  job.scenario = fs::path(file).stem().string();
  job.exit_code = kExitBadInput;
  job.error = error;
  jobs.push_back(job);
  malformed = true;
}

// The map backend a run of `s` with `combo` (and --map) uses; the file is read again only when
// the combination sets the backend.
std::string Planner::MapOf(const std::string& file, const scenarios::Scenario& s, const std::vector<std::string>& combo) const {
  if (o_.map_given) return o_.map;
  const bool sets_map = std::any_of(combo.begin(), combo.end(), [](const std::string& kv) { return kv.rfind("navigator.map=", 0) == 0; });
  if (!sets_map) return backends::MapKindName(s.map_backends.map);
  try {
    return backends::MapKindName(scenarios::LoadScenario(file, combo, preset_).map_backends.map);
  } catch (const scenarios::ScenarioError&) {
    return "?";  // the run reports the error
  }
}

void Planner::AddSeeds(const std::string& file, const std::string& name, const std::vector<std::string>& combo, const fs::path& dir,
                       const std::optional<DrawRun>& draw, const std::string& map, double time_limit_s) {
  if (jobs.size() + static_cast<std::size_t>(o_.seeds) > kMaxRuns) {
    throw BadInput("more than " + std::to_string(kMaxRuns) + " runs in one suite (" + file +
                   " and the inputs before it); split it with --first-seed or fewer inputs");
  }
  for (int k = 0; k < o_.seeds; ++k) {
    const int seed = o_.first_seed + k;
    Job job;
    job.file = file;
    job.scenario = name;
    job.seed = static_cast<std::uint64_t>(seed);
    job.settings = combo;
    job.out_dir = (dir / ("seed_" + std::to_string(seed))).string();
    job.draw = draw;
    job.map = map;
    job.time_limit_s = time_limit_s;
    CheckClearable(job.out_dir);
    jobs.push_back(job);
  }
}


// A family: drawn into OUT/<family>/draw_<iii>/scenario.yaml (a fresh folder), each draw then run like
// a scenario file into draw_<iii>[/<settings>]/seed_<k>.
void Planner::AddFamily(const std::string& file) {
  FamilyInput in;
  try {
    in.family = scenarios::LoadFamily(file);
    in.draws = scenarios::DrawFamily(in.family, {static_cast<std::size_t>(o_.samples), o_.family_seed}, preset_);
  } catch (const scenarios::ScenarioError& e) {
    return AddMalformed(file, e.what());
  }
  if (!NameIsFolder(file, in.family.name)) return;
  std::string folder = in.family.name;
  for (int k = 2; tag_files_.count(folder) && tag_files_[folder] != file; ++k) folder = in.family.name + "_" + std::to_string(k);
  tag_files_[folder] = file;
  in.dir = (fs::path(o_.out) / folder).string();
  in.folder = folder;
  MakeFresh(in.dir);
  in.files = scenarios::WriteDraws(in.family, in.draws, in.dir);
  const std::size_t first_job = jobs.size();
  for (std::size_t i = 0; i < in.draws.size(); ++i) {
    scenarios::Scenario s;
    try {
      s = scenarios::LoadScenario(in.files[i], {}, preset_);
    } catch (const scenarios::ScenarioError& e) {
      jobs.resize(first_job);
      return AddMalformed(in.files[i], e.what());
    }
    if (Skipped(s, in.files[i])) continue;
    const std::map<std::string, std::string> bad = BadSweepValues(in.files[i]);
    const fs::path draw_dir = fs::path(in.files[i]).parent_path();
    for (std::size_t k = 0; k < combos_.size(); ++k) {
      if (Refused(in.files[i], s.name, combos_[k], bad)) continue;
      std::string sub = Tag(combos_[k], "");
      if (sub.size() + 8 > kMaxComponentBytes) sub = "combo_" + std::to_string(k + 1);
      AddSeeds(in.files[i], s.name, combos_[k], draw_dir / sub, DrawRun{families.size(), i}, MapOf(in.files[i], s, combos_[k]),
               s.time_limit_s);
    }
  }
  families.push_back(std::move(in));
}

}  // namespace ovpc::suite
