#include "ovpc/scenarios/report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "config_yaml.h"
#include "ovpc/scenarios/diagnosis.h"
#include "ovpc/sim/image.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/world.h"

namespace ovpc::scenarios {
namespace {

nlohmann::json StageJson(const StageStats& s) {
  return {{"calls", s.calls}, {"mean_ms", s.mean_ms}, {"median_ms", s.median_ms},
          {"p90_ms", s.p90_ms}, {"p99_ms", s.p99_ms}, {"max_ms", s.max_ms}, {"total_ms", s.total_ms}};
}

double Yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

// A small raster canvas in world coordinates.
class Canvas {
 public:
  Canvas(double x0, double y0, double x1, double y1, double px_per_m)
      : x0_(x0), y1_(y1), scale_(px_per_m) {
    image_.width = std::max(1, static_cast<int>(std::ceil((x1 - x0) * px_per_m)));
    image_.height = std::max(1, static_cast<int>(std::ceil((y1 - y0) * px_per_m)));
    image_.rgb.assign(static_cast<std::size_t>(image_.width) * image_.height * 3, 255);
  }
  int width() const { return image_.width; }
  int height() const { return image_.height; }
  Eigen::Vector2d World(int px, int py) const { return {x0_ + (px + 0.5) / scale_, y1_ - (py + 0.5) / scale_}; }
  void Set(int px, int py, const std::array<int, 3>& c, double alpha = 1.0) {
    if (px < 0 || py < 0 || px >= image_.width || py >= image_.height) return;
    std::uint8_t* p = image_.rgb.data() + 3 * (static_cast<std::size_t>(py) * image_.width + px);
    for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(p[k] * (1 - alpha) + c[k] * alpha));
  }
  void Dot(const Eigen::Vector2d& w, int radius, const std::array<int, 3>& c, double alpha = 1.0) {
    const int cx = static_cast<int>((w.x() - x0_) * scale_), cy = static_cast<int>((y1_ - w.y()) * scale_);
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx)
        if (dx * dx + dy * dy <= radius * radius) Set(cx + dx, cy + dy, c, alpha);
  }
  void Line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, int radius, const std::array<int, 3>& c) {
    const int steps = std::max(1, static_cast<int>((b - a).norm() * scale_ * 2));
    for (int i = 0; i <= steps; ++i) Dot(a + (b - a) * (double(i) / steps), radius, c);
  }
  const sim::Image& image() const { return image_; }

 private:
  double x0_, y1_, scale_;
  sim::Image image_;
};

nlohmann::json DiagnosisJson(const Diagnosis& d) {
  nlohmann::json j = {{"verdict", d.verdict},
                      {"summary", d.summary},
                      {"stood_still_s", d.stood_still_s},
                      {"still_at_end_s", d.still_at_end_s},
                      {"reversals", d.reversals},
                      {"reversals_last_30s", d.reversals_last_30s},
                      {"moved_last_30s_m", d.moved_last_30s_m},
                      {"commonest_rejection", d.commonest_rejection},
                      {"commonest_failure", d.commonest_failure},
                      {"map_ahead", d.map_ahead},
                      {"planner_lately", d.planner_lately}};
  j["last_plan_found_s"] = d.last_plan_found_s ? nlohmann::json(*d.last_plan_found_s) : nlohmann::json(nullptr);
  return j;
}

// The run's effective configuration, as --print-config prints it.
nlohmann::json RunConfigJson(const Scenario& scenario) {
  internal::JsonWriter writer, record;
  ovpc::VisitFields(scenario.navigator, writer);
  ovpc::VisitFields(scenario.map_backends, writer);
  ovpc::VisitFields(scenario.record, record);
  return {{"navigator", writer.json()}, {"record", record.json()}};
}

}  // namespace

