#include "ovpc/planner/local_planner.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/goals/GoalStates.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "bounded_nearest_neighbors.h"

namespace ovpc::planner {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;
using Se2State = ob::SE2StateSpace::StateType;

Pose2 ToPose(const ob::State* state) {
  const auto* s = state->as<Se2State>();
  return Pose2{s->getX(), s->getY(), NormalizeYaw(s->getYaw())};
}

void SetPose(const Pose2& pose, ob::State* state) {
  auto* s = state->as<Se2State>();
  s->setXY(pose.x_m, pose.y_m);
  s->setYaw(NormalizeYaw(pose.yaw_rad));
}

// Reeds-Shepp space that keeps the last paths it solved. One tree extension asks for the same pair
// several times (the nearest-neighbour scan, the distance to the sample, the interpolation towards
// it, the motion check's segment count and states), and each would solve every path family again.
// Same numbers as the plain space: a kept path is the one reedsShepp() gave for exactly these states.
class CachingReedsSheppSpace final : public ob::ReedsSheppStateSpace {
 public:
  explicit CachingReedsSheppSpace(double turning_radius_m) : ob::ReedsSheppStateSpace(turning_radius_m) {}

  double distance(const ob::State* a, const ob::State* b) const override { return rho_ * Solve(a, b).length(); }

  void interpolate(const ob::State* from, const ob::State* to, double t, bool& first_time, ReedsSheppPath& path,
                   ob::State* state) const override {
    if (first_time) {  // as the base class: the end states exactly at t = 0 and 1
      if (t >= 1.0) {
        if (to != state) copyState(state, to);
        return;
      }
      if (t <= 0.0) {
        if (from != state) copyState(state, from);
        return;
      }
      path = Solve(from, to);
      first_time = false;
    }
    ob::ReedsSheppStateSpace::interpolate(from, path, t, state);
  }
  using ob::ReedsSheppStateSpace::interpolate;

 private:
  struct Entry {
    std::array<double, 6> key{};
    ReedsSheppPath path;
  };
  static constexpr std::size_t kEntries = 8;

  const ReedsSheppPath& Solve(const ob::State* a, const ob::State* b) const {
    const auto* sa = a->as<Se2State>();
    const auto* sb = b->as<Se2State>();
    const std::array<double, 6> key{sa->getX(), sa->getY(), sa->getYaw(), sb->getX(), sb->getY(), sb->getYaw()};
    for (std::size_t i = 0; i < used_; ++i) {
      if (std::memcmp(entries_[i].key.data(), key.data(), sizeof(key)) == 0) return entries_[i].path;  // bit for bit
    }
    Entry& e = entries_[next_];
    next_ = (next_ + 1) % kEntries;
    used_ = std::min(used_ + 1, kEntries);
    e.key = key;
    e.path = reedsShepp(a, b);
    return e.path;
  }

  mutable std::array<Entry, kEntries> entries_{};  // a ring, overwritten oldest first
  mutable std::size_t next_ = 0, used_ = 0;
};

// Uniform SE(2) sampler with its own seed, so that the sampled sequence does not depend on how many
// OMPL random generators the process created before.
class SeededSe2Sampler : public ob::StateSampler {
 public:
  SeededSe2Sampler(const ob::StateSpace* space, std::uint32_t seed) : ob::StateSampler(space) {
    rng_.setLocalSeed(seed);
  }

  void sampleUniform(ob::State* state) override {
    const ob::RealVectorBounds& b = space_->as<ob::SE2StateSpace>()->getBounds();
    auto* s = state->as<Se2State>();
    const double x = rng_.uniformReal(b.low[0], b.high[0]);
    const double y = rng_.uniformReal(b.low[1], b.high[1]);
    s->setXY(x, y);
    s->setYaw(rng_.uniformReal(-kPi, kPi));
  }

  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override {
    const auto* n = near->as<Se2State>();
    auto* s = state->as<Se2State>();
    const double x = rng_.uniformReal(n->getX() - distance, n->getX() + distance);
    const double y = rng_.uniformReal(n->getY() - distance, n->getY() + distance);
    s->setXY(x, y);
    s->setYaw(NormalizeYaw(rng_.uniformReal(n->getYaw() - distance, n->getYaw() + distance)));
    space_->enforceBounds(state);
  }

