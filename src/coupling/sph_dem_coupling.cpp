#include "coupling/sph_dem_coupling.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace millsim::coupling {

SphDemCoupling::SphDemCoupling(std::size_t balls, std::vector<sph::SphBody> held)
    : m_balls(balls), m_held(std::move(held)), m_now(balls), m_held_impulse(m_held.size(), {0.0, 0.0, 0.0}) {}

void SphDemCoupling::readBalls(const dem::DemHostState& s) {
  if (s.size() != m_balls)
    throw std::invalid_argument("SphDemCoupling: the DEM has " + std::to_string(s.size()) + " balls, the fluid " +
                                std::to_string(m_balls) + " ball bodies");
  for (std::size_t b = 0; b < m_balls; ++b)
    for (int a = 0; a < 3; ++a) {
      m_now[b].pos[a] = s.pos[3 * b + a];
      m_now[b].vel[a] = s.vel[3 * b + a];
      m_now[b].omega[a] = s.omega[3 * b + a];
    }
}

std::vector<sph::SphBody> SphDemCoupling::bodiesAt(double lead) const {
  std::vector<sph::SphBody> all(m_now);
  if (lead != 0)
    for (auto& b : all)
      for (int a = 0; a < 3; ++a) b.pos[a] += lead * b.vel[a];
  all.insert(all.end(), m_held.begin(), m_held.end());
  return all;
}

void SphDemCoupling::initialize(sph::SphEngine& sph, const dem::DemHostState& balls, const sph::SphMotion& now) {
  readBalls(balls);
  sph.setBodyKinematics(bodiesAt(0));
  sph.initialize(now);
}

double SphDemCoupling::advance(sph::SphEngine& sph, dem::DemEngine& dem,
                               const std::function<sph::SphMotion(double)>& half,
                               const std::function<sph::SphMotion(double)>& dem_steps) {
  const double dt = sph.nextDt();
  // The symplectic mid-step evaluation sees the shells where the balls will be at t + dt/2 if
  // they keep their velocity (the fluid is predicted the same way); Verlet evaluates nothing here.
  if (sph.evaluationsPerStep() == 2) sph.setBodyKinematics(bodiesAt(0.5 * dt));
  sph.beginStep(dt, half(dt));
  const std::vector<sph::SphBodyLoad>& impulse = sph.bodyImpulses();
  if (m_balls > 0) {
    std::vector<double> force(3 * m_balls), torque(3 * m_balls);
    for (std::size_t b = 0; b < m_balls; ++b)
      for (int a = 0; a < 3; ++a) {
        force[3 * b + a] = impulse[b].force[a] / dt;
        torque[3 * b + a] = impulse[b].torque[a] / dt;
      }
    dem.setExternalForces(force, torque);
  }
  for (std::size_t k = 0; k < m_held.size(); ++k)
    for (int a = 0; a < 3; ++a) m_held_impulse[k][a] += impulse[m_balls + k].force[a];
  const sph::SphMotion end = dem_steps(dt);
  if (m_balls > 0) {
    readBalls(dem::ballStates(dem));
  }
  sph.setBodyKinematics(bodiesAt(0));
  sph.endStep(dt, end);
  return dt;
}

}  // namespace millsim::coupling