std::string FormatScorecard(const Scenario& scenario, const RunResult& r) {
  std::ostringstream out;
  std::size_t w_name = 9, w_exp = 8, w_act = 6;
  for (const auto& c : r.criteria) {
    w_name = std::max(w_name, c.name.size());
    w_exp = std::max(w_exp, c.expected.size());
    w_act = std::max(w_act, c.actual.size());
  }
  out << "scenario " << scenario.name << " (seed " << r.seed << "): " << (r.passed ? "PASS" : "FAIL") << ", "
      << r.end_reason << "\n";
  out << std::left << std::setw(w_name + 2) << "criterion" << std::setw(w_exp + 2) << "expected" << std::setw(w_act + 2)
      << "actual" << "result\n";
  for (const auto& c : r.criteria) {
    out << std::left << std::setw(w_name + 2) << c.name << std::setw(w_exp + 2) << c.expected << std::setw(w_act + 2)
        << c.actual << (c.passed ? "pass" : "FAIL") << "\n";
  }
  out << std::fixed << std::setprecision(1) << "simulated " << r.sim_time_s << " s in " << r.wall_time_s
      << " s wall (" << r.real_time_factor << "x real time), driven " << r.distance_m << " m, route progress "
      << r.route_progress_m << " / " << r.route_length_m << " m, " << r.navigator.replans_found << " plans found of "
      << r.navigator.plans << ", " << r.navigator.map_updates << " map updates (" << r.map_backend << ", median "
      << std::setprecision(2) << r.navigator.mapper.median_ms << " ms)\n";
  out << "diagnosis: " << Diagnose(r).summary << "\n";
  return out.str();
}

void WriteResultJson(const Scenario& scenario, const RunResult& r, const std::string& path) {
  nlohmann::json criteria = nlohmann::json::array();
  for (const auto& c : r.criteria) {
    criteria.push_back({{"name", c.name}, {"expected", c.expected}, {"actual", c.actual}, {"passed", c.passed}});
  }
  nlohmann::json map_stages = nlohmann::json::object();
  for (const auto& [name, stats] : r.navigator.map_stages) map_stages[name] = StageJson(stats);
  const nlohmann::json j = {
      {"scenario", scenario.name},
      {"map", r.map_backend},
      {"file", scenario.path},
      {"seed", r.seed},
      {"passed", r.passed},
      {"end_reason", r.end_reason},
      {"criteria", criteria},
      {"sim_time_s", r.sim_time_s},
      {"wall_time_s", r.wall_time_s},
      {"real_time_factor", r.real_time_factor},
      {"distance_m", r.distance_m},
      {"route_progress_m", r.route_progress_m},
      {"route_length_m", r.route_length_m},
      {"map_updates", r.navigator.map_updates},
      {"map_failures", r.navigator.map_failures},
      {"plans", r.navigator.plans},
      {"replans_found", r.navigator.replans_found},
      {"plan_outcomes", r.navigator.plan_outcomes},
      {"collision_steps", r.collision_steps},
      {"collisions", r.collisions},
      {"files", r.files},
      {"config", RunConfigJson(scenario)},
      {"diagnosis", DiagnosisJson(Diagnose(r))},
      {"timing", {{"physics_lidar", StageJson(r.physics_lidar)},
                  {"buffer", StageJson(r.navigator.buffer)},
                  {"map_update", StageJson(r.navigator.mapper)},
                  {"map_stages", map_stages},
                  {"planning", StageJson(r.navigator.planner)},
                  {"control", StageJson(r.navigator.controller)}}},
  };
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << j.dump(2) << "\n";
  out.close();
  if (!out) throw std::runtime_error(path + ": could not write it whole (disk full?)");
}

namespace {
// Closes a written file and throws if any of it could not be written (a full disk shows here).
void CloseChecked(std::ofstream& out, const std::string& path) {
  out.close();
  if (!out) throw std::runtime_error(path + ": could not write it whole (disk full?)");
}
}  // namespace

