#pragma once
// The WCSPH step as MILLSIM_HD functors (paper eqs. 15-45, the DualSPHysics formulation), run by
// backend::parallelFor on OpenMP and CUDA alike. Options that sit in the pair loop (kernel,
// density diffusion, viscosity, shifting) are template parameters, so an option that is off
// costs nothing per pair.
//
// Particles: fluid, fixed boundary (DBC), moving boundary (DBC with imposed motion), body
// (DBC particles carried by a rigid body - a DEM ball's shell - whose fluid force is summed to
// drive the body), and excluded (left the domain or the density limits; counted, never
// searched, never moved).
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"
#include "millsim/neighbors/cell_grid.hpp"
#include "sph/eos.hpp"
#include "sph/sph_pair.hpp"
#include "sph/viscosity.hpp"

namespace millsim::sph {

using core::Vec3;

template <class T>
struct SphView {
  Vec3<T>* pos;
  Vec3<T>* vel;
  T* rho;
  int* code;
  T* press;
  Vec3<T>* ace;         // dv/dt without gravity (fluid); fluid force / mass (body particles)
  T* drho;              // drho/dt
  T* visc_dt;           // max_b |h v_ab . r_ab| / (r^2 + eta^2), for the time step (eq. 40)
  Vec3<T>* shift_grad;  // grad C = sum_b V_b grad W (shifting)
  T* shift_div;         // div r = -sum_b V_b r_ab . grad W (free-surface detection)
  Sym3<T>* strain;      // strain rate S (laminar+SPS)
  Sym3<T>* tau;         // SPS stress from the previous step
  // Velocity a particle brings into the viscous terms: its own (fluid, and walls with
  // wall_velocity = dbc: then this is `vel`) or a wall's no-slip velocity (WallNoSlipVelocity).
  const Vec3<T>* visc_vel;
};

template <class T>
struct EosPressure {
  TaitEos<T> eos;
  const T* rho;
  T* press;
  MILLSIM_HD void operator()(int i) const { press[i] = eos.pressure(rho[i]); }
};

// The state a pair term reads of particle i.
template <class T, bool kStrain>
MILLSIM_HD MILLSIM_FORCE_INLINE SphSide<T> loadSide(const SphView<T>& p, int i) {
  SphSide<T> s{p.code[i], p.vel[i], p.visc_vel[i], p.rho[i], p.press[i], zeroSym3<T>()};
  if constexpr (kStrain) s.tau = p.tau[i];
  return s;
}

template <class T, bool kShift, bool kStrain>
MILLSIM_HD inline void storeSums(const SphView<T>& p, int a, const PairSums<T>& s) {
  p.drho[a] = s.drho;
  p.visc_dt[a] = s.visc_max;
  p.ace[a] = s.acc;
  if constexpr (kShift) {
    p.shift_grad[a] = s.grad_c;
    p.shift_div[a] = s.div_r;
  }
  if constexpr (kStrain) p.strain[a] = s.strain;
}

// Forces, continuity and the shifting sums of particle a from every neighbour b within 2h,
// each particle gathering its own sums (every pair visited from both sides: no writes to a
// partner, the GPU's loop). Fluid a: continuity (+ DDT with fluid b), pressure, viscosity,
// shifting sums. Boundary a (DBC, eq. 42): continuity from fluid neighbours only; a body
// particle also sums the pressure and viscous force of its fluid neighbours (the same pair
// terms with the roles swapped, so the pair forces are equal and opposite and momentum passes
// exactly between fluid and body).
template <class Physics, class T = decltype(Physics::mass)>
struct SphInteraction {
  neighbors::CellListView<T> fluid_cells;  // the fluid segment of the cell list
  neighbors::CellListView<T> bound_cells;  // walls and bodies
  SphView<T> p;
  Physics phys;
  T support2;  // (2h)^2

