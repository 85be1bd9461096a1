#pragma once
// SphSolver<Space, T, Dim>: owns the SPH arrays in the execution space's memory and runs the
// functors of sph_kernels.hpp through the backend. Written once; instantiated for OpenMP in
// sph_solver_omp.cpp and for CUDA in backend/cuda/sph_solver_cuda.cu.
//
// Particles are renumbered in cell order before every force evaluation (the cell sort is done
// anyway, and it keeps neighbours close in memory); m_id keeps each particle's host number.
// Excluded particles sort to the end and no search finds them.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/neighbors/cell_list.hpp"
#include "millsim/scene/sph_choices.hpp"
#include "sph/density_diffusion.hpp"
#include "sph/diffusion_stability.hpp"
#include "sph/kernels.hpp"
#include "sph/mdbc.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_kernels.hpp"
#include "sph/sph_scatter.hpp"

namespace millsim::sph {

template <class U>
struct GatherArray {
  const U* src;
  U* dst;
  const int* order;
  MILLSIM_HD void operator()(int i) const { dst[i] = src[order[i]]; }
};

template <class T>
struct FluidSum {
  const Vec3<T>* pos;
  const Vec3<T>* vel;
  const int* code;
  Vec3<T> g;
  T mass;
  int what;  // 0 kinetic, 1 potential, 2 fluid count, 3 excluded density, 4 excluded domain, 5 boundary
  MILLSIM_HD double operator()(int i) const {
    const int c = code[i];
    switch (what) {
      case 0:
        return c == kFluid ? 0.5 * double(mass) * double(core::norm2(vel[i])) : 0.0;
      case 1:
        return c == kFluid ? -double(mass) * double(core::dot(g, pos[i])) : 0.0;
      case 2:
        return c == kFluid ? 1.0 : 0.0;
      case 3:
        return c == kExcludedDensity ? 1.0 : 0.0;
      case 4:
        return c == kExcludedDomain ? 1.0 : 0.0;
      default:
        return c == kBoundFixed || c == kBoundMoving || c == kBoundBody ? 1.0 : 0.0;
    }
  }
};

template <class T>
struct FluidMax {
  const Vec3<T>* pos;
  const Vec3<T>* vel;
  const T* rho;
  const int* code;
  int what;  // 0 speed, 1 x, 2 rho, 3 -rho
  MILLSIM_HD double operator()(int i) const {
    if (code[i] != kFluid) return -1e300;
    switch (what) {
      case 0:
        return std::sqrt(double(core::norm2(vel[i])));
      case 1:
        return double(pos[i].x);
      case 2:
        return double(rho[i]);
      default:
        return -double(rho[i]);
    }
  }
};

// Shepard interpolation of the fluid pressure at a point: numerator (P W V) or denominator (W V).
template <class T, class Kernel>
struct ProbeSum {
  const Vec3<T>* pos;
  const T* rho;
  const T* press;
  const int* code;
  Kernel kernel;
  Vec3<T> x;
  T mass, support2;
  bool numerator;
  MILLSIM_HD double operator()(int i) const {
    if (code[i] != kFluid) return 0.0;
    const T r2 = core::norm2(x - pos[i]);
    if (r2 >= support2) return 0.0;
    const double wv = double(kernel.w(std::sqrt(r2))) * double(mass) / double(rho[i]);
    return numerator ? wv * double(press[i]) : wv;
  }
};

// Neighbours within 2h that particle a interacts with (the interaction's own search).
template <class T>
struct CountInteractions {
  neighbors::CellListView<T> fluid_cells, bound_cells;
  const Vec3<T>* pos;
  const int* code;
  T support2;
  MILLSIM_HD double operator()(int a) const {
    if (isExcluded(code[a])) return 0.0;
    double n = 0;
    auto count = [&](int b, Vec3<T>, T) {
      if (b != a) n += 1;
    };
    fluid_cells.forEachWithin(pos[a], support2, pos, count);
    if (code[a] == kFluid) bound_cells.forEachWithin(pos[a], support2, pos, count);
    return n;
  }
};

struct CountExcluded {
  const int* code;
  MILLSIM_HD int operator()(int i) const { return isExcluded(code[i]) ? 1 : 0; }
};

template <class T>
struct ReadT {
  const T* v;
  MILLSIM_HD T operator()(int i) const { return v[i]; }
};

// The setup's named choices. The solver tests them with ==, so a name it does not know would
// run as some default (a misspelt "mdbc" as DBC walls); the case reader checks its own, this is
// for library callers who fill SphSetup themselves.
inline void checkSetupChoices(const SphSetup& s) {
  namespace choices = scene::sph_choices;
  auto check = [](const char* field, const std::string& value, const std::vector<std::string>& allowed) {
    if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return;
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw core::InputError(std::string("sph: ") + field + " = '" + value + "' is not one of: " + list);
  };
  check("kernel", s.kernel, choices::kKernel);
  check("ddt", s.ddt, choices::kDdt);
  check("viscosity", s.viscosity, choices::kViscosity);
  check("integrator", s.integrator, choices::kIntegrator);
  check("wall_velocity", s.wall_velocity, choices::kWallVelocity);
  check("boundary", s.boundary, choices::kBoundary);
}

template <class Space, class T, int Dim>
class SphSolver final : public SphEngine {
 public:
  explicit SphSolver(const SphSetup& s) : m_setup(s) {
    if (s.dp <= 0 || s.h <= 0 || s.c0 <= 0) throw core::InputError("sph: dp, h and c0 must be > 0");
    checkSetupChoices(s);
    m_mass = T(s.rho0 * std::pow(s.dp, Dim));
    m_eos = TaitEos<T>::make(s.rho0, s.c0, s.gamma);
    m_eta2 = T(s.eta2_factor * s.h * s.h);
    m_support2 = T(4 * s.h * s.h);
    m_gravity = toVec(s.gravity);
    const double g = std::sqrt(s.gravity[0] * s.gravity[0] + s.gravity[1] * s.gravity[1] + s.gravity[2] * s.gravity[2]);
    m_up = g > 0 ? Vec3<T>{T(-s.gravity[0] / g), T(-s.gravity[1] / g), T(-s.gravity[2] / g)} : core::zero3<T>();
    m_g_abs = g;
    Vec3<T> lo = toVec(s.domain_lo), hi = toVec(s.domain_hi);
    if (Dim == 2) {
      lo.z = T(-1);
      hi.z = T(1);
    }
    m_lo = lo;
    m_hi = hi;
    // Cells of h searched two deep: 125 h^3 (3D) for a support sphere of 33.5 h^3, instead of
    // 216 h^3 with cells of 2h.
    m_cells.setGrid(neighbors::makeGrid<T>(lo, hi, T(s.h), Dim == 2, 2), 2);
    m_symplectic = s.integrator == "symplectic";
    m_evaluations_per_step = m_symplectic ? 2 : 1;
    withKernel([&](auto kernel) {
      m_dt_limits =
          diffusionDtLimits(kernel, Dim, s.h, s.dp, s.eta2_factor * s.h * s.h, s.laminar() ? s.nu : 0.0,
                            s.ddt == "none" ? 0.0 : s.ddt_value, s.c0, m_symplectic, s.verlet_steps, s.central());
    });
    // A fixed step past a limit (the viscous one without its margin) is refused, naming it.
    auto refuse = [&](double limit, const std::string& term) {
      if (s.fixed_dt && s.dt_fixed > limit)
        throw core::InputError("sph: the fixed time step " + std::to_string(s.dt_fixed) + " s is above the stability " +
                               "limit of the " + term + ", " + std::to_string(limit) + " s with this kernel, h and " +
                               "integrator (Verlet's limit is about 15 times lower than the symplectic scheme's); " +
                               "use dt=\"auto\"");
    };
    refuse(m_dt_limits.ddt, "density diffusion (ddt_value = " + std::to_string(s.ddt_value) + ")");
    refuse(m_dt_limits.viscous / kViscousDtMargin, "laminar viscosity (nu = " + std::to_string(s.nu) + " m2/s)");
  }

