#include "ovpc/sim/gator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ovpc/sim/world_model.h"
#include "xml_util.h"

namespace ovpc::sim {
namespace {

using xml::Num;
using xml::Quat;
using xml::Rgba;
using xml::Vec;

constexpr double kGravity_mps2 = 9.81;
// Share of a front wheel's mass in its steering knuckle (the rest spins).
constexpr double kKnuckleMassFraction = 0.25;
constexpr double kSteerArmature_kgm2 = 0.5;  // steering rack and column, seen at the knuckle
constexpr double kSteerDampingRatio = 0.8;
constexpr double kSteerMarginDeg = 5.0;      // knuckle range beyond the inner wheel's full lock
constexpr double kDriveSpeedMargin = 1.2;    // wheel speed range beyond top speed
constexpr double kLidarBaseMass_kg = 2.0;
// The VLP-16 housing: 103 mm across, 72 mm tall.
constexpr double kLidarRadius_m = 0.0515;
constexpr double kLidarHalfHeight_m = 0.036;
constexpr double kMastRadius_m = 0.04;
constexpr double kRopsTube_m = 0.04;         // half width of the frame's posts and roof thickness

const char* const kBodyRgba = "0.21 0.49 0.17 1";   // the green of the paint
const char* const kTyreRgba = "0.12 0.12 0.12 1";
const char* const kRimRgba = "0.95 0.8 0.1 1";
const char* const kFrameRgba = "0.15 0.15 0.15 1";
const char* const kLidarRgba = "0.75 0.75 0.78 1";

double Curvature(const GatorParams& p, double steering_rad) {
  return std::tan(steering_rad) / p.wheelbase_m;
}

double MaxSteerRad(const GatorParams& p) { return DegToRad(p.max_steer_deg); }

/// Knuckle angle of the inner wheel at full lock, plus a margin: the joint and actuator range.
double KnuckleRangeRad(const GatorParams& p) {
  const double k = Curvature(p, MaxSteerRad(p));
  return std::atan2(p.wheelbase_m * k, 1.0 - k * 0.5 * p.track_m) + DegToRad(kSteerMarginDeg);
}

double ChassisMass(const GatorParams& p) { return p.mass_kg - 4.0 * p.wheel_mass_kg; }

/// Diagonal inertia of a solid box of the given mass and full extents.
Vec3 BoxInertia(double mass_kg, double lx, double ly, double lz) {
  return mass_kg / 12.0 * Vec3(ly * ly + lz * lz, lx * lx + lz * lz, lx * lx + ly * ly);
}

/// Diagonal inertia of a wheel (solid disc spinning about y).
Vec3 WheelInertia(double mass_kg, double radius_m, double width_m) {
  const double across = mass_kg * (3.0 * radius_m * radius_m + width_m * width_m) / 12.0;
  return Vec3(across, 0.5 * mass_kg * radius_m * radius_m, across);
}

std::string Inertial(const Vec3& pos, double mass_kg, const Vec3& diag) {
  return "<inertial pos=\"" + Vec(pos) + "\" mass=\"" + Num(mass_kg) + "\" diaginertia=\"" +
         Vec(diag) + "\"/>";
}

/// A box geom spanning [lo, hi] in its parent body frame.
std::string BoxGeom(const std::string& name, const Vec3& lo, const Vec3& hi, const char* rgba,
                    const char* cls = "gator") {
  const std::string name_attr = name.empty() ? "" : "name=\"" + name + "\" ";
  return "<geom " + name_attr + "class=\"" + cls + "\" type=\"box\" pos=\"" +
         Vec(0.5 * (lo + hi)) + "\" size=\"" + Vec(0.5 * (hi - lo)) + "\" rgba=\"" + rgba + "\"/>";
}

/// Spring preload that puts a slide joint at 0 under `load_n`.
double SpringRef(const GatorParams& p, double load_n) {
  return -load_n / p.suspension_stiffness_n_per_m;
}

std::string SuspensionJoint(const GatorParams& p, const std::string& name, double load_n) {
  return "<joint name=\"" + name + "\" type=\"slide\" axis=\"0 0 1\" limited=\"true\" range=\"" +
         Num(-p.suspension_travel_m) + " " + Num(p.suspension_travel_m) + "\" stiffness=\"" +
         Num(p.suspension_stiffness_n_per_m) + "\" springref=\"" + Num(SpringRef(p, load_n)) +
         "\" damping=\"" + Num(p.suspension_damping_ns_per_m) + "\"/>";
}

/// The wheel's collision ellipsoid (round in the wheel plane, as wide as the tyre) and its look.
std::string WheelGeoms(const GatorParams& p, const std::string& corner) {
  const Eigen::Quaterniond axle_y(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()));
  std::string s;
  s += "<geom name=\"" + std::string(gator_names::kWheelGeomPrefix) + corner +
       "\" class=\"gator\" type=\"ellipsoid\" size=\"" +
       Vec(p.wheel_radius_m, 0.5 * p.wheel_width_m, p.wheel_radius_m) + "\" rgba=\"" + kTyreRgba +
       "\" group=\"2\"/>\n";
  s += "<geom class=\"gator_visual\" type=\"cylinder\" size=\"" + Num(p.wheel_radius_m) + " " +
       Num(0.5 * p.wheel_width_m) + "\" quat=\"" + Quat(axle_y) + "\" rgba=\"" + kTyreRgba +
       "\"/>\n";
  s += "<geom class=\"gator_visual\" type=\"cylinder\" size=\"" + Num(0.55 * p.wheel_radius_m) +
       " " + Num(0.5 * p.wheel_width_m + 0.005) + "\" quat=\"" + Quat(axle_y) + "\" rgba=\"" +
       kRimRgba + "\"/>\n";
  return s;
}

}  // namespace