  MILLSIM_HD void operator()(int a) const {
    if (isExcluded(p.code[a])) {
      // Zero sums, as the OpenMP path's ClearPairSums leaves them: readers skip excluded
      // particles, but the slot must not hold another particle's sums from before a renumbering.
      storeSums<T, Physics::kShifting, Physics::kStrain>(p, a, PairSums<T>{});
      return;
    }
    const SphSide<T> sa = loadSide<T, Physics::kStrain>(p, a);
    PairSums<T> sums;
    auto pair = [&](int b, Vec3<T> r_ab, T r2) {
      if (b == a || r2 <= T(0)) return;
      const T fac = phys.kernel.fac(std::sqrt(r2));
      phys.addSide(sums, sa, loadSide<T, Physics::kStrain>(p, b), r_ab, r2, fac, fac * r_ab);
    };
    fluid_cells.forEachWithin(p.pos[a], support2, p.pos, pair);
    // A wall particle interacts with fluid only (in a 3D tank 3/4 of the particles are wall).
    if (sa.fluid()) bound_cells.forEachWithin(p.pos[a], support2, p.pos, pair);
    storeSums<T, Physics::kShifting, Physics::kStrain>(p, a, sums);
  }
};

// The same sums with each pair visited once (the host's loop): by its fluid side, and of a
// fluid-fluid pair by the lower-numbered particle (the particles are numbered in cell order,
// fluid first, so that is half the search block). Its partner's terms go to a sink
// (sph_scatter.hpp) that adds them to the partner's sums; boundary particles search nothing,
// as all their pairs have a fluid side. The sums must be cleared before the pass (ClearPairSums):
// a partner's share can arrive before or after its own pairs are done. Only the largest viscous
// speed is used, so each pair books it on its evaluating side alone.
template <class Physics, class Sink, class T = decltype(Physics::mass)>
struct SphPairInteraction {
  neighbors::CellListView<T> fluid_cells;
  neighbors::CellListView<T> bound_cells;
  SphView<T> p;
  Physics phys;
  T support2;
  Sink sink;

