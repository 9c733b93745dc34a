#include "ovpc/sim/world_model.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "xml_util.h"

namespace ovpc::sim {
namespace {

using xml::Num;
using xml::Quat;
using xml::Vec;

constexpr const char* kTerrainName = "terrain";
constexpr double kHeightfieldBase_m = 1.0;     // solid depth under the lowest point
constexpr double kMinHeightRange_m = 0.01;     // MuJoCo needs a positive vertical size
constexpr double kGroundTexture_m = 2.0;       // one checker tile of the ground texture

const char* ObjectRgba(const Solid& solid) {
  if (solid.name.rfind("carport", 0) == 0) return "0.55 0.55 0.6 1";
  switch (solid.shape) {
    case Solid::Shape::kBox:
      return "0.6 0.5 0.4 1";
    case Solid::Shape::kCylinder:
      return "0.45 0.35 0.25 1";
    case Solid::Shape::kEllipsoid:
    default:
      return "0.2 0.45 0.2 1";
  }
}

const char* MjcfType(Solid::Shape shape) {
  switch (shape) {
    case Solid::Shape::kBox:
      return "box";
    case Solid::Shape::kCylinder:
      return "cylinder";
    case Solid::Shape::kEllipsoid:
    default:
      return "ellipsoid";
  }
}

std::string SolidGeom(const Solid& solid) {
  const Vec3& h = solid.half_extents;
  // MuJoCo's cylinder size is (radius, half height).
  const std::string size = solid.shape == Solid::Shape::kCylinder
                               ? Num(h.x()) + " " + Num(h.z())
                               : Vec(h);
  return "<geom name=\"" + solid.name + "\" class=\"world\" type=\"" + MjcfType(solid.shape) +
         "\" pos=\"" + Vec(solid.T_W_X.translation()) + "\" quat=\"" +
         Quat(Eigen::Quaterniond(solid.T_W_X.linear())) + "\" size=\"" + size + "\" rgba=\"" +
         ObjectRgba(solid) + "\"/>\n";
}

double HeightRange(const Heightfield& terrain) {
  return std::max(terrain.max_height_m() - terrain.min_height_m(), kMinHeightRange_m);
}

}  // namespace

void PhysicsOptions::Validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("PhysicsOptions::") + what);
  };
  require(timestep_s > 0.0 && timestep_s <= 0.02, "timestep_s must be in (0, 0.02]");
  require(nconmax >= 1, "nconmax must be >= 1");
  require(njmax >= 1, "njmax must be >= 1");
  require(offscreen_width >= 16 && offscreen_width <= 8192, "offscreen_width out of [16, 8192]");
  require(offscreen_height >= 16 && offscreen_height <= 8192, "offscreen_height out of [16, 8192]");
}

std::string ModelPreambleXml(const PhysicsOptions& options) {
  options.Validate();
  std::ostringstream s;
  s << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "<option timestep=\"" << Num(options.timestep_s)
    << "\" integrator=\"implicit\" gravity=\"0 0 -9.81\"/>\n"
    << "<size nconmax=\"" << options.nconmax << "\" njmax=\"" << options.njmax << "\"/>\n"
    << "<visual>\n"
    << "<global offwidth=\"" << options.offscreen_width << "\" offheight=\""
    << options.offscreen_height << "\"/>\n"
    << "<quality shadowsize=\"0\" offsamples=\"0\"/>\n"
    << "<headlight ambient=\"0.35 0.35 0.35\" diffuse=\"0.5 0.5 0.5\"/>\n"
    << "</visual>\n";
  return s.str();
}

std::string WorldMjcf(const Heightfield& terrain, const std::vector<Solid>& solids,
                      const GatorParams& vehicle, const Eigen::Isometry3d& T_W_B,
                      const PhysicsOptions& options) {
  const double half_x = 0.5 * (terrain.x_max_m() - terrain.x_min_m());
  const double half_y = 0.5 * (terrain.y_max_m() - terrain.y_min_m());
  const Vec3 centre(terrain.x_min_m() + half_x, terrain.y_min_m() + half_y,
                    terrain.min_height_m());
  std::ostringstream s;
  s << "<mujoco model=\"ovpc_world\">\n"
    << ModelPreambleXml(options) << "<default>\n"
    << GatorDefaultsXml(vehicle) << "<default class=\"world\">\n"
    << "  <geom contype=\"1\" conaffinity=\"2\" condim=\"3\" friction=\"" << Num(vehicle.friction)
    << " 0.005 0.0001\"/>\n"
    << "</default>\n"
    << "</default>\n"
    << "<asset>\n"
    << "<hfield name=\"" << kTerrainName << "\" nrow=\"" << terrain.num_rows() << "\" ncol=\""
    << terrain.num_cols() << "\" size=\"" << Num(half_x) << " " << Num(half_y) << " "
    << Num(HeightRange(terrain)) << " " << Num(kHeightfieldBase_m) << "\"/>\n"
    << "<texture name=\"ground\" type=\"2d\" builtin=\"checker\" rgb1=\"0.45 0.42 0.33\" "
       "rgb2=\"0.4 0.37 0.29\" width=\"256\" height=\"256\"/>\n"
    << "<material name=\"ground\" texture=\"ground\" texrepeat=\""
    << Num(half_x / kGroundTexture_m) << " " << Num(half_y / kGroundTexture_m) << "\"/>\n"
    << "<texture name=\"sky\" type=\"skybox\" builtin=\"gradient\" rgb1=\"0.55 0.7 0.9\" "
       "rgb2=\"0.95 0.95 0.95\" width=\"256\" height=\"256\"/>\n"
    << "</asset>\n"
    << "<worldbody>\n"
    << "<light directional=\"true\" pos=\"0 0 50\" dir=\"-0.3 -0.2 -1\" castshadow=\"false\"/>\n"
    << "<geom name=\"" << kTerrainName << "\" class=\"world\" type=\"hfield\" hfield=\""
    << kTerrainName << "\" pos=\"" << Vec(centre) << "\" material=\"ground\"/>\n";
  for (const Solid& solid : solids) s << SolidGeom(solid);
  s << GatorBodyXml(vehicle, T_W_B) << "</worldbody>\n"
    << "<actuator>\n"
    << GatorActuatorsXml(vehicle) << "</actuator>\n"
    << "</mujoco>\n";
  return s.str();
}

