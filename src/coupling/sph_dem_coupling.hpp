#pragma once
// Two-way SPH-DEM coupling step (the wet mill's, and the momentum test's): one SPH step of dt
// with the DEM sub-stepped under held fluid loads inside it.
//
// Momentum: the pair forces between fluid and body particles are equal and opposite, and the
// impulse each ball receives is the one its shell took from the fluid in that same step
// (SphEngine::bodyImpulses: dt x the mid-step load for the symplectic integrator, the fluid's
// leap-frog share for Verlet), handed to the DEM as a load held over the step (J / dt; the DEM
// replaces the old held load in its current force, so its sub-steps deliver exactly J). Fluid +
// balls then conserve linear momentum up to rounding, apart from what fixed walls exchange.
// Bodies after the balls (`held`) stay where they are: walls made of body particles, whose
// accumulated impulse is booked (heldImpulse), so a closed box's momentum budget can be closed.
//
// Sequence of one step (dt from the SPH CFL condition of the last evaluation):
//   symplectic: shells at x + dt/2 v, predictor and mid-step forces; Verlet: the last forces;
//   J = bodyImpulses(); DEM over dt under J / dt; shells at the balls' new state; SPH step ends.
#include <array>
#include <cstddef>
#include <vector>

#include "dem/dem_engine.hpp"
#include "sph/sph_engine.hpp"

namespace millsim::coupling {

class SphDemCoupling {
 public:
  // Bodies 0..balls-1 of the SPH state are the DEM's balls 0..balls-1 (same order); bodies
  // balls.. are the `held` ones.
  SphDemCoupling(std::size_t balls, std::vector<sph::SphBody> held = {});

  // Places the shells at the DEM's balls and evaluates the first forces.
  void initialize(sph::SphEngine& sph, const dem::DemHostState& balls, const sph::SphMotion& now);

  // One coupled step. `half(dt)` gives the moving boundaries at mid-step; `dem_steps(dt)` advances
  // the DEM by dt (its own sub-steps, held loads already set) and returns the moving boundaries
  // at the end. Returns dt. (Callables, not std::function: a capturing lambda would allocate.)
  template <class Half, class DemSteps>
  double advance(sph::SphEngine& sph, dem::DemEngine& dem, Half&& half, DemSteps&& dem_steps) {
    const double dt = sph.nextDt();
    startStep(sph, dem, dt, half(dt));
    finishStep(sph, dem, dt, dem_steps(dt));
    return dt;
  }

  // Impulse the fluid delivered to the held bodies since initialize(), N s (per held body).
  const std::vector<std::array<double, 3>>& heldImpulse() const { return m_held_impulse; }

 private:
  // The step up to the DEM's sub-steps (fluid loads handed over), and from after them.
  void startStep(sph::SphEngine& sph, dem::DemEngine& dem, double dt, const sph::SphMotion& half);
  void finishStep(sph::SphEngine& sph, dem::DemEngine& dem, double dt, const sph::SphMotion& end);
  void readBalls(const std::vector<double>& pos, const std::vector<double>& vel, const std::vector<double>& omega);
  // The balls moved by lead x v, then the held bodies, in m_bodies.
  const std::vector<sph::SphBody>& bodiesAt(double lead);

  std::size_t m_balls;
  std::vector<sph::SphBody> m_held, m_now;  // m_now: the balls at the start of the next step
  std::vector<std::array<double, 3>> m_held_impulse;
  // Per-step buffers, sized at construction: a coupled step allocates nothing.
  std::vector<sph::SphBody> m_bodies;
  std::vector<double> m_force, m_torque;
  dem::BallKinematics m_kinematics;
};

}  // namespace millsim::coupling