  MILLSIM_HD void operator()(int a) const {
    if (p.code[a] != kFluid) return;
    const SphSide<T> sa = loadSide<T, Physics::kStrain>(p, a);
    PairSums<T> sums;
    auto pair = [&](int b, Vec3<T> r_ab, T r2) {
      if (r2 <= T(0)) return;
      const T fac = phys.kernel.fac(std::sqrt(r2));
      const Vec3<T> grad = fac * r_ab;
      const SphSide<T> sb = loadSide<T, Physics::kStrain>(p, b);
      phys.addSide(sums, sa, sb, r_ab, r2, fac, grad);
      PairSums<T> share;
      phys.template addSide<false>(share, sb, sa, -r_ab, r2, fac, -grad);
      sink.addPartner(b, share);
    };
    const Vec3<T> xa = p.pos[a];
    fluid_cells.forEachWithinAfter(a, xa, support2, p.pos, pair);
    bound_cells.forEachWithin(xa, support2, p.pos, pair);
    sink.addOwn(a, sums);
  }
};

// Zeroes the sums the pair-once loop accumulates into.
template <class T, bool kShift, bool kStrain>
struct ClearPairSums {
  SphView<T> p;
  MILLSIM_HD void operator()(int a) const { storeSums<T, kShift, kStrain>(p, a, PairSums<T>{}); }
};

// No-slip velocity of the wall particles for the viscous terms (Adami, Hu & Adams 2012, J.
// Comput. Phys. 231:7057, eq. 23): a wall particle enters them with 2 v_w - v~, v~ the Shepard
// average of its fluid neighbours' velocity, so the velocity the fluid sees inside the wall
// continues its own profile through zero relative velocity at the wall surface. With DBC's
// plain v_w the wall layers all move at v_w, the viscous operator sees a weaker shear than the
// real one, and the fluid slips about a spacing past the wall (docs/validation.md, settling
// sphere). Density and pressure stay DBC's. Fluid particles keep their own velocity; a wall
// particle with no fluid within 2h keeps v_w. With no_slip_ghost (ghost set) the wall particles
// that have a ghost node take theirs from it instead (MdbcDensity<..., kNoSlip>): skipped here.
//
// A turning wall (the drum about z at omega_z, a body at its omega): the mirror is taken in the
// wall's own frame. The fluid's velocity relative to the wall's rigid motion, v_b - v_w(x_b),
// is mirrored, i.e. v* = v_a - mean_b (v_b - v_a - omega x (x_b - x_a)) = 2 v_a - v~ + omega x
// (x~ - x_a), x~ the Shepard mean of the fluid's positions. Adami's 2 v_a - v~ takes v_w at the
// wall particle for every fluid neighbour; a layer dp deep that is omega dp slower than the
// surface, so a fluid turning rigidly with the wall would be sheared by its own wall
// (tests/unit/test_sph_mdbc.cpp), and a turning cylinder got 15%, 6% and 3% less torque at a =
// 4, 8 and 16 dp (tests/validation/test_sph_rotating_sphere.cpp). For a translating wall the
// two are the same.
template <class T, class Kernel>
struct WallNoSlipVelocity {
  neighbors::CellListView<T> fluid_cells;
  const Vec3<T>* pos;
  const Vec3<T>* vel;
  const int* code;
  Kernel kernel;
  T support2;
  Vec3<T>* visc_vel;
  const Vec3<T>* ghost = nullptr;
  T omega_z = T(0);                     // the moving walls' rate about z
  const int* body = nullptr;            // each particle's body (-1: none); nullptr without bodies
  const Vec3<T>* body_omega = nullptr;  // the bodies' angular velocities
  MILLSIM_HD void operator()(int a) const {
    const int c = code[a];
    if (c == kFluid || isExcluded(c)) {
      visc_vel[a] = vel[a];
      return;
    }
    if (ghost && (ghost[a].x != T(0) || ghost[a].y != T(0) || ghost[a].z != T(0))) return;
    const Vec3<T> xa = pos[a];
    T w_sum = T(0);
    Vec3<T> wv_sum = core::zero3<T>(), wd_sum = core::zero3<T>();
    fluid_cells.forEachWithin(xa, support2, pos, [&](int b, Vec3<T> d_ab, T r2) {
      const T w = kernel.w(std::sqrt(r2));
      w_sum += w;
      wv_sum += w * vel[b];
      wd_sum += w * d_ab;  // x_a - x_b
    });
    if (!(w_sum > T(0))) {
      visc_vel[a] = vel[a];
      return;
    }
    Vec3<T> omega = core::zero3<T>();
    if (c == kBoundMoving) omega.z = omega_z;
    if (c == kBoundBody && body && body[a] >= 0) omega = body_omega[body[a]];
    const T inv = T(1) / w_sum;
    visc_vel[a] = T(2) * vel[a] - inv * wv_sum - core::cross(omega, inv * wd_sum);
  }
};

template <class T>
struct SpsUpdate {
  SpsStress<T> sps;
  const Sym3<T>* strain;
  const T* rho;
  const int* code;
  Sym3<T>* tau;
  MILLSIM_HD void operator()(int i) const { tau[i] = code[i] == kFluid ? sps(strain[i], rho[i]) : zeroSym3<T>(); }
};

// |dv/dt + g| of fluid particles (force condition of the time step, eq. 40).
template <class T>
struct FluidAcceleration {
  const Vec3<T>* ace;
  const int* code;
  Vec3<T> g;
  MILLSIM_HD T operator()(int i) const { return code[i] == kFluid ? core::norm(ace[i] + g) : T(0); }
};

template <class T>
struct ReadVisc {
  const T* visc;
  const int* code;
  MILLSIM_HD T operator()(int i) const { return isExcluded(code[i]) ? T(0) : visc[i]; }
};

// Imposed motion of moving boundaries: rotation about the z axis through `center` by `theta`
// (rad) from the initial position, at angular velocity `omega` (rad/s).
template <class T>
struct BoundaryMotion {
  Vec3<T> center;
  T cos_t, sin_t, omega;
  MILLSIM_HD void apply(Vec3<T> x0, Vec3<T>& x, Vec3<T>& v) const {
    const T dx = x0.x - center.x, dy = x0.y - center.y;
    x = {center.x + cos_t * dx - sin_t * dy, center.y + sin_t * dx + cos_t * dy, x0.z};
    v = {-omega * (x.y - center.y), omega * (x.x - center.x), T(0)};
  }
};

// Moving walls at their imposed position and velocity (initial placement).
template <class T>
struct PlaceMovingBoundaries {
  const Vec3<T>* pos0;
  Vec3<T>* pos;
  Vec3<T>* vel;
  const int* code;
  BoundaryMotion<T> motion;
  MILLSIM_HD void operator()(int i) const {
    if (code[i] == kBoundMoving) motion.apply(pos0[i], pos[i], vel[i]);
  }
};

// Body particles at their body's centre + offset, moving with it: v + omega x offset.
template <class T>
struct PlaceBodyParticles {
  const int* body;
  const Vec3<T>* offset;
  const Vec3<T>* body_pos;
  const Vec3<T>* body_vel;
  const Vec3<T>* body_omega;
  const int* code;
  Vec3<T>* pos;
  Vec3<T>* vel;
  MILLSIM_HD void operator()(int i) const {
    if (code[i] != kBoundBody) return;
    const int k = body[i];
    pos[i] = body_pos[k] + offset[i];
    vel[i] = body_vel[k] + core::cross(body_omega[k], offset[i]);
  }
};

// Slot of each particle by host number, after a renumbering (BodyLoadSum finds a body's
// particles through it).
struct SlotOfId {
  const int* id;
  int* slot_of;
  MILLSIM_HD void operator()(int i) const { slot_of[id[i]] = i; }
};

// The fluid's force and torque (about the centre) on body k: the sum of m a over its particles,
// which hold the pair forces from the fluid only (bodies are boundary particles: no gravity, and
// boundary pairs are not evaluated). One body per thread, its particles summed in host-number
// order (members[start[k] .. start[k + 1]), fixed at set-up), in double: the result is the same
// whatever the cell order, so a restarted run sums exactly as the straight one, and no per-step
// copy of the particle arrays to the host is needed.
template <class T>
struct BodyLoadSum {
  const int* start;
  const int* members;
  const int* slot_of;
  const Vec3<T>* ace;
  const Vec3<T>* offset;
  T mass;
  Vec3<double>* force;
  Vec3<double>* torque;
  MILLSIM_HD void operator()(int k) const {
    Vec3<double> f{0, 0, 0}, tq{0, 0, 0};
    for (int m = start[k]; m < start[k + 1]; ++m) {
      const int i = slot_of[members[m]];
      const Vec3<T> fi = mass * ace[i];
      const Vec3<T> ti = core::cross(offset[i], fi);
      f += Vec3<double>{double(fi.x), double(fi.y), double(fi.z)};
      tq += Vec3<double>{double(ti.x), double(ti.y), double(ti.z)};
    }
    force[k] = f;
    torque[k] = tq;
  }
};

// Shared by the integrators: limits that exclude a fluid particle, and the shifting displacement.
template <class T>
struct FluidChecks {
  T rho_min, rho_max;
  Vec3<T> lo, hi;
  // Fickian shifting (Lind et al. 2012, eqs. 44-45): dr = -A_s h |v| dt grad C, off where the
  // particle sees a free surface (div r < tfs).
  T shift_ah;  // A_s h
  T shift_tfs;