  // The stability limits of the diffusion terms (diffusion_stability.hpp); infinite when off.
  double viscousDtLimit() const override { return m_dt_limits.viscous; }
  double ddtDtLimit() const override { return m_dt_limits.ddt; }

  double interactionsPerEvaluation() override {
    return backend::reduceSum<double>(
        Space{}, m_n, CountInteractions<T>{m_cells.view(0), m_cells.view(1), m_pos.data(), m_code.data(), m_support2});
  }

  const char* backendName() const override { return Space::kName; }
  const char* precisionName() const override { return sizeof(T) == 4 ? "float" : "double"; }

  void setState(const SphHostState& s) override {
    const std::size_t n = s.size();
    m_n = static_cast<int>(n);
    std::vector<Vec3<T>> pos(n), vel(n);
    std::vector<T> rho(n);
    std::vector<int> id(n);
    for (std::size_t i = 0; i < n; ++i) {
      pos[i] = {T(s.pos[3 * i]), T(s.pos[3 * i + 1]), Dim == 2 ? T(0) : T(s.pos[3 * i + 2])};
      vel[i] = {T(s.vel[3 * i]), T(s.vel[3 * i + 1]), Dim == 2 ? T(0) : T(s.vel[3 * i + 2])};
      rho[i] = T(s.rho[i]);
      id[i] = static_cast<int>(i);
    }
    m_has_moving = std::find(s.code.begin(), s.code.end(), int(kBoundMoving)) != s.code.end();
    m_bodies = 0;
    if (s.body.size() == n) {
      std::vector<Vec3<T>> offset(n);
      for (std::size_t i = 0; i < n; ++i) {
        offset[i] = {T(s.offset[3 * i]), T(s.offset[3 * i + 1]), Dim == 2 ? T(0) : T(s.offset[3 * i + 2])};
        m_bodies = std::max(m_bodies, s.body[i] + 1);
      }
      m_body.copyFromHost(s.body);
      m_offset.copyFromHost(offset);
      setBodyMembers(s);
    }
    if (m_setup.wall_velocity == "no_slip_ghost" && m_setup.boundary != "mdbc")
      throw std::invalid_argument("SphSolver: wall_velocity = no_slip_ghost needs boundary = mdbc (its ghost nodes)");
    if (m_setup.boundary == "mdbc") {
      if (s.ghost.size() != 3 * n)
        throw std::invalid_argument("SphSolver: boundary = mdbc needs a ghost offset per particle (" +
                                    std::to_string(s.ghost.size()) + " values for " + std::to_string(n) +
                                    " particles): build the walls with sph/geometry.hpp");
      std::vector<Vec3<T>> ghost(n);
      for (std::size_t i = 0; i < n; ++i)
        ghost[i] = {T(s.ghost[3 * i]), T(s.ghost[3 * i + 1]), Dim == 2 ? T(0) : T(s.ghost[3 * i + 2])};
      m_ghost.copyFromHost(ghost);
    }
    m_pos.copyFromHost(pos);
    m_vel.copyFromHost(vel);
    m_rho.copyFromHost(rho);
    m_code.copyFromHost(s.code);
    m_id.copyFromHost(id);
    // Only what the chosen options need is allocated.
    if (m_has_moving) m_pos0.copyFromHost(pos);
    if (m_symplectic) {
      m_pos_pre.resize(n, core::zero3<T>());
      m_vel_pre.resize(n, core::zero3<T>());
      m_rho_pre.resize(n, T(0));
    } else {
      m_vel_m1.copyFromHost(vel);
      m_rho_m1.copyFromHost(rho);
    }
    m_press.resize(n, T(0));
    m_ace.resize(n, core::zero3<T>());
    m_drho.resize(n, T(0));
    m_visc.resize(n, T(0));
    if (m_setup.shifting) {
      m_shift_grad.resize(n, core::zero3<T>());
      m_shift_div.resize(n, T(0));
    }
    if (m_setup.wall_velocity != "dbc") m_wall_visc_vel.resize(n, core::zero3<T>());
    if (m_setup.sps()) {
      m_strain.resize(n, zeroSym3<T>());
      m_tau.resize(n, zeroSym3<T>());
    }
    m_scratch_vec.resize(n, core::zero3<T>());
    m_scratch_real.resize(n, T(0));
    m_scratch_int.resize(n, 0);
    m_scratch_sym.resize(m_tau.size(), zeroSym3<T>());
    m_step = 0;
    m_impulse.assign(static_cast<std::size_t>(m_bodies), SphBodyLoad{});
  }

