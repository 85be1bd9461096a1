#pragma once
// Backend-neutral face of the SPH solver. The time loop (src/sim/sph_run.cpp) drives an engine
// through this interface; SphSolver<Space, T, Dim> implements it once for every execution space.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace millsim::sph {

// Everything the solver needs, in SI units, resolved from the case (h, c0 already computed).
struct SphSetup {
  int dimension = 2;
  std::string kernel = "wendland";       // wendland | cubic
  std::string ddt = "fourtakas";         // none | molteni | fourtakas
  std::string viscosity = "artificial";  // artificial | laminar | laminar_sps | laminar_central
  std::string integrator = "verlet";     // verlet | symplectic
  bool shifting = false;
  double dp = 0, h = 0, c0 = 0, rho0 = 1000, gamma = 7;
  double alpha = 0.1, visco_bound_factor = 1.0, nu = 1e-6;
  std::string wall_velocity = "dbc";  // dbc | no_slip (WallNoSlipVelocity) | no_slip_ghost (mdbc only: MdbcDensity)
  std::string boundary = "dbc";       // dbc | mdbc: wall densities by continuity or from ghost nodes (mdbc.hpp)
  double ddt_value = 0.1;
  double eta2_factor = 0.01;  // eta^2 = factor h^2
  double shift_coef = 2.0, shift_tfs = 1.5;
  double sps_cs = 0.12, sps_ci = 0.0066;
  // A physical viscosity nu: Lo & Shao's laminar term (laminar or laminar_sps) or its central
  // form (laminar_central).
  bool laminar() const { return viscosity == "laminar" || viscosity == "laminar_sps" || central(); }
  bool central() const { return viscosity == "laminar_central"; }
  // The SPS stress is on: laminar_sps with a non-zero coefficient (with Cs = C_I = 0 the stress
  // is zero at every step, and the solver runs the laminar term alone, without strain sums).
  bool sps() const { return viscosity == "laminar_sps" && (sps_cs != 0 || sps_ci != 0); }
  int verlet_steps = 40;
  double cfl = 0.2;
  bool fixed_dt = false;
  double dt_fixed = 1e-5;
  double rho_min = 700, rho_max = 1300;
  std::array<double, 3> gravity{0, -9.81, 0};
  std::array<double, 3> domain_lo{}, domain_hi{};  // fluid leaving this box is excluded
  std::array<double, 3> motion_center{};           // moving boundaries rotate about z through this
};

// Plain host copy of the particles, in their original order (ids never change).
struct SphHostState {
  std::vector<double> pos, vel;  // 3 per particle
  std::vector<double> rho;
  std::vector<int> code;  // ParticleCode
  // Body particles (code kBoundBody) only: the body they belong to and their offset from its
  // centre (3 per particle, fixed in the lab orientation: bodies are spheres, whose shell looks
  // the same however they turn). Empty when the case has no bodies.
  std::vector<int> body;
  std::vector<double> offset;
  // mDBC (mdbc.hpp): each wall particle's ghost offset, x_ghost - x (3 per particle, zero for
  // fluid and for walls without one; moving walls: at the start). Empty: none.
  std::vector<double> ghost;
  std::size_t size() const { return rho.size(); }
};

struct SphMotion {
  double theta = 0, omega = 0;  // rotation of moving boundaries about z: angle from the start, rate
};

// Kinematics of a rigid body carrying body particles.
struct SphBody {
  std::array<double, 3> pos{}, vel{}, omega{};
};

// What the fluid does to a body (from its body particles), about the body centre.
struct SphBodyLoad {
  std::array<double, 3> force{}, torque{};
};

// Everything a restart needs to continue a run exactly: the particles (with the bodies' offsets),
// the moving walls' reference positions (the imposed motion is applied to them), Verlet's
// history (previous velocity and density, the step count that places its Euler steps) and the
// bodies' leap-frog impulses. Host order, like SphHostState; arrays an integrator or scene does
// not use are empty.
struct SphRestartState {
  SphHostState particles;
  std::vector<double> pos0;            // 3 per particle, with moving walls
  std::vector<double> vel_m1, rho_m1;  // Verlet
  long long step = 0;
  std::vector<SphBodyLoad> impulse;  // per body
};

struct SphSums {
  double kinetic = 0, potential = 0;  // fluid only, J (per metre of depth in 2D)
  double fluid_mass = 0;              // active fluid, kg (per metre in 2D)
  double max_speed = 0;               // fluid, m/s
  double max_x = 0;                   // largest x of active fluid (dam-break front), m
  double rho_min = 0, rho_max = 0;    // over active fluid
  long long fluid = 0, excluded_density = 0, excluded_domain = 0, boundary = 0;
};