void WriteTrajectoryCsv(const RunResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << "time_s,true_x_m,true_y_m,true_z_m,true_yaw_rad,odom_x_m,odom_y_m,odom_z_m,odom_yaw_rad,speed_mps,"
         "cmd_steering_rad,cmd_speed_mps\n";
  out << std::setprecision(9);
  for (const auto& s : r.trajectory) {
    const Vec3 t = s.T_W_B.translation(), o = s.T_O_B.translation();
    out << s.time_s << "," << t.x() << "," << t.y() << "," << t.z() << "," << Yaw(s.T_W_B) << "," << o.x() << ","
        << o.y() << "," << o.z() << "," << Yaw(s.T_O_B) << "," << s.speed_mps << "," << s.cmd_steering_rad << ","
        << s.cmd_speed_mps << "\n";
  }
  CloseChecked(out, path);
}

void WriteCyclesCsv(const RunResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << "time_s,cloud_points,map_ok,trigger,outcome,prepare_ms,map_ms,plan_ms,prepare_cpu_ms,map_cpu_ms,plan_cpu_ms\n"
      << std::setprecision(9);
  for (const navigation::CycleRecord& c : r.cycles) {
    out << c.time_s << "," << c.cloud_points << "," << (c.map_ok ? 1 : 0) << "," << c.trigger << "," << c.outcome << ","
        << c.prepare_ms << "," << c.map_ms << "," << c.plan_ms << "," << c.prepare_cpu_ms << "," << c.map_cpu_ms << ","
        << c.plan_cpu_ms << "\n";
  }
  CloseChecked(out, path);
}

void WritePlansCsv(const RunResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << "time_s,reason,blocked_at_m,blocked_by,vehicle_x_m,vehicle_y_m,vehicle_yaw_rad,goal_x_m,goal_y_m,goal_yaw_rad,goal_progress_m,outcome,"
         "iterations";
  for (std::size_t c = 0; c < planner::kNumPoseChecks; ++c) {
    std::string name = planner::PoseCheckName(static_cast<planner::PoseCheck>(c));
    std::replace(name.begin(), name.end(), ' ', '_');
    out << ",states_" << name;
  }
  out << "\n" << std::setprecision(9);
  for (const PlanRecord& record : r.plan_log) {
    const navigation::PlanAttempt& p = record.attempt;
    const Eigen::Vector3d vehicle_W = record.VehicleW();
    out << p.time_s << "," << p.reason << "," << p.blocked_at_m << "," << p.blocked_by << "," << vehicle_W.x() << ","
        << vehicle_W.y() << "," << vehicle_W.z() << ",";
    if (p.has_goal) {
      const Eigen::Vector3d goal_W = record.GoalW();
      out << goal_W.x() << "," << goal_W.y() << "," << goal_W.z() << "," << p.goal_progress_m;
    } else {
      out << ",,,";
    }
    out << "," << p.outcome << "," << p.iterations;
    for (std::size_t n : p.state_checks) out << "," << n;
    out << "\n";
  }
  CloseChecked(out, path);
}