  void getState(SphHostState& s) const override {
    std::vector<Vec3<T>> pos, vel;
    std::vector<T> rho;
    std::vector<int> code, id;
    m_pos.copyToHost(pos);
    m_vel.copyToHost(vel);
    m_rho.copyToHost(rho);
    m_code.copyToHost(code);
    m_id.copyToHost(id);
    const std::size_t n = pos.size();
    s.pos.assign(3 * n, 0.0);
    s.vel.assign(3 * n, 0.0);
    s.rho.assign(n, 0.0);
    s.code.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t h = static_cast<std::size_t>(id[i]);
      s.pos[3 * h] = double(pos[i].x);
      s.pos[3 * h + 1] = double(pos[i].y);
      s.pos[3 * h + 2] = double(pos[i].z);
      s.vel[3 * h] = double(vel[i].x);
      s.vel[3 * h + 1] = double(vel[i].y);
      s.vel[3 * h + 2] = double(vel[i].z);
      s.rho[h] = double(rho[i]);
      s.code[h] = code[i];
    }
  }

  void getRestartState(SphRestartState& s) const override {
    getState(s.particles);
    std::vector<int> id;
    m_id.copyToHost(id);
    if (m_body.size() > 0) {
      std::vector<int> body;
      m_body.copyToHost(body);
      s.particles.body.assign(body.size(), 0);
      for (std::size_t i = 0; i < body.size(); ++i) s.particles.body[static_cast<std::size_t>(id[i])] = body[i];
      s.particles.offset = hostOrder(m_offset, id);
    }
    if (m_ghost.size() > 0) s.particles.ghost = hostOrder(m_ghost, id);
    s.pos0 = m_has_moving ? hostOrder(m_pos0, id) : std::vector<double>{};
    s.vel_m1 = m_symplectic ? std::vector<double>{} : hostOrder(m_vel_m1, id);
    s.rho_m1.clear();
    if (!m_symplectic) {
      std::vector<T> rho;
      m_rho_m1.copyToHost(rho);
      s.rho_m1.assign(rho.size(), 0.0);
      for (std::size_t i = 0; i < rho.size(); ++i) s.rho_m1[static_cast<std::size_t>(id[i])] = double(rho[i]);
    }
    s.step = m_step;
    s.impulse = m_impulse;
  }

