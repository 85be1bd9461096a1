#pragma once
// Scene -> initial DEM state of a drum case: Bond classes, counts from the filling, placement in
// the generation drum. Errors name the case file and the <charge> line.
#include "dem/charge.hpp"
#include "dem/dem_engine.hpp"
#include "millsim/scene/scene.hpp"

namespace millsim::sim {

struct ChargeSetup {
  std::vector<dem::BallClass> classes;
  dem::DemHostState state;
  double generation_length = 0;
  double mean_radius = 0;  // mass-weighted, for the critical speed
  double min_radius = 0, max_radius = 0;
  double total_mass = 0;
};

ChargeSetup buildCharge(const scene::Scene& s);

// The same balls as DCDEM bodies (dem.representation = "dcdem"): each ball becomes the lattice
// of element particles at spacing dp that fills it (dcdem_bodies.hpp), with the ball's mass and
// velocities; the elements' radius is dp/2.
struct DcdemCharge {
  dem::DemHostState state;  // the elements
  dem::DemBodies bodies;
};

DcdemCharge dcdemCharge(const dem::DemHostState& balls, double dp);

}  // namespace millsim::sim
