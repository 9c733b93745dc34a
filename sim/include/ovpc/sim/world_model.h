// Builds the MuJoCo model of a world with the vehicle in it: the MJCF text (heightfield declared by
// size), then the compiled model with the heightfield filled from the terrain grid.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/sim/gator.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/world.h"

struct mjModel_;

namespace ovpc::sim {

/// Solver and buffer settings known to work with MuJoCo 2.2.2 for this vehicle.
struct PhysicsOptions {
  double timestep_s = 0.005;
  int nconmax = 400;        ///< contact buffer: heightfield contacts come many per wheel
  /// Constraint rows. MuJoCo 2.2.2 sizes (and zeroes, twice per run) a stack of about
  /// 5 njmax^2 numbers from it: 2000 made that 163 MB and 9 % of a 23 s run. The suite and one draw
  /// of every family used at most 88 rows (22 contacts); 1000 leaves room for a crash.
  int njmax = 1000;
  int offscreen_width = 640;   ///< offscreen render buffer
  int offscreen_height = 480;

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// `<compiler>`, `<option>`, `<size>` and `<visual>` for the given options.
std::string ModelPreambleXml(const PhysicsOptions& options);

/// The complete MJCF of the world (terrain as a heightfield named "terrain", one geom per solid
/// named after it) with the vehicle at `T_W_B`. The heightfield's values are filled after loading
/// (FillHeightfield): MuJoCo 2.2 has no way to give them in the XML.
std::string WorldMjcf(const Heightfield& terrain, const std::vector<Solid>& solids,
                      const GatorParams& vehicle, const Eigen::Isometry3d& T_W_B,
                      const PhysicsOptions& options);

struct MjModelDeleter {
  void operator()(mjModel_* model) const;
};
using ModelPtr = std::unique_ptr<mjModel_, MjModelDeleter>;

/// Compiles MJCF text (through MuJoCo's virtual file system). A compiler warning, if any, is
/// stored in `warning`.
/// @throws std::runtime_error with MuJoCo's message if it does not compile.
ModelPtr CompileMjcf(const std::string& xml, std::string* warning = nullptr);

/// Writes the terrain into the model's heightfield "terrain" (values in [0, 1] scaled by its size).
/// @throws std::invalid_argument if the model has no such heightfield or its grid differs.
void FillHeightfield(const Heightfield& terrain, mjModel_* model);

/// WorldMjcf + CompileMjcf + FillHeightfield.
ModelPtr BuildWorldModel(const Heightfield& terrain, const std::vector<Solid>& solids,
                         const GatorParams& vehicle, const Eigen::Isometry3d& T_W_B,
                         const PhysicsOptions& options, std::string* warning = nullptr);

/// A resting pose of B over the terrain at (x, y) with heading yaw: roll and pitch follow the
/// ground under the four wheels, and the wheels are `drop_m` above it.
Eigen::Isometry3d RestingPose(const Heightfield& terrain, const GatorParams& vehicle, double x_m,
                              double y_m, double yaw_rad, double drop_m = 0.01);

}  // namespace ovpc::sim