  void setRestartState(const SphRestartState& s) override {
    setState(s.particles);  // host order: particle i is slot i
    const std::size_t n = s.particles.size();
    auto vec = [&](const std::vector<double>& a, const char* what) {
      if (a.size() != 3 * n)
        throw core::InputError(std::string("SPH restart: ") + what + " has " + std::to_string(a.size()) +
                               " values for " + std::to_string(n) + " particles");
      std::vector<Vec3<T>> v(n);
      for (std::size_t i = 0; i < n; ++i) v[i] = {T(a[3 * i]), T(a[3 * i + 1]), Dim == 2 ? T(0) : T(a[3 * i + 2])};
      return v;
    };
    if (m_has_moving) m_pos0.copyFromHost(vec(s.pos0, "the moving walls' reference positions"));
    if (!m_symplectic) {
      m_vel_m1.copyFromHost(vec(s.vel_m1, "Verlet's previous velocity"));
      if (s.rho_m1.size() != n)
        throw core::InputError("SPH restart: Verlet's previous density does not match the particles");
      m_rho_m1.copyFromHost(std::vector<T>(s.rho_m1.begin(), s.rho_m1.end()));
    }
    if (s.impulse.size() != static_cast<std::size_t>(m_bodies))
      throw core::InputError("SPH restart: " + std::to_string(s.impulse.size()) + " body impulses for " +
                             std::to_string(m_bodies) + " bodies");
    m_step = s.step;
    m_impulse = s.impulse;
  }

  void initialize(const SphMotion& now) override {
    if (m_has_moving) placeMovingBoundaries(now);
    forces();
  }

  double nextDt() const override {
    if (m_setup.fixed_dt) return m_setup.dt_fixed;
    const double acc =
        backend::reduceMax<T>(Space{}, m_n, T(0), FluidAcceleration<T>{m_ace.data(), m_code.data(), m_gravity});
    const double visc = backend::reduceMax<T>(Space{}, m_n, T(0), ReadVisc<T>{m_visc.data(), m_code.data()});
    // reduceMax keeps a NaN: one NaN particle stops the run here, with its cause.
    if (!(acc == acc) || !(visc == visc))
      throw core::SimulationError("SPH: time step is not finite (NaN in accelerations or velocities)");
    const double h = m_setup.h;
    // Eq. 40 with the force condition as sqrt(h / |a|) (DualSPHysics; the paper prints h / |a|,
    // which is not a time).
    const double dt_f = acc > 0 ? std::sqrt(h / acc) : std::numeric_limits<double>::infinity();
    const double dt_c = h / (m_setup.c0 + visc);
    // The diffusion terms' own limits (not scaled by the CFL number: they carry their margins).
    const double dt = std::min({m_setup.cfl * std::min(dt_f, dt_c), m_dt_limits.viscous, m_dt_limits.ddt});
    if (!std::isfinite(dt) || dt <= 0)
      throw core::SimulationError("SPH: time step is not finite (NaN in accelerations or velocities)");
    return dt;
  }

  void beginStep(double dt_in, const SphMotion& half) override {
    const double dt = dt_in;
    if (m_symplectic) {
      backend::parallelFor(Space{}, m_n,
                           SymplecticPredictor<T>{view(), m_pos_pre.data(), m_vel_pre.data(), m_rho_pre.data(),
                                                  m_pos0.data(), motionOf(half), m_gravity, T(dt), m_eos.rho0});
      forces();
    }
    if (m_bodies == 0) return;
    const std::vector<SphBodyLoad>& loads = bodyLoads();
    const bool leap = !m_symplectic && !verletEulerStep();
    m_impulse.resize(loads.size());
    for (std::size_t k = 0; k < loads.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        // The leap-frog chain: what this step adds to the fluid's momentum is 2 dt F_n minus
        // what the previous step added (v_(n+1) - v_n = v_(n-1) - v_n + 2 dt a_n).
        m_impulse[k].force[a] = leap ? 2 * dt * loads[k].force[a] - m_impulse[k].force[a] : dt * loads[k].force[a];
        m_impulse[k].torque[a] = leap ? 2 * dt * loads[k].torque[a] - m_impulse[k].torque[a] : dt * loads[k].torque[a];
      }
  }

