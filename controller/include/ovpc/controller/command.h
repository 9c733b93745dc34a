// What the follower asks of the vehicle: independent of any simulator.
#pragma once

namespace ovpc::controller {

/// A steering angle of the (virtual, bicycle-model) front wheel and a signed wheel speed. The
/// closed loop maps these to the simulated vehicle's actuators.
struct Command {
  double steering_rad = 0.0;  ///< positive turns left
  double speed_mps = 0.0;     ///< negative drives backwards
  bool done = false;          ///< the end of the path is reached; the vehicle is told to stand
};

}  // namespace ovpc::controller
