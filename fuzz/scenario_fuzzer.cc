// libFuzzer harness for the scenario loader (scenarios/): the input is the text of a scenario file or
// of a family file (top-level `parameters:`). A plain scenario is read over the default preset, and
// when its terrain is small enough to build quickly, its heightfield and objects are built as the
// closed loop would build them. A family is read and drawn (up to 4 draws, each checked as a
// scenario). A refusal is a ScenarioError, one line naming the file; anything else (another exception,
// a valid scenario whose world cannot be built, a crash, a sanitizer report, a hang) is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "ovpc/scenarios/family.h"
#include "ovpc/scenarios/scenario_yaml.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/world.h"

namespace {

constexpr const char* kName = "fuzz.yaml";

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "scenario_fuzzer: %s\n", what.c_str());
  std::abort();
}

void CheckMessage(const std::string& what) {
  if (what.find(kName) == std::string::npos) Finding("error does not name the file: " + what);
  if (what.find('\n') != std::string::npos) Finding("error is not one line: " + what);
}

// Builds what the closed loop builds from the world first, for terrains of at most 40,000 vertices
// (larger ones are valid but slow the fuzzer down; their size limit is checked by the loader).
void BuildWorld(const ovpc::scenarios::Scenario& scenario) {
  const ovpc::sim::TerrainConfig& terrain = scenario.sim.world.terrain;
  const double vertices = (terrain.size_x_m / terrain.cell_m + 2.0) * (terrain.size_y_m / terrain.cell_m + 2.0);
  if (!(vertices <= 4e4)) return;
  const ovpc::sim::Heightfield heightfield = ovpc::sim::MakeHeightfield(terrain);
  (void)ovpc::sim::ResolveSolids(scenario.sim.world, heightfield);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const ovpc::scenarios::Preset& preset = [] () -> const ovpc::scenarios::Preset& {
    static const ovpc::scenarios::Preset p = ovpc::scenarios::DefaultPreset();
    return p;
  }();
  try {
    if (ovpc::scenarios::IsFamilyText(text)) {
      const ovpc::scenarios::Family family = ovpc::scenarios::ParseFamily(text, kName);
      if (ovpc::scenarios::GridPoints(family) <= 4) {
        ovpc::scenarios::DrawOptions options;
        options.samples = 1;
        (void)ovpc::scenarios::DrawFamily(family, options, preset);
      }
    } else {
      BuildWorld(ovpc::scenarios::ParseScenario(text, kName, {}, preset));
    }
  } catch (const ovpc::scenarios::ScenarioError& e) {
    CheckMessage(e.what());
  }
  return 0;
}