  MILLSIM_HD int code(Vec3<T> x, T rho) const {
    if (!(rho >= rho_min && rho <= rho_max)) return kExcludedDensity;  // also NaN
    if (!(x.x >= lo.x && x.x <= hi.x && x.y >= lo.y && x.y <= hi.y && x.z >= lo.z && x.z <= hi.z))
      return kExcludedDomain;
    return kFluid;
  }
  MILLSIM_HD Vec3<T> shift(Vec3<T> v, T dt, Vec3<T> grad_c, T div_r) const {
    if (div_r < shift_tfs) return core::zero3<T>();
    return (-shift_ah * core::norm(v) * dt) * grad_c;
  }
};

// Verlet (paper's scheme, DualSPHysics ComputeVerlet): normal steps leap-frog over two steps,
// every Ns-th step is an Euler step that re-couples the two chains.
template <class T, bool kShift>
struct VerletUpdate {
  SphView<T> p;
  Vec3<T>* vel_m1;
  T* rho_m1;
  const Vec3<T>* pos0;  // initial positions (moving boundaries only)
  BoundaryMotion<T> motion;
  FluidChecks<T> checks;
  Vec3<T> g;
  T dt, rho0;
  bool euler;

  MILLSIM_HD void operator()(int a) const {
    const int code = p.code[a];
    if (isExcluded(code)) return;
    const T rho = p.rho[a];
    const T rho_new = euler ? rho + dt * p.drho[a] : rho_m1[a] + T(2) * dt * p.drho[a];
    rho_m1[a] = rho;
    if (code != kFluid) {
      // DBC: density by continuity, never below rho0 (fluid must not be sucked into a wall).
      // Body particles are placed by the body (SphSolver::setBodyKinematics).
      p.rho[a] = rho_new > rho0 ? rho_new : rho0;
      if (code == kBoundMoving) motion.apply(pos0[a], p.pos[a], p.vel[a]);
      return;
    }
    const Vec3<T> acc = p.ace[a] + g;
    const Vec3<T> v = p.vel[a];
    const Vec3<T> v_new = euler ? v + dt * acc : vel_m1[a] + (T(2) * dt) * acc;
    Vec3<T> dx = dt * v + (T(0.5) * dt * dt) * acc;
    if constexpr (kShift) dx += checks.shift(v, dt, p.shift_grad[a], p.shift_div[a]);
    vel_m1[a] = v;
    p.vel[a] = v_new;
    p.rho[a] = rho_new;
    p.pos[a] += dx;
    p.code[a] = checks.code(p.pos[a], rho_new);
  }
};

// Symplectic position Verlet (eqs. 33-39), predictor half: state n kept in the *_pre arrays,
// the particle moved to n + 1/2 where the second force evaluation happens.
template <class T>
struct SymplecticPredictor {
  SphView<T> p;
  Vec3<T>* pos_pre;
  Vec3<T>* vel_pre;
  T* rho_pre;
  const Vec3<T>* pos0;
  BoundaryMotion<T> motion;  // at t + dt/2
  Vec3<T> g;
  T dt, rho0;

