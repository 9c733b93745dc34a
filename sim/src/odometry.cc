#include "ovpc/sim/odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "random.h"

namespace ovpc::sim {
namespace {

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

Eigen::Matrix3d Yaw(double yaw_rad) {
  return Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
}

}  // namespace

double YawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

void OdometrySim::Config::Validate() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("OdometrySim::Config: " + what);
  };
  auto sigma = [&](double v, const char* field) {
    require(v >= 0.0 && std::isfinite(v), std::string(field) + " must be finite and >= 0");
  };
  sigma(drift_xy_m_per_sqrt_m, "drift_xy_m_per_sqrt_m");
  sigma(drift_z_m_per_sqrt_m, "drift_z_m_per_sqrt_m");
  sigma(drift_yaw_rad_per_sqrt_m, "drift_yaw_rad_per_sqrt_m");
  sigma(noise_xy_m, "noise_xy_m");
  sigma(noise_z_m, "noise_z_m");
  sigma(noise_yaw_rad, "noise_yaw_rad");
  for (std::size_t i = 0; i < bumps.size(); ++i) {
    const Bump& b = bumps[i];
    require(std::isfinite(b.time_s) && std::isfinite(b.forward_m) && std::isfinite(b.left_m) &&
                std::isfinite(b.up_m) && std::isfinite(b.yaw_rad),
            "bumps[" + std::to_string(i) + "] must be finite");
  }
}

OdometrySim::OdometrySim(const Config& config)
    : config_(config), rng_(std::make_unique<Rng>(config.seed)), bumps_(config.bumps) {
  config_.Validate();
  std::stable_sort(bumps_.begin(), bumps_.end(),
                   [](const Bump& a, const Bump& b) { return a.time_s < b.time_s; });
}

OdometrySim::~OdometrySim() = default;
OdometrySim::OdometrySim(OdometrySim&&) noexcept = default;
OdometrySim& OdometrySim::operator=(OdometrySim&&) noexcept = default;

void OdometrySim::Update(double time_s, const Eigen::Isometry3d& T_W_B) {
  if (!std::isfinite(time_s) || !T_W_B.matrix().allFinite()) {
    throw std::invalid_argument("OdometrySim::Update: time or pose is not finite");
  }
  if (started_ && time_s < time_s_) {
    throw std::invalid_argument("OdometrySim::Update: time went backwards");
  }
  const double yaw_true = YawOf(T_W_B.linear());
  Rng& rng = *rng_;
  if (!started_) {
    started_ = true;
    position_O_ = T_W_B.translation();
    yaw_O_ = yaw_true;
  } else {
    const Vec3 step_W = T_W_B.translation() - T_W_B_.translation();
    const double step_m = step_W.norm();
    const double yaw_prev = YawOf(T_W_B_.linear());
    // The true step in the previous heading frame, replayed in the odometry's heading.
    const Vec3 step_H = Yaw(yaw_prev).transpose() * step_W;
    const double sqrt_step = std::sqrt(step_m);
    position_O_ += Yaw(yaw_O_) * step_H;
    position_O_.x() += config_.drift_xy_m_per_sqrt_m * sqrt_step * rng.Gaussian();
    position_O_.y() += config_.drift_xy_m_per_sqrt_m * sqrt_step * rng.Gaussian();
    position_O_.z() += config_.drift_z_m_per_sqrt_m * sqrt_step * rng.Gaussian();
    yaw_O_ += WrapAngle(yaw_true - yaw_prev) +
              config_.drift_yaw_rad_per_sqrt_m * sqrt_step * rng.Gaussian();
    distance_m_ += step_m;
  }
  while (next_bump_ < bumps_.size() && bumps_[next_bump_].time_s <= time_s) {
    const Bump& b = bumps_[next_bump_++];
    position_O_ += Yaw(yaw_O_) * Vec3(b.forward_m, b.left_m, b.up_m);
    yaw_O_ += b.yaw_rad;
  }
  yaw_O_ = WrapAngle(yaw_O_);
  time_s_ = time_s;
  T_W_B_ = T_W_B;

  const Vec3 noise(config_.noise_xy_m * rng.Gaussian(), config_.noise_xy_m * rng.Gaussian(),
                   config_.noise_z_m * rng.Gaussian());
  const double yaw_reported = yaw_O_ + config_.noise_yaw_rad * rng.Gaussian();
  T_O_B_.translation() = position_O_ + noise;
  // True roll and pitch: only the heading is replaced.
  T_O_B_.linear() = Yaw(yaw_reported) * Yaw(yaw_true).transpose() * T_W_B.linear();
}

}  // namespace ovpc::sim