void WriteTopdownPng(const Scenario& scenario, const RunResult& r, const std::string& path) {
  // Extent: route, start, trajectory and goal, with a margin, inside the terrain.
  Eigen::Vector2d lo(scenario.sim.start_x_m, scenario.sim.start_y_m), hi = lo;
  auto grow = [&](const Eigen::Vector2d& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); };
  for (const auto& p : scenario.route_m) grow(p);
  for (const auto& s : r.trajectory) grow(s.T_W_B.translation().head<2>());
  if (scenario.criteria.goal_m) grow(*scenario.criteria.goal_m);
  lo -= Eigen::Vector2d(10, 10);
  hi += Eigen::Vector2d(10, 10);
  const double px_per_m = std::clamp(1000.0 / std::max(hi.x() - lo.x(), hi.y() - lo.y()), 2.0, 20.0);
  Canvas canvas(lo.x(), lo.y(), hi.x(), hi.y(), px_per_m);

  // Terrain: grey by height with hill shading.
  const sim::Heightfield terrain = sim::MakeHeightfield(scenario.sim.world.terrain);
  const double zmin = terrain.min_height_m(), zspan = std::max(1e-6, terrain.max_height_m() - zmin);
  const Vec3 light = Vec3(-1, 1, 2).normalized();
  for (int py = 0; py < canvas.height(); ++py) {
    for (int px = 0; px < canvas.width(); ++px) {
      const Eigen::Vector2d w = canvas.World(px, py);
      const double h = (terrain.HeightAt(w.x(), w.y()) - zmin) / zspan;
      const double shade = std::clamp(terrain.NormalAt(w.x(), w.y()).dot(light), 0.0, 1.0);
      const int g = static_cast<int>(150 + 60 * h + 45 * (shade - 0.8));
      canvas.Set(px, py, {g, g, std::min(255, g + 10)});
    }
  }
  // Objects: footprints of every solid (dark), roofs lighter.
  for (const sim::Solid& s : sim::ResolveSolids(scenario.sim.world, terrain)) {
    const bool elevated = s.T_W_X.translation().z() - terrain.HeightAt(s.T_W_X.translation().x(), s.T_W_X.translation().y()) -
                              s.half_extents.z() > 1.0;
    const std::array<int, 3> colour = elevated ? std::array<int, 3>{120, 90, 170} : std::array<int, 3>{70, 60, 50};
    const double reach = s.half_extents.head<2>().norm();
    const Eigen::Isometry3d T_X_W = s.T_W_X.inverse();
    const Vec3 c = s.T_W_X.translation();
    // Only the part on the picture: the loops scale with the image, not with the object.
    for (double y = std::max(c.y() - reach, lo.y()); y <= std::min(c.y() + reach, hi.y()); y += 0.5 / px_per_m) {
      for (double x = std::max(c.x() - reach, lo.x()); x <= std::min(c.x() + reach, hi.x()); x += 0.5 / px_per_m) {
        const Vec3 p = T_X_W * Vec3(x, y, c.z());
        bool inside;
        if (s.shape == sim::Solid::Shape::kBox) {
          inside = std::abs(p.x()) <= s.half_extents.x() && std::abs(p.y()) <= s.half_extents.y();
        } else {
          inside = (p.x() * p.x()) / (s.half_extents.x() * s.half_extents.x()) +
                       (p.y() * p.y()) / (s.half_extents.y() * s.half_extents.y()) <= 1.0;
        }
        if (inside) canvas.Dot({x, y}, 0, colour, elevated ? 0.45 : 0.9);
      }
    }
  }
  for (const Region& region : scenario.criteria.forbidden) {
    for (double y = std::max(region.min_m.y(), lo.y()); y <= std::min(region.max_m.y(), hi.y()); y += 0.5 / px_per_m)
      for (double x = std::max(region.min_m.x(), lo.x()); x <= std::min(region.max_m.x(), hi.x()); x += 0.5 / px_per_m)
        canvas.Dot({x, y}, 0, {230, 120, 0}, 0.25);
  }
  // The robot's maps: traversable green, not traversable red.
  for (const MapPoint& p : r.map_points) {
    canvas.Dot(p.position_W.head<2>(), 0, p.traversable ? std::array<int, 3>{30, 170, 60} : std::array<int, 3>{210, 40, 40}, 0.35);
  }
  for (std::size_t i = 0; i + 1 < scenario.route_m.size(); ++i) canvas.Line(scenario.route_m[i], scenario.route_m[i + 1], 0, {40, 80, 220});
  for (std::size_t i = 0; i + 1 < r.trajectory.size(); ++i) {
    canvas.Line(r.trajectory[i].T_W_B.translation().head<2>(), r.trajectory[i + 1].T_W_B.translation().head<2>(), 1, {0, 0, 0});
  }
  canvas.Dot({scenario.sim.start_x_m, scenario.sim.start_y_m}, 4, {40, 80, 220});
  if (scenario.criteria.goal_m) {
    canvas.Dot(*scenario.criteria.goal_m, static_cast<int>(scenario.criteria.goal_radius_m * px_per_m), {250, 200, 0}, 0.4);
  }
  sim::WritePng(canvas.image(), path);
}

}  // namespace ovpc::scenarios