  void sampleGaussian(ob::State* state, const ob::State* mean, double std_dev) override {
    const auto* m = mean->as<Se2State>();
    auto* s = state->as<Se2State>();
    const double x = rng_.gaussian(m->getX(), std_dev);
    const double y = rng_.gaussian(m->getY(), std_dev);
    s->setXY(x, y);
    s->setYaw(NormalizeYaw(rng_.gaussian(m->getYaw(), std_dev)));
    space_->enforceBounds(state);
  }
};

// RRTConnect with its own seed, and trees searched by BoundedNearestNeighbors instead of OMPL's
// default metric tree: the same nearest states for a fraction of the Reeds-Shepp distances.
class SeededRrtConnect : public og::RRTConnect {
 public:
  SeededRrtConnect(const ob::SpaceInformationPtr& si, std::uint32_t seed, double turning_radius_m)
      : og::RRTConnect(si) {
    rng_.setLocalSeed(seed);
    using Tree = internal::BoundedNearestNeighbors<Motion*>;
    const auto pose_of = [](Motion* const& motion) {
      const auto* s = motion->state->as<Se2State>();
      return Pose2{s->getX(), s->getY(), s->getYaw()};
    };
    tStart_ = std::make_shared<Tree>(pose_of, turning_radius_m);  // setup() keeps trees already set
    tGoal_ = std::make_shared<Tree>(pose_of, turning_radius_m);
  }
};

class SeededPathSimplifier : public og::PathSimplifier {
 public:
  SeededPathSimplifier(const ob::SpaceInformationPtr& si, std::uint32_t seed) : og::PathSimplifier(si) {
    rng_.setLocalSeed(seed);
  }
};

class MapValidityChecker : public ob::StateValidityChecker {
 public:
  MapValidityChecker(const ob::SpaceInformationPtr& si, const PlanningMap& map, const VehicleBox& vehicle,
                     std::array<std::size_t, kNumPoseChecks>* counts)
      : ob::StateValidityChecker(si), map_(map), vehicle_(vehicle), counts_(counts) {}
  bool isValid(const ob::State* state) const override {
    const PoseCheck check = CheckPose(map_, vehicle_, ToPose(state));
    ++(*counts_)[static_cast<std::size_t>(check)];
    return check == PoseCheck::kValid;
  }

 private:
  const PlanningMap& map_;
  const VehicleBox& vehicle_;
  std::array<std::size_t, kNumPoseChecks>* counts_;  // owned by the PlanResult of the running Plan() call
};

// Appends `pose` to the path, starting a new segment at a change of direction (the cusp pose ends
// one segment and starts the next).
void AppendPose(const PlanningMap& map, const Pose2& pose, Direction direction, std::vector<PathSegment>* segments) {
  PathPose out{pose, 0.0};
  if (const auto ground = map.Project(pose)) out.z_m = ground->T_L_B.translation().z();
  if (segments->empty()) {
    segments->push_back(PathSegment{direction, {out}});
    return;
  }
  PathSegment& last = segments->back();
  if (last.direction != direction) {
    if (last.poses.size() < 2) {
      last.direction = direction;  // only the start pose so far: it takes the first real direction
    } else {
      segments->push_back(PathSegment{direction, {last.poses.back()}});
    }
  }
  segments->back().poses.push_back(out);
}

// Samples the Reeds-Shepp curves between the path's vertices about every `resolution_m`, with the
// direction of the curve piece each sample lies on.
Path Densify(const ob::ReedsSheppStateSpace& space, const og::PathGeometric& geometric, double turning_radius_m,
             double resolution_m, const PlanningMap& map) {
  std::vector<PathSegment> path;
  const std::size_t n = geometric.getStateCount();
  if (n == 0) return Path();
  ob::State* sample = space.allocState();
  AppendPose(map, ToPose(geometric.getState(0)), Direction::kForward, &path);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const ob::State* from = geometric.getState(i);
    const ob::State* to = geometric.getState(i + 1);
    ob::ReedsSheppStateSpace::ReedsSheppPath rs = space.reedsShepp(from, to);
    const double total = rs.length();  // in units of the turning radius
    if (!(total > 1e-9)) continue;
    double done = 0.0;
    for (double piece : rs.length_) {
      const double length = std::abs(piece);
      if (length < 1e-9) continue;
      const Direction direction = piece < 0.0 ? Direction::kReverse : Direction::kForward;
      const int steps = std::max(1, static_cast<int>(std::ceil(length * turning_radius_m / resolution_m)));
      for (int k = 1; k <= steps; ++k) {
        const double t = std::min(1.0, (done + length * k / steps) / total);
        bool first_time = false;  // `rs` is already the curve from `from` to `to`
        space.interpolate(from, to, t, first_time, rs, sample);
        AppendPose(map, ToPose(sample), direction, &path);
      }
      done += length;
    }
  }
  space.freeState(sample);
  if (path.size() == 1 && path.front().poses.size() < 2) path.clear();
  return Path(std::move(path));
}

}  // namespace