void GatorParams::Validate() const {
  auto require = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("GatorParams::") + field + " " + what);
  };
  auto positive = [&](double v, const char* field) {
    require(v > 0.0 && std::isfinite(v), field, "must be > 0");
  };
  positive(max_speed_mps, "max_speed_mps");
  positive(length_m, "length_m");
  positive(width_m, "width_m");
  positive(wheelbase_m, "wheelbase_m");
  positive(track_m, "track_m");
  positive(wheel_radius_m, "wheel_radius_m");
  positive(wheel_width_m, "wheel_width_m");
  positive(mass_kg, "mass_kg");
  positive(wheel_mass_kg, "wheel_mass_kg");
  require(4.0 * wheel_mass_kg < mass_kg, "wheel_mass_kg", "times 4 must be below mass_kg");
  require(max_steer_deg > 0.0 && max_steer_deg < 60.0, "max_steer_deg", "must be in (0, 60)");
  require(rear_overhang_m >= 0.0, "rear_overhang_m", "must be >= 0");
  require(length_m > wheelbase_m + rear_overhang_m, "length_m",
          "must exceed wheelbase_m + rear_overhang_m");
  require(width_m >= track_m + wheel_width_m, "width_m", "must cover track_m + wheel_width_m");
  require(wheel_width_m < track_m, "wheel_width_m", "must be below track_m");
  positive(ground_clearance_m, "ground_clearance_m");
  require(body_top_m > 2.0 * wheel_radius_m + suspension_travel_m, "body_top_m",
          "must be above the wheels' top at full suspension travel");
  require(rops_height_m > body_top_m + 2.0 * kRopsTube_m, "rops_height_m",
          "must be above body_top_m");
  require(rops_rear_x_m < rops_front_x_m, "rops_rear_x_m", "must be below rops_front_x_m");
  require(rops_rear_x_m >= -rear_overhang_m && rops_front_x_m <= length_m - rear_overhang_m,
          "rops_rear_x_m/rops_front_x_m", "must lie within the body");
  require(cg_x_m > 0.0 && cg_x_m < wheelbase_m, "cg_x_m", "must lie between the axles");
  positive(cg_z_m, "cg_z_m");
  positive(friction, "friction");
  positive(suspension_travel_m, "suspension_travel_m");
  require(suspension_travel_m < ground_clearance_m, "suspension_travel_m",
          "must be below ground_clearance_m");
  positive(suspension_stiffness_n_per_m, "suspension_stiffness_n_per_m");
  positive(suspension_damping_ns_per_m, "suspension_damping_ns_per_m");
  positive(drive_gain_nms, "drive_gain_nms");
  positive(drive_max_torque_nm, "drive_max_torque_nm");
  positive(steer_gain_nm_per_rad, "steer_gain_nm_per_rad");
  require(lidar.height_m > body_top_m + 0.1, "lidar.height_m", "must be above the body");
  positive(lidar.scan_hz, "lidar.scan_hz");
  require(std::isfinite(lidar.spin_hz), "lidar.spin_hz", "must be finite");
  require(std::isfinite(lidar.tilt_rad), "lidar.tilt_rad", "must be finite");
  // The static spring deflection must fit in the travel with room to spare.
  const double rear_load_n =
      ChassisMass(*this) * kGravity_mps2 * (1.0 - cg_x_m / wheelbase_m) / 2.0;
  require(rear_load_n / suspension_stiffness_n_per_m < 2.0 * ground_clearance_m,
          "suspension_stiffness_n_per_m", "is too soft for the load");
}