class SphEngine {
 public:
  virtual ~SphEngine() = default;
  virtual const char* backendName() const = 0;
  virtual const char* precisionName() const = 0;
  virtual void setState(const SphHostState& s) = 0;
  virtual void getState(SphHostState& s) const = 0;
  // A checkpoint's state: getRestartState after a step, setRestartState then initialize() on a
  // new engine of the same setup continue as if there had been no break.
  virtual void getRestartState(SphRestartState& s) const = 0;
  virtual void setRestartState(const SphRestartState& s) = 0;
  // Neighbours and forces of the current state (call after setState).
  virtual void initialize(const SphMotion& now) = 0;
  // Time step from the last force evaluation: CFL (eqs. 40-41) or the fixed one, and never above
  // the stability limits of the laminar viscosity and the density diffusion.
  virtual double nextDt() const = 0;
  // Those limits (diffusion_stability.hpp), s; infinite for a term that is off.
  virtual double viscousDtLimit() const = 0;
  virtual double ddtDtLimit() const = 0;
  // One step of dt; moving boundaries at `half` (symplectic predictor) and `end`.
  void step(double dt, const SphMotion& half, const SphMotion& end) {
    beginStep(dt, half);
    endStep(dt, end);
  }
  // The step in two halves, for a coupling that moves bodies in between. beginStep evaluates
  // the forces that drive the step (symplectic: predictor to t + dt/2 and the evaluation there,
  // with the bodies where setBodyKinematics put them; Verlet: nothing, the last evaluation drives
  // it) and books bodyImpulses(); endStep completes the step (call setBodyKinematics with the
  // bodies at t + dt first).
  virtual void beginStep(double dt, const SphMotion& half) = 0;
  virtual void endStep(double dt, const SphMotion& end) = 0;
  virtual SphSums sums() const = 0;
  // Fluid particles excluded so far (by density or domain): one reduction, for the per-step
  // parts_out_max check (sums() runs nine).
  virtual long long excludedCount() const = 0;
  // Places every body's particles at its centre + offset, with velocity v + omega x offset.
  // Call before step() with the bodies at the end of the step (and once before initialize()).
  virtual void setBodyKinematics(const std::vector<SphBody>& bodies) = 0;
  // Fluid force and torque on each body from the last force evaluation (pressure and viscosity
  // of the fluid neighbours of its particles). The engine's own buffer, valid until the next call
  // (a coupled step allocates nothing).
  virtual const std::vector<SphBodyLoad>& bodyLoads() const = 0;
  // Impulse (N s) and angular impulse (N m s) the fluid delivers to each body over the step
  // begun by the last beginStep(): exactly what the fluid's own update takes from it, so fluid
  // and bodies exchange equal and opposite momentum (up to rounding). Symplectic: dt x the load
  // at the mid-step evaluation. Verlet: the fluid's leap-frog share, 2 dt F_n - J_(n-1) (the
  // fluid's velocity chain is v_(n+1) = v_(n-1) + 2 dt a_n), and dt F_n on the Euler steps.
  virtual const std::vector<SphBodyLoad>& bodyImpulses() const = 0;
  // Shepard-interpolated fluid pressure at a point (probe), Pa; NaN when no fluid within 2h.
  virtual double probePressure(const std::array<double, 3>& x) const = 0;
  virtual std::map<std::string, std::size_t> memoryBytes() const = 0;
  // Particle pairs within 2h evaluated by one force evaluation (fluid-fluid pairs twice, once
  // from each side; wall-fluid pairs twice: the wall's continuity and the fluid's forces):
  // the "particle interactions" of throughput figures. A diagnostic: one extra search.
  virtual double interactionsPerEvaluation() = 0;
  // Force evaluations per step: 1 (Verlet) or 2 (symplectic).
  int evaluationsPerStep() const { return m_evaluations_per_step; }

 protected:
  int m_evaluations_per_step = 1;
};

// single_precision: positions, velocities, densities and the pair sums in float (the
// accumulated time, sums() and the host state stay double); measured in docs/accuracy-cost.md.
std::unique_ptr<SphEngine> makeSphEngineOmp(const SphSetup& setup, bool single_precision = false);
#if defined(MILLSIM_HAVE_CUDA)
std::unique_ptr<SphEngine> makeSphEngineCuda(const SphSetup& setup, bool single_precision = false);
#endif

}  // namespace millsim::sph