const char* PlanStatusName(PlanStatus status) {
  switch (status) {
    case PlanStatus::kFound: return "found";
    case PlanStatus::kNoPath: return "no path";
    case PlanStatus::kStartInvalid: return "start invalid";
    case PlanStatus::kGoalInvalid: return "goal invalid";
  }
  return "unknown";
}

std::uint32_t SeedOmplOnce(std::uint32_t seed) {
  static std::once_flag once;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    ompl::RNG::setSeed(seed);
  });
  return static_cast<std::uint32_t>(ompl::RNG::getSeed());
}

void LocalPlanner::Config::Validate() const {
  vehicle.Validate();
  const auto positive = [](double value, const char* field) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("LocalPlanner::Config: ") + field + " must be > 0, got " +
                                  std::to_string(value));
    }
  };
  positive(check_resolution_m, "check_resolution_m");
  positive(output_resolution_m, "output_resolution_m");
  if (!(check_resolution_m >= 0.005) || !(output_resolution_m >= 0.005)) {
    throw std::invalid_argument("LocalPlanner::Config: check_resolution_m and output_resolution_m must be >= 0.005");
  }
  if (!(range_m >= 0.0) || !std::isfinite(range_m)) {
    throw std::invalid_argument("LocalPlanner::Config: range_m must be >= 0 (0: OMPL's default)");
  }
  if (max_iterations == 0) throw std::invalid_argument("LocalPlanner::Config: max_iterations must be > 0");
}

LocalPlanner::LocalPlanner(const Config& config, const VehicleModel& vehicle, std::uint32_t seed)
    : config_(config), box_(VehicleBox::Of(vehicle, config.vehicle)), turning_radius_m_(vehicle.turning_radius_m), seed_(seed) {
  config_.Validate();
  vehicle.Validate();
  box_.Validate();
  SeedOmplOnce(seed_);
}

