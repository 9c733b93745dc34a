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

namespace ovpc::scenarios {
namespace {

nlohmann::json StageJson(const StageStats& s) {
  return {{"calls", s.calls}, {"mean_ms", s.mean_ms}, {"median_ms", s.median_ms},
          {"p90_ms", s.p90_ms}, {"p99_ms", s.p99_ms}, {"max_ms", s.max_ms}, {"total_ms", s.total_ms}};
}

double Yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

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
  out << "time_s,reason,blocked_at_m,blocked_by,vehicle_x_m,vehicle_y_m,vehicle_yaw_rad,goal_x_m,goal_y_m,goal_yaw_rad,goal_progress_m,"
         "goal_is_look,outcome,iterations";
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
      out << goal_W.x() << "," << goal_W.y() << "," << goal_W.z() << "," << p.goal_progress_m << "," << (p.goal_is_look ? 1 : 0);
    } else {
      out << ",,,,";
    }
    out << "," << p.outcome << "," << p.iterations;
    for (std::size_t n : p.state_checks) out << "," << n;
    out << "\n";
  }
  CloseChecked(out, path);
}

}  // namespace ovpc::scenarios