double GatorParams::NominalTurnRadius_m() const {
  return wheelbase_m / std::tan(DegToRad(max_steer_deg));
}

WheelCommands AckermannCommands(const GatorParams& p, double steering_rad, double speed_mps) {
  const double max_steer = MaxSteerRad(p);
  const double steer = std::clamp(std::isfinite(steering_rad) ? steering_rad : 0.0, -max_steer,
                                  max_steer);
  const double speed = std::clamp(std::isfinite(speed_mps) ? speed_mps : 0.0, -p.max_speed_mps,
                                  p.max_speed_mps);
  const double k = Curvature(p, steer);
  const double half_track = 0.5 * p.track_m;
  WheelCommands out;
  out.steer_left_rad = std::atan2(p.wheelbase_m * k, 1.0 - k * half_track);
  out.steer_right_rad = std::atan2(p.wheelbase_m * k, 1.0 + k * half_track);
  out.drive_left_radps = speed * (1.0 - k * half_track) / p.wheel_radius_m;
  out.drive_right_radps = speed * (1.0 + k * half_track) / p.wheel_radius_m;
  return out;
}

std::string GatorDefaultsXml(const GatorParams& p) {
  std::ostringstream s;
  s << "<default class=\"gator\">\n"
    << "  <geom contype=\"2\" conaffinity=\"1\" condim=\"3\" friction=\"" << Num(p.friction)
    << " 0.005 0.0001\" density=\"0\"/>\n"
    << "  <default class=\"gator_visual\">\n"
    << "    <geom contype=\"0\" conaffinity=\"0\" group=\"1\" density=\"0\"/>\n"
    << "  </default>\n"
    << "</default>\n";
  return s.str();
}

namespace {

// Collision shapes of the body, all named body_*: frame between the wheels, deck over them,
// roll-over frame, mast; and the seats and hood, for the pictures only.
std::string ChassisShapesXml(const GatorParams& p) {
  const double r = p.wheel_radius_m;
  const double half_track = 0.5 * p.track_m;
  const double half_width = 0.5 * p.width_m;
  const double front_x = p.length_m - p.rear_overhang_m;
  std::ostringstream s;
  const double deck_bottom = 2.0 * r + p.suspension_travel_m + 0.02;
  const double frame_half_y = half_track - 0.5 * p.wheel_width_m - 0.03;
  s << BoxGeom("body_frame", Vec3(-p.rear_overhang_m, -frame_half_y, p.ground_clearance_m),
               Vec3(front_x, frame_half_y, deck_bottom), kFrameRgba)
    << "\n"
    << BoxGeom("body_deck", Vec3(-p.rear_overhang_m, -half_width, deck_bottom),
               Vec3(front_x, half_width, p.body_top_m), kBodyRgba)
    << "\n"
    << BoxGeom("body_rops_roof",
               Vec3(p.rops_rear_x_m - kRopsTube_m, -half_width + 0.05,
                    p.rops_height_m - 2.0 * kRopsTube_m),
               Vec3(p.rops_front_x_m + kRopsTube_m, half_width - 0.05, p.rops_height_m),
               kBodyRgba)
    << "\n";
  int post = 0;
  for (const double x : {p.rops_rear_x_m, p.rops_front_x_m}) {
    for (const double side : {-1.0, 1.0}) {
      const double y = side * (half_width - 0.05 - kRopsTube_m);
      s << BoxGeom("body_rops_post" + std::to_string(post++),
                   Vec3(x - kRopsTube_m, y - kRopsTube_m, p.body_top_m),
                   Vec3(x + kRopsTube_m, y + kRopsTube_m, p.rops_height_m - 2.0 * kRopsTube_m),
                   kFrameRgba)
        << "\n";
    }
  }
  s << "<geom name=\"body_mast\" class=\"gator\" type=\"cylinder\" fromto=\"0 0 "
    << Num(p.body_top_m) << " 0 0 " << Num(p.lidar.height_m - kLidarRadius_m - 0.01)
    << "\" size=\"" << Num(kMastRadius_m) << "\" rgba=\"" << kFrameRgba << "\"/>\n";
  s << BoxGeom("", Vec3(p.rops_rear_x_m + 0.05, -half_width + 0.15, p.body_top_m),
               Vec3(p.rops_rear_x_m + 0.5, half_width - 0.15, p.body_top_m + 0.35),
               "0.95 0.8 0.1 1", "gator_visual")
    << "\n";
  return s.str();
}

// The spinning LiDAR base; the simulator sets its angle from the mount's clock every step.
std::string LidarBaseXml(const GatorParams& p) {
  namespace n = gator_names;
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(p.lidar.tilt_rad, Vec3::UnitX()));
  std::ostringstream s;
  s << "<body name=\"" << n::kLidarBase << "\" pos=\"0 0 " << Num(p.lidar.height_m) << "\">\n"
    << "<joint name=\"" << n::kLidarSpin << "\" type=\"hinge\" axis=\"0 0 1\"/>\n"
    << Inertial(Vec3::Zero(), kLidarBaseMass_kg, Vec3(0.01, 0.01, 0.01)) << "\n"
    << "<geom name=\"body_lidar\" class=\"gator\" type=\"cylinder\" size=\""
    << Num(kLidarRadius_m) << " " << Num(kLidarHalfHeight_m) << "\" quat=\"" << Quat(tilt)
    << "\" rgba=\"" << kLidarRgba << "\"/>\n"
    << "<site name=\"" << n::kLidarSite << "\" quat=\"" << Quat(tilt) << "\" size=\"0.02\"/>\n"
    << "</body>\n";
  return s.str();
}

