// `ovpc synth`: writes a generated outdoor cloud (the bundled sample and the benchmark's clouds).
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "ovpc/io/cloud_io.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc::apps {

Runner RegisterSynth(CLI::App& app) {
  struct Options {
    std::size_t points = 14000;
    std::uint64_t seed = 1;
    std::string out;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "synth", "Generate a buffered outdoor cloud (VLP-16 tilted 45 deg on a spinning base, 1.88 m above a slope, "
               "a carport, poles and trees); the viewpoint is the origin");
  cmd->add_option("--points", o->points, "Points in the cloud")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Scene and noise seed")->capture_default_str();
  cmd->add_option("--out", o->out, "Output .ply file")->required();
  return [o]() {
    if (o->points < 4) throw BadInput("--points must be >= 4");
    if (FormatFromExtension(o->out) != CloudFormat::kPly) throw BadInput("--out must name a .ply file");
    const Points cloud = synth::MakeOutdoorCloud(o->points, o->seed);
    WriteCloudPly(o->out, cloud);
    std::printf("wrote %zu points to %s (viewpoint 0,0,0)\n", cloud.size(), o->out.c_str());
    return kExitOk;
  };
}

}  // namespace ovpc::apps
