#pragma once
// Building DCDEM rigid bodies on the host: element points at spacing dp, equal mass shares, the
// body's centre and inertia from the elements as point masses (paper eqs. 49-50), packed into
// the DemHostState (elements as particles) and DemBodies the DEM engine takes.
#include <array>
#include <vector>

#include "dem/dem_engine.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

// A ball as the paper's DualSPHysics set-up makes it: the points of a cubic lattice of spacing dp
// centred on the ball within radius - dp/2, so element spheres of radius dp/2 reach the ball's
// radius along the lattice axes (between them the surface is bumpy). Relative to the centre.
std::vector<core::Vec3<double>> latticeBallPoints(double radius, double dp);

class BodyAssembler {
 public:
  // Appends a body made of `points` (world positions) with element radius r_e and total mass,
  // moving with velocity v and angular velocity w (world frame) about its centre of mass.
  // outer_radius: the ball it stands for (front view, fluid shell); 0: the elements' bounding
  // radius about the centre.
  void addBody(const std::vector<core::Vec3<double>>& points, double element_radius, double mass,
               std::array<double, 3> v = {0, 0, 0}, std::array<double, 3> w = {0, 0, 0}, double outer_radius = 0);
  const DemHostState& state() const { return m_state; }
  const DemBodies& bodies() const { return m_bodies; }

 private:
  DemHostState m_state;
  DemBodies m_bodies{{0}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
};

}  // namespace millsim::dem
