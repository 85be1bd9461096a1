#include "coupling/sph_dem_coupling.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace millsim::coupling {

SphDemCoupling::SphDemCoupling(std::size_t balls, std::vector<sph::SphBody> held)
    : m_balls(balls),
      m_held(std::move(held)),
      m_now(balls),
      m_held_impulse(m_held.size(), {0.0, 0.0, 0.0}),
      m_bodies(balls + m_held.size()),
      m_force(3 * balls),
      m_torque(3 * balls) {}

void SphDemCoupling::readBalls(const std::vector<double>& pos, const std::vector<double>& vel,
                               const std::vector<double>& omega) {
  if (pos.size() != 3 * m_balls)
    throw std::invalid_argument("SphDemCoupling: the DEM has " + std::to_string(pos.size() / 3) + " balls, the fluid " +
                                std::to_string(m_balls) + " ball bodies");
  for (std::size_t b = 0; b < m_balls; ++b)
    for (int a = 0; a < 3; ++a) {
      m_now[b].pos[a] = pos[3 * b + a];
      m_now[b].vel[a] = vel[3 * b + a];
      m_now[b].omega[a] = omega[3 * b + a];
    }
}

const std::vector<sph::SphBody>& SphDemCoupling::bodiesAt(double lead) {
  for (std::size_t b = 0; b < m_balls; ++b) {
    m_bodies[b] = m_now[b];
    for (int a = 0; a < 3; ++a) m_bodies[b].pos[a] += lead * m_now[b].vel[a];
  }
  std::copy(m_held.begin(), m_held.end(), m_bodies.begin() + static_cast<std::ptrdiff_t>(m_balls));
  return m_bodies;
}

void SphDemCoupling::initialize(sph::SphEngine& sph, const dem::DemHostState& balls, const sph::SphMotion& now) {
  readBalls(balls.pos, balls.vel, balls.omega);
  sph.setBodyKinematics(bodiesAt(0));
  sph.initialize(now);
}

void SphDemCoupling::startStep(sph::SphEngine& sph, dem::DemEngine& dem, double dt, const sph::SphMotion& half) {
  // The symplectic mid-step evaluation sees the shells where the balls will be at t + dt/2 if
  // they keep their velocity (the fluid is predicted the same way); Verlet evaluates nothing here.
  if (sph.evaluationsPerStep() == 2) sph.setBodyKinematics(bodiesAt(0.5 * dt));
  sph.beginStep(dt, half);
  const std::vector<sph::SphBodyLoad>& impulse = sph.bodyImpulses();
  if (m_balls > 0) {
    for (std::size_t b = 0; b < m_balls; ++b)
      for (int a = 0; a < 3; ++a) {
        m_force[3 * b + a] = impulse[b].force[a] / dt;
        m_torque[3 * b + a] = impulse[b].torque[a] / dt;
      }
    dem.setExternalForces(m_force, m_torque);
  }
  for (std::size_t k = 0; k < m_held.size(); ++k)
    for (int a = 0; a < 3; ++a) m_held_impulse[k][a] += impulse[m_balls + k].force[a];
}

void SphDemCoupling::finishStep(sph::SphEngine& sph, dem::DemEngine& dem, double dt, const sph::SphMotion& end) {
  if (m_balls > 0) {
    dem.ballKinematics(m_kinematics);
    readBalls(m_kinematics.pos, m_kinematics.vel, m_kinematics.omega);
  }
  sph.setBodyKinematics(bodiesAt(0));
  sph.endStep(dt, end);
}

}  // namespace millsim::coupling