// Wheels. Rear: suspension slide + driven axle. Front: suspension slide + steering knuckle, then a
// free-rolling wheel. Each suspension carries its share of the chassis's weight.
std::string WheelBodiesXml(const GatorParams& p) {
  namespace n = gator_names;
  const double r = p.wheel_radius_m;
  const double half_track = 0.5 * p.track_m;
  const double chassis_mass = ChassisMass(p);
  const double front_load_n = chassis_mass * kGravity_mps2 * (p.cg_x_m / p.wheelbase_m) / 2.0;
  const double rear_load_n = chassis_mass * kGravity_mps2 - 2.0 * front_load_n;
  const double knuckle_mass = kKnuckleMassFraction * p.wheel_mass_kg;
  const double spin_mass = p.wheel_mass_kg - knuckle_mass;
  const double knuckle_range = KnuckleRangeRad(p);
  const Vec3 spin_inertia = WheelInertia(spin_mass, r, p.wheel_width_m);
  // Steering: damping for the chosen ratio with the knuckle, wheel and armature inertia.
  const double steer_inertia = spin_inertia.z() + knuckle_mass * 0.01 + kSteerArmature_kgm2;
  const double steer_damping =
      2.0 * kSteerDampingRatio * std::sqrt(p.steer_gain_nm_per_rad * steer_inertia);
  struct Side {
    const char* name;
    double sign;
    const char* steer_joint;
    const char* drive_joint;
  };
  const Side sides[2] = {{"left", 1.0, n::kSteerLeft, n::kDriveLeft},
                         {"right", -1.0, n::kSteerRight, n::kDriveRight}};
  std::ostringstream s;
  for (const Side& side : sides) {
    const std::string corner = std::string("rear_") + side.name;
    s << "<body name=\"" << corner << "\" pos=\"" << Vec(0.0, side.sign * half_track, r)
      << "\">\n"
      << SuspensionJoint(p, "suspension_" + corner, 0.5 * rear_load_n) << "\n"
      << "<joint name=\"" << side.drive_joint << "\" type=\"hinge\" axis=\"0 1 0\"/>\n"
      << Inertial(Vec3::Zero(), p.wheel_mass_kg, WheelInertia(p.wheel_mass_kg, r, p.wheel_width_m))
      << "\n"
      << WheelGeoms(p, corner) << "</body>\n";
  }
  for (const Side& side : sides) {
    const std::string corner = std::string("front_") + side.name;
    s << "<body name=\"" << corner << "_knuckle\" pos=\""
      << Vec(p.wheelbase_m, side.sign * half_track, r) << "\">\n"
      << SuspensionJoint(p, "suspension_" + corner, front_load_n) << "\n"
      << "<joint name=\"" << side.steer_joint
      << "\" type=\"hinge\" axis=\"0 0 1\" limited=\"true\" range=\"" << Num(-knuckle_range) << " "
      << Num(knuckle_range) << "\" armature=\"" << Num(kSteerArmature_kgm2) << "\" damping=\""
      << Num(steer_damping) << "\"/>\n"
      << Inertial(Vec3::Zero(), knuckle_mass, Vec3(0.05, 0.05, 0.05)) << "\n"
      << "<body name=\"" << corner << "\">\n"
      << "<joint name=\"roll_" << corner << "\" type=\"hinge\" axis=\"0 1 0\"/>\n"
      << Inertial(Vec3::Zero(), spin_mass, spin_inertia) << "\n"
      << WheelGeoms(p, corner) << "</body>\n"
      << "</body>\n";
  }
  return s.str();
}

}  // namespace