  MILLSIM_HD void operator()(int a) const {
    const int code = p.code[a];
    if (isExcluded(code)) return;
    const T h = T(0.5) * dt;
    pos_pre[a] = p.pos[a];
    vel_pre[a] = p.vel[a];
    rho_pre[a] = p.rho[a];
    const T rho_half = p.rho[a] + h * p.drho[a];
    if (code != kFluid) {
      p.rho[a] = rho_half > rho0 ? rho_half : rho0;
      if (code == kBoundMoving) motion.apply(pos0[a], p.pos[a], p.vel[a]);
      return;
    }
    p.rho[a] = rho_half;
    p.pos[a] += h * p.vel[a];
    p.vel[a] += h * (p.ace[a] + g);
  }
};

template <class T, bool kShift>
struct SymplecticCorrector {
  SphView<T> p;
  const Vec3<T>* pos_pre;
  const Vec3<T>* vel_pre;
  const T* rho_pre;
  const Vec3<T>* pos0;
  BoundaryMotion<T> motion;  // at t + dt
  FluidChecks<T> checks;
  Vec3<T> g;
  T dt, rho0;

  MILLSIM_HD void operator()(int a) const {
    const int code = p.code[a];
    if (isExcluded(code)) return;
    const T eps = -p.drho[a] / p.rho[a] * dt;
    const T rho_new = rho_pre[a] * (T(2) - eps) / (T(2) + eps);
    if (code != kFluid) {
      p.rho[a] = rho_new > rho0 ? rho_new : rho0;
      if (code == kBoundMoving) motion.apply(pos0[a], p.pos[a], p.vel[a]);
      return;
    }
    const Vec3<T> v_new = vel_pre[a] + dt * (p.ace[a] + g);
    Vec3<T> x_new = pos_pre[a] + (T(0.5) * dt) * (vel_pre[a] + v_new);
    if constexpr (kShift) x_new += checks.shift(v_new, dt, p.shift_grad[a], p.shift_div[a]);
    p.vel[a] = v_new;
    p.rho[a] = rho_new;
    p.pos[a] = x_new;
    p.code[a] = checks.code(x_new, rho_new);
  }
};

}  // namespace millsim::sph