void MjModelDeleter::operator()(mjModel_* model) const { mj_deleteModel(model); }

ModelPtr CompileMjcf(const std::string& xml, std::string* warning) {
  constexpr const char* kFileName = "model.xml";
  // mjVFS holds 2000 file names inline (about 2 MB): keep it off the stack.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), kFileName, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("CompileMjcf: could not create the virtual file");
  }
  const int index = mj_findFileVFS(vfs.get(), kFileName);
  std::memcpy(vfs->filedata[index], xml.data(), xml.size());
  char error[1024] = {0};
  mjModel* model = mj_loadXML(kFileName, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (model == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
  if (warning != nullptr) *warning = error;
  return ModelPtr(model);
}

void FillHeightfield(const Heightfield& terrain, mjModel_* model) {
  const int id = mj_name2id(model, mjOBJ_HFIELD, kTerrainName);
  if (id < 0) throw std::invalid_argument("FillHeightfield: the model has no hfield 'terrain'");
  if (model->hfield_nrow[id] != terrain.num_rows() || model->hfield_ncol[id] != terrain.num_cols()) {
    throw std::invalid_argument("FillHeightfield: the model's hfield grid differs from the terrain");
  }
  const double scale = 1.0 / model->hfield_size[4 * id + 2];
  float* data = model->hfield_data + model->hfield_adr[id];
  const double base = terrain.min_height_m();
  for (int r = 0; r < terrain.num_rows(); ++r) {
    for (int c = 0; c < terrain.num_cols(); ++c) {
      const double value = (terrain.At(r, c) - base) * scale;
      data[r * terrain.num_cols() + c] = static_cast<float>(std::clamp(value, 0.0, 1.0));
    }
  }
}

ModelPtr BuildWorldModel(const Heightfield& terrain, const std::vector<Solid>& solids,
                         const GatorParams& vehicle, const Eigen::Isometry3d& T_W_B,
                         const PhysicsOptions& options, std::string* warning) {
  ModelPtr model = CompileMjcf(WorldMjcf(terrain, solids, vehicle, T_W_B, options), warning);
  FillHeightfield(terrain, model.get());
  return model;
}

Eigen::Isometry3d RestingPose(const Heightfield& terrain, const GatorParams& vehicle, double x_m,
                              double y_m, double yaw_rad, double drop_m) {
  const Eigen::Matrix3d R_yaw = Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 origin(x_m, y_m, 0.0);
  auto ground = [&](double bx, double by) {
    const Vec3 p = origin + R_yaw * Vec3(bx, by, 0.0);
    return terrain.HeightAt(p.x(), p.y());
  };
  const double half_track = 0.5 * vehicle.track_m;
  const double rear_left = ground(0.0, half_track);
  const double rear_right = ground(0.0, -half_track);
  const double front_left = ground(vehicle.wheelbase_m, half_track);
  const double front_right = ground(vehicle.wheelbase_m, -half_track);
  const double pitch = -std::atan2(0.5 * (front_left + front_right - rear_left - rear_right),
                                   vehicle.wheelbase_m);
  const double roll =
      std::atan2(0.5 * (rear_left + front_left - rear_right - front_right), vehicle.track_m);
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
  T_W_B.linear() = (Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()) *
                    Eigen::AngleAxisd(pitch, Vec3::UnitY()) * Eigen::AngleAxisd(roll, Vec3::UnitX()))
                       .toRotationMatrix();
  // The highest wheel contact decides the height, so no wheel starts inside the ground.
  double z_m = -1e300;
  for (const Vec3& wheel_B : {Vec3(0.0, half_track, 0.0), Vec3(0.0, -half_track, 0.0),
                              Vec3(vehicle.wheelbase_m, half_track, 0.0),
                              Vec3(vehicle.wheelbase_m, -half_track, 0.0)}) {
    const Vec3 offset_W = T_W_B.linear() * wheel_B;
    const Vec3 p = origin + offset_W;
    const double ground_m = terrain.HeightAt(p.x(), p.y());
    z_m = std::max(z_m, ground_m - offset_W.z());
  }
  T_W_B.translation() = Vec3(x_m, y_m, z_m + drop_m);
  return T_W_B;
}

}  // namespace ovpc::sim