  void endStep(double dt_in, const SphMotion& end) override {
    const T dt = T(dt_in);
    const FluidChecks<T> checks{T(m_setup.rho_min),  T(m_setup.rho_max), m_lo, m_hi, T(m_setup.shift_coef * m_setup.h),
                                T(m_setup.shift_tfs)};
    const SphView<T> p = view();
    if (!m_symplectic) {
      const bool euler = verletEulerStep();
      withShift([&](auto shift) {
        backend::parallelFor(
            Space{}, m_n,
            VerletUpdate<T, decltype(shift)::value>{p, m_vel_m1.data(), m_rho_m1.data(), m_pos0.data(), motionOf(end),
                                                    checks, m_gravity, dt, m_eos.rho0, euler});
      });
    } else {
      withShift([&](auto shift) {
        backend::parallelFor(Space{}, m_n,
                             SymplecticCorrector<T, decltype(shift)::value>{
                                 p, m_pos_pre.data(), m_vel_pre.data(), m_rho_pre.data(), m_pos0.data(), motionOf(end),
                                 checks, m_gravity, dt, m_eos.rho0});
      });
    }
    forces();
    ++m_step;
  }

  const std::vector<SphBodyLoad>& bodyImpulses() const override { return m_impulse; }

  SphSums sums() const override {
    SphSums s;
    auto sum = [&](int what) {
      return backend::reduceSum<double>(
          Space{}, m_n, FluidSum<T>{m_pos.data(), m_vel.data(), m_code.data(), m_gravity, m_mass, what});
    };
    auto most = [&](int what) {
      return backend::reduceMax<double>(Space{}, m_n, -1e300,
                                        FluidMax<T>{m_pos.data(), m_vel.data(), m_rho.data(), m_code.data(), what});
    };
    s.kinetic = sum(0);
    s.potential = sum(1);
    s.fluid = std::llround(sum(2));
    s.excluded_density = std::llround(sum(3));
    s.excluded_domain = std::llround(sum(4));
    s.boundary = std::llround(sum(5));
    s.fluid_mass = double(m_mass) * double(s.fluid);
    if (s.fluid > 0) {
      s.max_speed = most(0);
      s.max_x = most(1);
      s.rho_max = most(2);
      s.rho_min = -most(3);
    }
    return s;
  }

