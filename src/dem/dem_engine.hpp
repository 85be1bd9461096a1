#pragma once
// Backend-neutral face of the DEM solver. The time loop (src/sim) drives an engine through this
// interface; DemSolver<Space, T> implements it once for every execution space and precision.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dem/contact/damping.hpp"
#include "dem/stirrer_state.hpp"

namespace millsim::dem {

// An ensemble of drum scenes in one solver (ensemble.hpp: scene k in its own slab along z, its
// own drum and contact law). Empty `start`: a single scene, the plain solver.
struct DemEnsemble {
  std::vector<int> start;               // host numbers of scene k: [start[k], start[k + 1])
  double origin = 0, pitch = 0;         // scene k's slab: z in [origin + k pitch, origin + (k + 1) pitch)
  double lead = 0;                      // scene k's local z = 0 (its front plate) at origin + k pitch + lead
  std::vector<double> alpha, friction;  // contact law per scene (k_coef and the law's kind are the setup's)
  std::vector<double> skin;             // neighbour skin per scene (empty: the setup's for all; the setup's
                                        // skin, at least the largest, sizes the cells)
  int scenes() const { return start.empty() ? 0 : static_cast<int>(start.size()) - 1; }
};

struct DemSetup {
  double k_coef = 0;            // 4/3 E*
  double alpha = 0;             // damping, see damping.hpp
  double wall_mass_factor = 1;  // m* of a wall contact = factor * m
  double friction = 0;
  bool tanh_smoothing = false;
  bool dualsphysics_tangential = false;  // drum walls only: HertzDualSphysicsTangential
  std::array<double, 3> gravity{0, -9.81, 0};
  double skin = 0;                                 // neighbour-list skin [m]
  std::array<double, 3> domain_lo{}, domain_hi{};  // box covering every particle position
  double max_radius = 0;
  // Stirred mill (StirrerState walls): contact law, collision tallies, lubrication.
  bool linear_law = false;           // seed 004's linear spring-dashpot instead of Hertz
  double linear_kn = 0;              // N/m
  double linear_zeta = 0;            // damping ratio (linearDampingRatio(e))
  double lubrication_viscosity = 0;  // Pa s; 0: no lubrication stage and no arrays for it
  double lubrication_inner = 0.001, lubrication_outer = 0.05;
  bool collision_stats = true;  // Beinert tallies per contact (a <collisions> element); off: no tally arrays
  DemEnsemble ensemble;         // several drum scenes at once (spheres only); empty: one scene
};

// Plain host copy of the state: what checkpoints, writers and tests read and write.
struct DemHostState {
  std::vector<double> pos, vel, omega;  // 3 per particle
  std::vector<double> radius, mass, inertia;
  std::vector<std::int64_t> hist_id;  // kHistorySlots per particle
  std::vector<double> hist_xi;        // 3 * kHistorySlots per particle
  std::vector<double> dissipated, work_in;
  // Work of the external (fluid) loads on each particle, J (DemSums::work_external); empty
  // without external loads. A restart needs it for the energy budget to carry on.
  std::vector<double> work_external;
  // The force and torque the next step's first half-kick uses (contacts and gravity; held
  // external loads left out: they are set again by whoever holds them), 3 per particle. The
  // velocity Verlet step evaluates them with the half-step velocity, which the state does not
  // hold, so a restart takes them from here instead of evaluating them anew with v(t) (that
  // moved every damped and sliding contact: kinetic energy 2.5e-7 off after one step). Empty:
  // evaluated from the state (a new run).
  std::vector<double> force, torque;
  std::size_t size() const { return radius.size(); }
};

// DCDEM rigid bodies (rigid_body.hpp): the elements of body b are the state's particles with host
// numbers start[b] .. start[b + 1] - 1, the first start.back() particles; the particles after
// them are free spheres. An element's mass in the state is its share of the body's (M / count:
// gravity, energies and the centre of mass then sum right), its inertia 0; contacts use the
// body's mass for the damping, as DualSPHysics's DEM between floating bodies does.
struct DemBodies {
  std::vector<int> start;        // size() + 1
  std::vector<double> pos, vel;  // centre of mass and its velocity, 3 per body
  std::vector<double> ang_mom;   // angular momentum about the centre, world frame, 3 per body
  std::vector<double> quat;      // orientation (w, x, y, z): body frame -> world, 4 per body
  std::vector<double> mass;
  std::vector<double> inertia;        // body frame, about the centre: xx, yy, zz, xy, xz, yz per body
  std::vector<double> offset;         // element positions in the body frame, 3 per element
  std::vector<double> radius;         // the ball's radius (front view, fluid shell), per body
  std::vector<double> work_external;  // work of the external (fluid) loads, J, per body; empty: none
  std::size_t size() const { return mass.size(); }
  int elements() const { return start.empty() ? 0 : start.back(); }
};

struct DrumState {
  double radius = 0, z_back = 0, v_back = 0, omega = 0, phi = 0, phase0 = 0;
  int lifter_count = 0;
  double lifter_height = 0, lifter_width = 0;
};

struct DemSums {
  double kinetic = 0;           // translational + rotational, J
  double potential = 0;         // -sum m g . x, J
  double dissipated = 0;        // accumulated, J
  double work_in = 0;           // accumulated work of the walls on the balls, J
  double work_external = 0;     // accumulated work of the external (fluid) forces on the balls, J
  double elastic = 0;           // normal elastic energy stored in contacts now, J
  double drum_torque = 0;       // moment of the charge on the drum about +z now, N m
  double max_speed = 0;         // m/s
  double mass = 0;              // kg, total
  double com_x = 0, com_y = 0;  // centre of mass in the front view, m (the gravity moment's arm)
  double pair_contacts = 0;     // particle pairs overlapping now (coordination number = 2 x this / N)
};

// Positions, velocities and spins of the balls, 3 per ball in host order (per DCDEM body, in
// body order, when the engine has bodies): what a coupling reads every step.
struct BallKinematics {
  std::vector<double> pos, vel, omega;
  std::size_t size() const { return pos.size() / 3; }
};

class DemEngine {
 public:
  virtual ~DemEngine() = default;
  virtual const char* backendName() const = 0;
  virtual const char* precisionName() const = 0;
  virtual void setState(const DemHostState& state) = 0;
  virtual void getState(DemHostState& state) const = 0;
  // Rigid bodies over the state's first particles (after setState, before initialize); empty:
  // none. getBodies returns the bodies' current state.
  virtual void setBodies(const DemBodies& bodies) = 0;
  virtual void getBodies(DemBodies& bodies) const = 0;
  // Builds the neighbour list and the forces of the current state (call after setState).
  virtual void initialize(const DrumState& walls) = 0;
  // One velocity-Verlet step; `walls` is the wall state at the end of the step.
  virtual void step(const DrumState& walls, double dt) = 0;
  virtual DemSums sums() const = 0;
  virtual std::map<std::string, std::size_t> memoryBytes() const = 0;
  virtual std::int64_t neighbourRebuilds() const = 0;
  // Forces and torques from outside the DEM (the fluid on each ball in a wet mill), 3 per ball in
  // host order (per body, in body order, when there are DCDEM bodies), held until the next call
  // and added every step. Their work is booked in
  // DemSums::work_external. Empty vectors switch them off.
  virtual void setExternalForces(const std::vector<double>& force, const std::vector<double>& torque) = 0;
  // The balls' kinematics into `out` (resized; reused across steps, nothing else is copied: no
  // history, no neighbour list, no allocation once sized).
  virtual void ballKinematics(BallKinematics& out) const = 0;
  // Stirred mill: the same step with the stirrer's walls (and lubrication when set up).
  virtual void initialize(const StirrerState& walls) = 0;
  virtual void step(const StirrerState& walls, double dt) = 0;
  virtual StirredSums stirredSums() const = 0;
  // Ensembles (DemSetup::ensemble): the same step with every scene's drum and its own time step
  // (dt[k] = 0: scene k has ended and rests, no forces evaluated), in scene order, and the sums
  // of each scene (its particles' energies, work, torque, centre of mass in the ensemble's
  // frame: x and y as the scene's own, z shifted by its slab).
  virtual void initialize(const std::vector<DrumState>& drums) = 0;
  virtual void step(const std::vector<DrumState>& drums, const std::vector<double>& dt) = 0;
  // `wanted` (one flag per scene; empty: all) limits the work to the scenes asked for (each
  // scene's sums are ~11 reductions over every particle); the others come back zero.
  virtual std::vector<DemSums> sceneSums(const std::vector<bool>& wanted = {}) const = 0;
  // Per bead, in host numbering: tallies (collision_stats.hpp).
  virtual void collisionTallies(std::vector<CollisionTally>& out) const = 0;
  // Stirred mill checkpoints: the per-bead accounts a stirred step accumulates, in host numbering
  // (tallies empty without collision statistics, lubrication empty without lubrication), and
  // their restore, called after setState and before initialize (a vector of another size: that
  // account starts from zero).
  virtual void stirredAccounts(std::vector<CollisionTally>& tallies, std::vector<double>& lubrication) const = 0;
  virtual void setStirredAccounts(const std::vector<CollisionTally>& tallies,
                                  const std::vector<double>& lubrication) = 0;
};

// The balls as the fluid and the observers see them: one entry per DCDEM body (its centre,
// velocity, angular velocity, mass and ball radius; inertia and history empty) when the engine
// has bodies, else the particles themselves.
DemHostState ballStates(const DemEngine& engine);

std::unique_ptr<DemEngine> makeDemEngineOmp(const DemSetup& setup, bool single_precision);
#if defined(MILLSIM_HAVE_CUDA)
std::unique_ptr<DemEngine> makeDemEngineCuda(const DemSetup& setup, bool single_precision);
#endif

}  // namespace millsim::dem
