#pragma once
// Host-side state and sums of the stirred-mill walls and pair hooks, passed through the
// backend-neutral DemEngine interface (dem_engine.hpp). Physics: walls/stirrer_walls.hpp,
// contact/lubrication.hpp, collision_stats.hpp.
#include <vector>

#include "dem/collision_stats.hpp"

namespace millsim::dem {

struct StirrerState {
  double radius = 0, length = 0, shaft_radius = 0;
  double omega = 0, phi = 0;  // stirrer angular velocity [rad/s] and angle [rad] about +z
  int disk_count = 0;
  double disk_radius = 0, disk_thickness = 0;
  std::vector<double> disk_z;
  int hole_count = 0;
  double hole_radius = 0, hole_ring_radius = 0;
};

struct StirredSums {
  double stirrer_torque = 0;          // N m about +z, on the stirrer (shaft + disks) from the beads
  double outer_torque = 0;            // N m about +z, on the still chamber from the beads
  double lubrication_dissipated = 0;  // J, accumulated
  CollisionTally totals{};            // summed over the beads
};

}  // namespace millsim::dem
