#include "ovpc/navigation/vehicle_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ovpc::navigation {

void VehicleModel::Validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("vehicle.") + name + " must be > 0");
  };
  positive(length_m, "length_m");
  positive(width_m, "width_m");
  positive(height_m, "height_m");
  positive(wheelbase_m, "wheelbase_m");
  positive(track_m, "track_m");
  positive(turning_radius_m, "turning_radius_m");
  if (!(rear_overhang_m >= 0.0) || rear_overhang_m >= length_m) {
    throw std::invalid_argument("vehicle.rear_overhang_m must be in [0, length_m)");
  }
  if (!(max_steering_rad > 0.0) || max_steering_rad >= DegToRad(90.0)) {
    throw std::invalid_argument("vehicle.max_steering_rad must be in (0, pi/2)");
  }
}

}  // namespace ovpc::navigation