std::string GatorBodyXml(const GatorParams& p, const Eigen::Isometry3d& T_W_B) {
  p.Validate();
  namespace n = gator_names;
  const double chassis_mass = ChassisMass(p);
  const Eigen::Quaterniond q_W_B(T_W_B.linear());
  std::ostringstream s;
  s << "<body name=\"" << n::kChassis << "\" pos=\"" << Vec(T_W_B.translation()) << "\" quat=\""
    << Quat(q_W_B) << "\">\n"
    << "<freejoint name=\"chassis_free\"/>\n"
    << Inertial(Vec3(p.cg_x_m, 0.0, p.cg_z_m), chassis_mass,
                BoxInertia(chassis_mass, p.length_m, p.width_m, p.body_top_m))
    << "\n"
    << ChassisShapesXml(p) << LidarBaseXml(p) << WheelBodiesXml(p) << "</body>\n";
  return s.str();
}

std::string GatorActuatorsXml(const GatorParams& p) {
  namespace n = gator_names;
  const double knuckle_range = KnuckleRangeRad(p);
  const double max_wheel_speed =
      kDriveSpeedMargin * p.max_speed_mps * (1.0 + Curvature(p, MaxSteerRad(p)) * 0.5 * p.track_m) /
      p.wheel_radius_m;
  std::ostringstream s;
  for (const char* joint : {n::kSteerLeft, n::kSteerRight}) {
    s << "<position name=\"" << joint << "\" joint=\"" << joint << "\" kp=\""
      << Num(p.steer_gain_nm_per_rad) << "\" ctrllimited=\"true\" ctrlrange=\""
      << Num(-knuckle_range) << " " << Num(knuckle_range) << "\"/>\n";
  }
  for (const char* joint : {n::kDriveLeft, n::kDriveRight}) {
    s << "<velocity name=\"" << joint << "\" joint=\"" << joint << "\" kv=\""
      << Num(p.drive_gain_nms) << "\" ctrllimited=\"true\" ctrlrange=\"" << Num(-max_wheel_speed)
      << " " << Num(max_wheel_speed) << "\" forcelimited=\"true\" forcerange=\""
      << Num(-p.drive_max_torque_nm) << " " << Num(p.drive_max_torque_nm) << "\"/>\n";
  }
  return s.str();
}

std::string GatorStandaloneXml(const GatorParams& p) {
  const PhysicsOptions options;
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
  std::ostringstream s;
  s << "<!-- The Gator-like vehicle of the OVPC testbed on a plane. Generated by\n"
    << "     ovpc::sim::GatorStandaloneXml() from GatorParams' defaults (sim/include/ovpc/sim/gator.h);\n"
    << "     the simulator generates the same vehicle into every world. Do not edit by hand: change\n"
    << "     GatorParams and regenerate (see models/README.md). -->\n"
    << "<mujoco model=\"gator\">\n"
    << ModelPreambleXml(options) << "<default>\n"
    << GatorDefaultsXml(p) << "</default>\n"
    << "<asset>\n"
    << "<texture name=\"ground\" type=\"2d\" builtin=\"checker\" rgb1=\"0.45 0.42 0.33\" "
       "rgb2=\"0.4 0.37 0.29\" width=\"256\" height=\"256\"/>\n"
    << "<material name=\"ground\" texture=\"ground\" texrepeat=\"20 20\"/>\n"
    << "</asset>\n"
    << "<worldbody>\n"
    << "<light directional=\"true\" pos=\"0 0 20\" dir=\"-0.3 -0.2 -1\" castshadow=\"false\"/>\n"
    << "<geom name=\"ground\" type=\"plane\" size=\"20 20 0.1\" material=\"ground\" contype=\"1\" "
       "conaffinity=\"2\" friction=\""
    << Num(p.friction) << " 0.005 0.0001\"/>\n"
    << GatorBodyXml(p, T_W_B) << "</worldbody>\n"
    << "<actuator>\n"
    << GatorActuatorsXml(p) << "</actuator>\n"
    << "</mujoco>\n";
  return s.str();
}

}  // namespace ovpc::sim