PlanResult LocalPlanner::Plan(const PlanningMap& map, const Pose2& start_in, const Pose2& goal_in,
                              const std::vector<double>& other_goal_yaws) const {
  PlanResult result;
  const Pose2 start{start_in.x_m, start_in.y_m, NormalizeYaw(start_in.yaw_rad)};
  const Pose2 goal{goal_in.x_m, goal_in.y_m, NormalizeYaw(goal_in.yaw_rad)};
  result.start_check = CheckPose(map, box_, start);
  if (result.start_check != PoseCheck::kValid) {
    result.status = PlanStatus::kStartInvalid;
    return result;
  }
  std::vector<Pose2> goals;
  result.goal_check = CheckPose(map, box_, goal);
  if (result.goal_check == PoseCheck::kValid) goals.push_back(goal);
  for (double yaw : other_goal_yaws) {
    const Pose2 other{goal.x_m, goal.y_m, NormalizeYaw(yaw)};
    if (std::isfinite(other.yaw_rad) && CheckPose(map, box_, other) == PoseCheck::kValid) goals.push_back(other);
  }
  if (goals.empty()) {
    result.status = PlanStatus::kGoalInvalid;
    return result;
  }

  // Reeds-Shepp space bounded by the local map's extent.
  const MapBounds extent = map.Bounds();
  auto space = std::make_shared<CachingReedsSheppSpace>(turning_radius_m_);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, extent.min_x_m);
  bounds.setHigh(0, extent.max_x_m);
  bounds.setLow(1, extent.min_y_m);
  bounds.setHigh(1, extent.max_y_m);
  space->setBounds(bounds);
  const std::uint32_t seed = seed_;
  space->setStateSamplerAllocator(
      [seed](const ob::StateSpace* s) { return std::make_shared<SeededSe2Sampler>(s, seed); });

  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<MapValidityChecker>(si, map, box_, &result.state_checks));
  si->setMotionValidator(std::make_shared<ob::ReedsSheppMotionValidator>(si));
  si->setStateValidityCheckingResolution(
      std::min(1.0, config_.check_resolution_m / space->getMaximumExtent()));
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<ob::SE2StateSpace> start_state(space);
  SetPose(start, start_state.get());
  if (goals.size() == 1) {
    ob::ScopedState<ob::SE2StateSpace> goal_state(space);
    SetPose(goals.front(), goal_state.get());
    pdef->setStartAndGoalStates(start_state, goal_state);
  } else {  // RRTConnect grows its goal tree from each of them in turn
    pdef->addStartState(start_state);
    auto goal_states = std::make_shared<ob::GoalStates>(si);
    for (const Pose2& g : goals) {
      ob::ScopedState<ob::SE2StateSpace> goal_state(space);
      SetPose(g, goal_state.get());
      goal_states->addState(goal_state);
    }
    pdef->setGoal(goal_states);
  }

  auto planner = std::make_shared<SeededRrtConnect>(si, seed, turning_radius_m_);
  if (config_.range_m > 0.0) planner->setRange(config_.range_m);
  planner->setProblemDefinition(pdef);
  planner->setup();

  // Budget by iterations, stopping at the first exact solution; no wall clock.
  ob::IterationTerminationCondition iterations(config_.max_iterations);
  const ob::PlannerTerminationCondition ptc = ob::plannerOrTerminationCondition(
      iterations, ob::exactSolnPlannerTerminationCondition(pdef));
  planner->solve(ptc);
  // The condition is evaluated once per iteration, plus the final evaluation that stops the loop.
  result.iterations = std::min(iterations.getTimesCalled(), config_.max_iterations);
  if (!pdef->hasExactSolution()) {
    result.status = PlanStatus::kNoPath;
    return result;
  }

  og::PathGeometric path(*pdef->getSolutionPath()->as<og::PathGeometric>());
  result.raw_states = path.getStateCount();
  if (config_.simplify_rounds > 0) {
    og::PathGeometric simplified(path);
    SeededPathSimplifier simplifier(si, seed);
    for (unsigned round = 0; round < config_.simplify_rounds; ++round) {
      simplifier.reduceVertices(simplified);
      simplifier.shortcutPath(simplified);
    }
    simplifier.collapseCloseVertices(simplified);
    if (simplified.check()) path = simplified;  // every state and motion valid, else keep the raw path
  }
  for (std::size_t i = 0; i < path.getStateCount(); ++i) result.waypoints.push_back(ToPose(path.getState(i)));
  result.path = Densify(*space, path, turning_radius_m_, config_.output_resolution_m, map);
  result.status = PlanStatus::kFound;
  return result;
}

std::optional<std::size_t> LocalPlanner::FirstInvalidPose(const PlanningMap& map, const Path& path,
                                                          std::size_t from_index) const {
  const std::vector<PathPose>& poses = path.Poses();
  for (std::size_t i = from_index; i < poses.size(); ++i) {
    if (CheckPose(map, box_, poses[i].pose) != PoseCheck::kValid) return i;
  }
  return std::nullopt;
}

}  // namespace ovpc::planner
