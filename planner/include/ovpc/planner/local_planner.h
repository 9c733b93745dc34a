// The local planner: OMPL RRTConnect in a Reeds-Shepp space on a PlanningMap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ovpc/core/vehicle_model.h"
#include "ovpc/planner/path.h"
#include "ovpc/planner/planning_map.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::planner {

enum class PlanStatus {
  kFound,         ///< an exact solution, simplified and densified
  kNoPath,        ///< the iteration budget ran out without an exact solution
  kStartInvalid,  ///< the start pose fails CheckPose
  kGoalInvalid,   ///< the goal pose fails CheckPose
};
const char* PlanStatusName(PlanStatus status);

struct PlanResult {
  PlanStatus status = PlanStatus::kNoPath;
  Path path;                                 ///< empty unless status is kFound
  PoseCheck start_check = PoseCheck::kValid; ///< why the start was rejected
  PoseCheck goal_check = PoseCheck::kValid;  ///< why the goal was rejected
  std::vector<Pose2> waypoints;              ///< the simplified OMPL path (Reeds-Shepp vertices)
  unsigned iterations = 0;                   ///< planner iterations used out of the budget
  std::size_t raw_states = 0;                ///< states on the path before simplification
  /// States the validity checker saw during the search, by outcome (index: PoseCheck), so a user can
  /// tell which check stops the planner (outside the map, non-traversable ground, box collision).
  std::array<std::size_t, kNumPoseChecks> state_checks{};
  bool found() const { return status == PlanStatus::kFound; }
};

/// Plans from a start to a goal pose on a map. Each call builds fresh OMPL objects; nothing is kept
/// between calls, and the result depends only on the map, the poses and the config.
///
/// Determinism: OMPL draws per-object seeds from a process-wide generator that can be seeded only
/// once, before the first OMPL object exists (ompl::RNG::setSeed). The constructor does that through
/// SeedOmplOnce. On top of it, every random source that shapes the path (the state sampler, the
/// planner's and the path simplifier's generators) gets the constructor's seed as its own seed on each call, so
/// the same seed gives the same path in one process however many plans ran before. The budget is a
/// number of iterations, never wall-clock time.
class LocalPlanner {
 public:
  struct Config {
    /// The box check's rules; the box's size and the Reeds-Shepp turning radius come from the
    /// VehicleModel given to the constructor.
    BoxRules vehicle;
    /// Planning budget in RRTConnect iterations, replacing the paper's 0.1 s: a plan that finds no
    /// path spends about 0.1 s of CPU time on 500 iterations on the benchmark's scenes
    /// (bench/planner_bench.cc), while plans that succeed need a median of 10 to 30.
    unsigned max_iterations = 500;
    /// Longest tree extension; 0 keeps OMPL's default (a fifth of the space's extent).
    double range_m = 0.0;
    /// Spacing of the validity checks along a motion, m of Reeds-Shepp path length.
    double check_resolution_m = 0.1;
    /// Spacing of the output poses, m.
    double output_resolution_m = 0.1;
    /// Shortcut and vertex-reduction rounds of the path simplifier (0: no simplification).
    unsigned simplify_rounds = 2;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Section(OVPC_FIELD(c, vehicle), "the vehicle box's rules");
      v.Field(OVPC_FIELD(c, max_iterations), "iterations", "the budget, instead of the paper's 0.1 s");
      v.Field(OVPC_FIELD(c, range_m), "m", "longest tree extension; 0: OMPL's fifth of the space");
      v.Field(OVPC_FIELD(c, check_resolution_m), "m", "validity checks along a motion");
      v.Field(OVPC_FIELD(c, output_resolution_m), "m", "spacing of the output poses");
      v.Field(OVPC_FIELD(c, simplify_rounds), "rounds", "the path simplifier's; 0: none");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// `vehicle` gives the box's size and the turning radius (3.7 m for the default Gator: half its
  /// 7.3 m turning circle, docs/REFERENCE.md); `seed` seeds every random source of each plan.
  /// @throws std::invalid_argument for an invalid config or vehicle.
  explicit LocalPlanner(const Config& config, const VehicleModel& vehicle = {}, std::uint32_t seed = 1);

  /// Plans from `start` to `goal` (yaw normalised to [-pi, pi) first). Never throws on a bad
  /// problem: an invalid start or goal, or no path within the budget, is a status.
  /// `other_goal_yaws`: the goal position with these headings is a goal too (the route's end, where
  /// only the position matters); the goal is invalid only if every heading is.
  PlanResult Plan(const PlanningMap& map, const Pose2& start, const Pose2& goal,
                  const std::vector<double>& other_goal_yaws = {}) const;

  /// Index (in Path::Poses() order) of the first pose at or after `from_index` that fails CheckPose on
  /// `map`, or nothing if the rest of the path is valid. Re-planning trigger (i): the current path
  /// collides after a map update.
  std::optional<std::size_t> FirstInvalidPose(const PlanningMap& map, const Path& path,
                                              std::size_t from_index = 0) const;

  const Config& config() const { return config_; }
  /// The box the planner checks (the vehicle's size with the config's rules).
  const VehicleBox& box() const { return box_; }
  double turning_radius_m() const { return turning_radius_m_; }
  std::uint32_t seed() const { return seed_; }

 private:
  Config config_;
  VehicleBox box_;
  double turning_radius_m_;
  std::uint32_t seed_;
};

/// Calls ompl::RNG::setSeed(seed) the first time it runs in the process and does nothing on later
/// calls: OMPL accepts the process seed only before its first random number generator exists, so
/// this must run before any OMPL object is created (LocalPlanner's constructor calls it). Also lowers
/// OMPL's console output to warnings. Returns the seed in effect for the process. Thread-safe.
std::uint32_t SeedOmplOnce(std::uint32_t seed);

}  // namespace ovpc::planner