  void setBodyKinematics(const std::vector<SphBody>& bodies) override {
    if (bodies.empty()) return;
    if (static_cast<int>(bodies.size()) != m_bodies)
      throw std::invalid_argument("SphSolver::setBodyKinematics: " + std::to_string(bodies.size()) +
                                  " bodies given, the particles belong to " + std::to_string(m_bodies));
    // Host buffers kept across steps (sized once): a coupled step allocates nothing.
    std::vector<Vec3<T>>&x = m_host_body_pos, &v = m_host_body_vel, &w = m_host_body_omega;
    x.resize(bodies.size());
    v.resize(bodies.size());
    w.resize(bodies.size());
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      x[k] = toVec(bodies[k].pos);
      v[k] = toVec(bodies[k].vel);
      w[k] = toVec(bodies[k].omega);
      if (Dim == 2) {  // in the plane, spinning about z (as setState flattens the particles)
        x[k].z = v[k].z = w[k].x = w[k].y = T(0);
      }
    }
    m_body_pos.copyFromHost(x);
    m_body_vel.copyFromHost(v);
    m_body_omega.copyFromHost(w);
    backend::parallelFor(Space{}, m_n,
                         PlaceBodyParticles<T>{m_body.data(), m_offset.data(), m_body_pos.data(), m_body_vel.data(),
                                               m_body_omega.data(), m_code.data(), m_pos.data(), m_vel.data()});
  }

  const std::vector<SphBodyLoad>& bodyLoads() const override {
    std::vector<SphBodyLoad>& loads = m_loads;
    loads.resize(static_cast<std::size_t>(m_bodies));
    if (m_bodies == 0) return loads;
    // Summed where the particles live; only the per-body totals come back.
    backend::parallelForWork(Space{}, m_bodies, static_cast<long long>(m_body_members.size()),
                             BodyLoadSum<T>{m_body_start.data(), m_body_members.data(), m_slot_of.data(), m_ace.data(),
                                            m_offset.data(), m_mass, m_load_force.data(), m_load_torque.data()});
    m_load_force.copyToHost(m_host_load_force);
    m_load_torque.copyToHost(m_host_load_torque);
    for (std::size_t k = 0; k < loads.size(); ++k) {
      const Vec3<double>&f = m_host_load_force[k], &tq = m_host_load_torque[k];
      loads[k].force = {f.x, f.y, f.z};
      loads[k].torque = {tq.x, tq.y, tq.z};
    }
    return loads;
  }

  long long excludedCount() const override {
    return backend::reduceSum<int>(Space{}, m_n, CountExcluded{m_code.data()});
  }

  double probePressure(const std::array<double, 3>& x_in) const override {
    const Vec3<T> x{T(x_in[0]), T(x_in[1]), Dim == 2 ? T(0) : T(x_in[2])};
    double num = 0, den = 0;
    withKernel([&](auto kernel) {
      using K = decltype(kernel);
      num = backend::reduceSum<double>(Space{}, m_n,
                                       ProbeSum<T, K>{m_pos.data(), m_rho.data(), m_press.data(), m_code.data(), kernel,
                                                      x, m_mass, m_support2, true});
      den = backend::reduceSum<double>(Space{}, m_n,
                                       ProbeSum<T, K>{m_pos.data(), m_rho.data(), m_press.data(), m_code.data(), kernel,
                                                      x, m_mass, m_support2, false});
    });
    return den > 0 ? num / den : std::numeric_limits<double>::quiet_NaN();
  }

  std::map<std::string, std::size_t> memoryBytes() const override {
    return {{"sph.particles",
             m_pos.bytes() + m_vel.bytes() + m_rho.bytes() + m_code.bytes() + m_id.bytes() + m_pos0.bytes()},
            {"sph.bodies", m_body.bytes() + m_offset.bytes() + m_body_pos.bytes() + m_body_vel.bytes() +
                               m_body_omega.bytes() + m_body_start.bytes() + m_body_members.bytes() +
                               m_slot_of.bytes() + m_load_force.bytes() + m_load_torque.bytes()},
            {"sph.integrator",
             m_vel_m1.bytes() + m_rho_m1.bytes() + m_pos_pre.bytes() + m_vel_pre.bytes() + m_rho_pre.bytes()},
            {"sph.forces", m_press.bytes() + m_ace.bytes() + m_drho.bytes() + m_visc.bytes() + m_wall_visc_vel.bytes()},
            {"sph.shifting", m_shift_grad.bytes() + m_shift_div.bytes()},
            {"sph.sps", m_strain.bytes() + m_tau.bytes()},
            {"sph.mdbc", m_ghost.bytes()},
            {"sph.reorder_scratch",
             m_scratch_vec.bytes() + m_scratch_real.bytes() + m_scratch_int.bytes() + m_scratch_sym.bytes()},
            {"neighbors", m_cells.bytes()},
            {"sph.pair_rows", m_pair_scatter.bytes()}};
  }

 private:
  template <bool B>
  struct Flag {
    static constexpr bool value = B;
  };

  static Vec3<T> toVec(const std::array<double, 3>& a) { return {T(a[0]), T(a[1]), T(a[2])}; }

  // A per-particle vector array in host order (3 doubles per particle).
  static std::vector<double> hostOrder(const backend::Array<Space, Vec3<T>>& a, const std::vector<int>& id) {
    std::vector<Vec3<T>> v;
    a.copyToHost(v);
    std::vector<double> out(3 * v.size(), 0.0);
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::size_t h = 3 * static_cast<std::size_t>(id[i]);
      out[h] = double(v[i].x), out[h + 1] = double(v[i].y), out[h + 2] = double(v[i].z);
    }
    return out;
  }

  // Every verlet_steps-th Verlet step is an Euler step (re-couples the leap-frog chains).
  bool verletEulerStep() const { return m_setup.verlet_steps > 0 && (m_step + 1) % m_setup.verlet_steps == 0; }

  SphView<T> view() {
    return {m_pos.data(),
            m_vel.data(),
            m_rho.data(),
            m_code.data(),
            m_press.data(),
            m_ace.data(),
            m_drho.data(),
            m_visc.data(),
            m_shift_grad.data(),
            m_shift_div.data(),
            m_strain.data(),
            m_tau.data(),
            m_wall_visc_vel.size() > 0 ? m_wall_visc_vel.data() : m_vel.data()};
  }

  // The motion the moving walls are placed with; remembered for the mDBC ghost offsets, which
  // turn with the walls (every placement is followed by the force evaluation that reads it).
  BoundaryMotion<T> motionOf(const SphMotion& m) const {
    m_theta = m.theta;
    m_omega = m.omega;
    const Vec3<T> c = toVec(m_setup.motion_center);
    return {c, T(std::cos(m.theta)), T(std::sin(m.theta)), T(m.omega)};
  }

  // Each body's particles by host number (the state's order; kept across renumberings).
  void setBodyMembers(const SphHostState& s) {
    const std::size_t n = s.size();
    std::vector<int> start(static_cast<std::size_t>(m_bodies) + 1, 0), members, slot(n);
    for (std::size_t i = 0; i < n; ++i)
      if (s.code[i] == kBoundBody && s.body[i] >= 0) ++start[static_cast<std::size_t>(s.body[i]) + 1];
    for (int k = 0; k < m_bodies; ++k) start[k + 1] += start[k];
    members.resize(static_cast<std::size_t>(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      slot[i] = static_cast<int>(i);
      if (s.code[i] == kBoundBody && s.body[i] >= 0) members[fill[s.body[i]]++] = static_cast<int>(i);
    }
    m_body_start.copyFromHost(start);
    m_body_members.copyFromHost(members);
    m_slot_of.copyFromHost(slot);
    m_load_force.resize(static_cast<std::size_t>(m_bodies), Vec3<double>{0, 0, 0});
    m_load_torque.resize(static_cast<std::size_t>(m_bodies), Vec3<double>{0, 0, 0});
  }

  void placeMovingBoundaries(const SphMotion& m) {
    backend::parallelFor(
        Space{}, m_n, PlaceMovingBoundaries<T>{m_pos0.data(), m_pos.data(), m_vel.data(), m_code.data(), motionOf(m)});
  }

  // One choice per option, each a compile-time type: the pair loop holds only what is on.
  template <class F>
  void withKernel(F&& f) const {
    if (m_setup.kernel == "cubic")
      f(CubicSpline<Dim, T>::make(m_setup.h));
    else
      f(WendlandC2<Dim, T>::make(m_setup.h));
  }
  template <class F>
  void withDdt(F&& f) const {
    const T coef = T(2 * m_setup.ddt_value * m_setup.h * m_setup.c0);
    if (m_setup.ddt == "fourtakas")
      f(DdtFourtakas2019<T>{coef, m_eta2, m_eos.rho0, T(m_setup.rho0 * m_g_abs / double(m_eos.b)),
                            T(1.0 / m_setup.gamma)});
    else if (m_setup.ddt == "molteni")
      f(DdtMolteni2009<T>{coef, m_eta2});
    else
      f(DdtNone{});
  }
  template <class F>
  void withVisc(F&& f) const {
    if (m_setup.sps())
      f(ViscosityLaminarSps<T>{{T(m_setup.nu), m_eta2}});
    else if (m_setup.central())
      f(ViscosityLaminarCentral<T>{T(m_setup.nu), m_eta2, T(2 * (Dim + 2))});
    else if (m_setup.laminar())
      f(ViscosityLaminar<T>{T(m_setup.nu), m_eta2});
    else
      f(ViscosityArtificial<T>{T(m_setup.alpha), T(m_setup.alpha * m_setup.visco_bound_factor), T(m_setup.h),
                               T(m_setup.c0), m_eta2});
  }
  template <class F>
  void withShift(F&& f) const {
    if (m_setup.shifting)
      f(Flag<true>{});
    else
      f(Flag<false>{});
  }

  template <class U>
  void gather(backend::Array<Space, U>& a, backend::Array<Space, U>& scratch, const int* order) {
    if (a.size() == 0) return;
    backend::parallelFor(Space{}, m_n, GatherArray<U>{a.data(), scratch.data(), order});
    a.swap(scratch);
  }

  // Cell sort, renumbering of the particle state in cell order, pressure, interaction.
  void forces() {
    // Fluid first, then walls and bodies, each in cell order; excluded particles last.
    m_cells.build(m_pos.data(), m_n, m_code.data(), kExcludedDensity, kBoundFixed);
    const int* order = m_cells.view().order;
    gather(m_pos, m_scratch_vec, order);
    gather(m_vel, m_scratch_vec, order);
    gather(m_pos0, m_scratch_vec, order);
    gather(m_vel_m1, m_scratch_vec, order);
    gather(m_pos_pre, m_scratch_vec, order);
    gather(m_vel_pre, m_scratch_vec, order);
    gather(m_rho, m_scratch_real, order);
    gather(m_rho_m1, m_scratch_real, order);
    gather(m_rho_pre, m_scratch_real, order);
    gather(m_tau, m_scratch_sym, order);
    gather(m_id, m_scratch_int, order);
    gather(m_code, m_scratch_int, order);
    gather(m_body, m_scratch_int, order);
    gather(m_offset, m_scratch_vec, order);
    gather(m_ghost, m_scratch_vec, order);
    m_cells.renumberedInOrder();
    if (m_bodies > 0) backend::parallelFor(Space{}, m_n, SlotOfId{m_id.data(), m_slot_of.data()});
    if (m_ghost.size() > 0)
      withKernel([&](auto kernel) {
        auto run = [&](auto no_slip) {
          using Mdbc = MdbcDensity<T, decltype(kernel), Dim, decltype(no_slip)::value>;
          backend::parallelFor(
              Space{}, m_n,
              Mdbc{m_cells.view(0), m_pos.data(), m_code.data(), m_ghost.data(), kernel, m_support2, m_mass, m_eos.rho0,
                   T(std::cos(m_theta)), T(std::sin(m_theta)), 0, m_rho.data(), m_vel.data(), m_wall_visc_vel.data(),
                   T(m_omega), m_bodies > 0 ? m_body.data() : nullptr, m_body_omega.data()});
        };
        if (m_setup.wall_velocity == "no_slip_ghost")
          run(std::true_type{});
        else
          run(std::false_type{});
      });
    backend::parallelFor(Space{}, m_n, EosPressure<T>{m_eos, m_rho.data(), m_press.data()});
    const SphView<T> p = view();
    withKernel([&](auto kernel) {
      if (m_wall_visc_vel.size() > 0)
        backend::parallelFor(
            Space{}, m_n,
            WallNoSlipVelocity<T, decltype(kernel)>{
                m_cells.view(0), m_pos.data(), m_vel.data(), m_code.data(), kernel, m_support2, m_wall_visc_vel.data(),
                m_setup.wall_velocity == "no_slip_ghost" ? m_ghost.data() : nullptr, T(m_omega),
                m_bodies > 0 ? m_body.data() : nullptr, m_body_omega.data()});
      withDdt([&](auto ddt) {
        withVisc([&](auto visc) {
          withShift([&](auto shift) {
            using Physics = SphPairPhysics<T, decltype(kernel), decltype(ddt), decltype(visc), decltype(shift)::value>;
            const Physics phys{kernel, ddt, visc, m_mass, m_eta2, m_up};
            if constexpr (std::is_same_v<Space, backend::Omp>) {
              // Host: each pair once, the partner's share scattered (about half the pair work of
              // visiting both sides, and wall particles search nothing).
              constexpr bool kShift = Physics::kShifting, kStrain = Physics::kStrain;
              backend::parallelFor(Space{}, m_n, ClearPairSums<T, kShift, kStrain>{p});
              m_pair_scatter.template run<kShift, kStrain>(
                  m_cells.view(0), m_cells.view(1), m_pos.data(), p, [&](auto sink) {
                    return SphPairInteraction<Physics, decltype(sink)>{
                        m_cells.view(0), m_cells.view(1), p, phys, m_support2, sink};
                  });
            } else {
              // GPU: every particle gathers its own sums (no atomics).
              backend::parallelFor(Space{}, m_n,
                                   SphInteraction<Physics>{m_cells.view(0), m_cells.view(1), p, phys, m_support2});
            }
          });
        });
      });
    });
    if (m_setup.sps()) {
      const double dp = m_setup.dp;
      const SpsStress<T> sps{T(m_setup.sps_cs * m_setup.sps_cs * dp * dp), T(2.0 / 3.0 * m_setup.sps_ci * dp * dp)};
      backend::parallelFor(Space{}, m_n, SpsUpdate<T>{sps, m_strain.data(), m_rho.data(), m_code.data(), m_tau.data()});
    }
  }

  SphSetup m_setup;
  int m_n = 0;
  long long m_step = 0;
  bool m_symplectic = false, m_has_moving = false;
  DiffusionDtLimits m_dt_limits;
  T m_mass = 0, m_eta2 = 0, m_support2 = 0;
  double m_g_abs = 0;
  TaitEos<T> m_eos;
  Vec3<T> m_gravity{}, m_up{}, m_lo{}, m_hi{};
  neighbors::CellList<Space, T> m_cells;  // two segments: fluid, then walls and bodies
  SphPairScatter<T> m_pair_scatter;       // host pair loop: rows for partners across thread chunks
  backend::Array<Space, Vec3<T>> m_pos, m_vel, m_pos0, m_vel_m1, m_pos_pre, m_vel_pre, m_ace, m_shift_grad;
  backend::Array<Space, Vec3<T>> m_wall_visc_vel;  // wall_velocity = no_slip, no_slip_ghost only
  backend::Array<Space, T> m_rho, m_rho_m1, m_rho_pre, m_press, m_drho, m_visc, m_shift_div;
  backend::Array<Space, int> m_code, m_id;
  // Bodies (DEM balls carrying a shell of body particles): per particle, per body.
  int m_bodies = 0;
  backend::Array<Space, int> m_body;
  backend::Array<Space, Vec3<T>> m_offset, m_body_pos, m_body_vel, m_body_omega;
  std::vector<SphBodyLoad> m_impulse;  // per body, of the step begun last (bodyImpulses)
  // Each body's particles by host number (CSR over bodies), the slot of every host number after
  // the last renumbering, and the per-body sums of bodyLoads().
  backend::Array<Space, int> m_body_start, m_body_members, m_slot_of;
  mutable backend::Array<Space, Vec3<double>> m_load_force, m_load_torque;
  // Host buffers of the per-body exchange (bodyLoads, setBodyKinematics), reused every step.
  mutable std::vector<SphBodyLoad> m_loads;
  mutable std::vector<Vec3<double>> m_host_load_force, m_host_load_torque;
  std::vector<Vec3<T>> m_host_body_pos, m_host_body_vel, m_host_body_omega;
  // mDBC (boundary = mdbc): ghost offsets per particle; the moving walls' angle.
  backend::Array<Space, Vec3<T>> m_ghost;
  mutable double m_theta = 0, m_omega = 0;
  backend::Array<Space, Sym3<T>> m_strain, m_tau;
  backend::Array<Space, Vec3<T>> m_scratch_vec;
  backend::Array<Space, T> m_scratch_real;
  backend::Array<Space, int> m_scratch_int;
  backend::Array<Space, Sym3<T>> m_scratch_sym;
};

}  // namespace millsim::sph
