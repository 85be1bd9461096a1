#pragma once
// DemSolver<Space, T>: owns the DEM arrays in the execution space's memory and runs the step
// functors of dem_kernels.hpp through the backend. Written once; instantiated for OpenMP in
// dem_solver_omp.cpp and for CUDA in backend/cuda/dem_solver_cuda.cu (which first includes the
// CUDA PartnerScatter). The solver's particle numbering changes at every neighbour rebuild (cell
// order); m_id keeps each particle's number in the host state, which never changes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "dem/collision_stats.hpp"
#include "dem/contact/linear_spring.hpp"
#include "dem/dem_engine.hpp"
#include "dem/dem_kernels.hpp"
#include "dem/ensemble.hpp"
#include "dem/partner_scatter.hpp"
#include "dem/reorder_kernels.hpp"
#include "dem/rigid_body.hpp"
#include "dem/walls/stirrer_walls.hpp"
#include "millsim/core/capacity.hpp"
#include "millsim/core/error.hpp"
#include "millsim/neighbors/cell_list.hpp"

namespace millsim::dem {

template <class T>
struct KineticEnergy {
  ParticleView<T> p;
  MILLSIM_HD double operator()(int i) const {
    const double inertia = p.inv_inertia[i] > T(0) ? 1.0 / double(p.inv_inertia[i]) : 0.0;
    return 0.5 * double(p.mass[i]) * double(core::norm2(p.vel[i])) + 0.5 * inertia * double(core::norm2(p.omega[i]));
  }
};

// Pairs of i's half-list slots that overlap now by more than a rounding floor:
// dist < (ri + rj)(1 - 1e-9). A lattice charge (the stirred mills') puts neighbours at exactly
// touching, and without the floor the last bit of a position decides whether thousands of such
// force-free pairs count (on the GPU, 2026-12-04, 50 steps of cases/stirred_mill_ls1.xml: CUDA
// and OpenMP differed by 0.5% in contacts per bead, tests/gpu/test_cases_cuda_vs_omp.cpp).
// 1e-9 of the reach (1.8e-12 m for 1.8 mm beads) is ~1000x below the overlap one bead's weight
// makes at the linear stiffness of cases/stirred_mill_ls1.xml, so every load-carrying contact
// counts. In float the floor is below the rounding of the distance (~6e-8), so the count is the
// plain dist < ri + rj there.
template <class T>
struct PairContactCount {
  ParticleView<T> p;
  const int* nbr_start;
  const int* nbr_list;
  MILLSIM_HD double operator()(int i) const {
    constexpr double kFloor = 1.0 - 2e-9;  // on the squared distance: (1 - 1e-9)^2
    int c = 0;
    for (int slot = nbr_start[i]; slot < nbr_start[i + 1]; ++slot) {
      const int j = nbr_list[slot];
      const double reach = double(p.radius[i]) + double(p.radius[j]);
      if (double(core::norm2(p.pos[i] - p.pos[j])) < kFloor * reach * reach) ++c;
    }
    return double(c);
  }
};

template <class T>
struct PotentialEnergy {
  ParticleView<T> p;
  Vec3<T> g;
  MILLSIM_HD double operator()(int i) const { return -double(p.mass[i]) * double(core::dot(g, p.pos[i])); }
};

template <class T>
struct MassMoment {
  ParticleView<T> p;
  int axis;
  MILLSIM_HD double operator()(int i) const {
    const Vec3<T> x = p.pos[i];
    return double(p.mass[i]) * double(axis == 0 ? x.x : x.y);
  }
};

template <class T>
struct ReadDouble {
  const double* v;
  MILLSIM_HD double operator()(int i) const { return v[i]; }
};

template <class T>
struct ReadReal {
  const T* v;
  MILLSIM_HD double operator()(int i) const { return double(v[i]); }
};

template <class T>
struct Speed {
  const Vec3<T>* v;
  MILLSIM_HD double operator()(int i) const { return std::sqrt(double(core::norm2(v[i]))); }
};

struct ReadTally {
  const CollisionTally* t;
  int field;  // 0..3 dissipated by mode, 4 normal, 5 wall, 6..9 energy, 10 collisions
  MILLSIM_HD double operator()(int i) const {
    const CollisionTally& c = t[i];
    if (field < 4) return c.dissipated[field];
    if (field == 4) return c.dissipated_normal;
    if (field == 5) return c.dissipated_wall;
    if (field < 10) return c.energy[field - 6];
    return c.collisions;
  }
};

template <class U>
struct Copy {
  const U* src;
  U* dst;
  MILLSIM_HD void operator()(int i) const { dst[i] = src[i]; }
};

template <class Space, class T>
class DemSolver final : public DemEngine {
 public:
  explicit DemSolver(const DemSetup& setup) : m_setup(setup) {
    m_law.k_coef = T(setup.k_coef);
    m_law.alpha = T(setup.alpha);
    m_law.friction = T(setup.friction);
    m_linear.kn = T(setup.linear_kn);
    m_linear.zeta = T(setup.linear_zeta);
    m_linear.friction = T(setup.friction);
    m_lub.viscosity = T(setup.lubrication_viscosity);
    m_lub.inner = T(setup.lubrication_inner);
    m_lub.outer = T(setup.lubrication_outer);
    // Lubrication acts at gaps up to outer (r_i + r_j): the cells and the list reach that far.
    const double range_factor = lubricated() ? setup.lubrication_outer : 0.0;
    const T cell = T(2 * setup.max_radius * (1 + range_factor) + setup.skin);
    m_cells.setGrid(neighbors::makeGrid<T>(toVec(setup.domain_lo), toVec(setup.domain_hi), cell, false));
    if (setup.ensemble.scenes() > 0) setEnsemble(setup.ensemble, double(cell));
  }

  const char* backendName() const override { return Space::kName; }
  const char* precisionName() const override { return sizeof(T) == 4 ? "float" : "double"; }

  void setState(const DemHostState& s) override {
    m_n = static_cast<int>(s.size());
    if (ensemble() && m_setup.ensemble.start.back() != m_n)
      throw std::invalid_argument("DemSolver::setState: the ensemble's scenes hold " +
                                  std::to_string(m_setup.ensemble.start.back()) + " particles, the state " +
                                  std::to_string(m_n));
    const std::size_t n = s.size();
    std::vector<Vec3<T>> pos(n), vel(n), omega(n);
    std::vector<T> radius(n), mass(n), inv_mass(n), inv_inertia(n);
    std::vector<int> id(n);
    for (std::size_t i = 0; i < n; ++i) {
      pos[i] = {T(s.pos[3 * i]), T(s.pos[3 * i + 1]), T(s.pos[3 * i + 2])};
      vel[i] = {T(s.vel[3 * i]), T(s.vel[3 * i + 1]), T(s.vel[3 * i + 2])};
      omega[i] = {T(s.omega[3 * i]), T(s.omega[3 * i + 1]), T(s.omega[3 * i + 2])};
      radius[i] = T(s.radius[i]);
      mass[i] = T(s.mass[i]);
      inv_mass[i] = T(1.0 / s.mass[i]);
      inv_inertia[i] = s.inertia[i] > 0 ? T(1.0 / s.inertia[i]) : T(0);
      id[i] = static_cast<int>(i);
    }
    m_max_radius = std::max(m_setup.max_radius, s.radius.empty() ? 0.0 : *std::max_element(s.radius.begin(), s.radius.end()));
    m_pos.copyFromHost(pos);
    m_vel.copyFromHost(vel);
    m_omega.copyFromHost(omega);
    m_radius.copyFromHost(radius);
    m_mass.copyFromHost(mass);
    m_inv_mass.copyFromHost(inv_mass);
    m_inv_inertia.copyFromHost(inv_inertia);
    m_id.copyFromHost(id);
    m_force.resize(n, core::zero3<T>());
    m_torque.resize(n, core::zero3<T>());
    m_pos_ref.resize(n, core::zero3<T>());
    m_dissipated.copyFromHost(s.dissipated.size() == n ? s.dissipated : std::vector<double>(n, 0.0));
    m_work_in.copyFromHost(s.work_in.size() == n ? s.work_in : std::vector<double>(n, 0.0));
    m_elastic.resize(n, T(0));
    m_drum_torque.resize(n, T(0));
    m_overflow.resize(n, 0);
    m_nbr_count.resize(n, 0);
    m_nbr_start.resize(n + 1, 0);
    m_scatter.listChanged(nullptr, nullptr);
    seedHistory(s);
    m_restored_force.resize(0);
    m_restored_torque.resize(0);
    if (s.force.size() == 3 * n && s.torque.size() == 3 * n) {
      std::vector<Vec3<T>> f(n), tq(n);
      for (std::size_t i = 0; i < n; ++i) {
        f[i] = {T(s.force[3 * i]), T(s.force[3 * i + 1]), T(s.force[3 * i + 2])};
        tq[i] = {T(s.torque[3 * i]), T(s.torque[3 * i + 1]), T(s.torque[3 * i + 2])};
      }
      m_restored_force.copyFromHost(f);
      m_restored_torque.copyFromHost(tq);
    }
    m_scratch.resize(0);
    m_old_of_new.resize(n, 0);
    m_nb = 0;  // bodies, if any, come with setBodies
    m_steps = 0;
    m_has_external = false;
    m_has_body_external = false;
    if (s.work_external.size() == n)  // a restart's external work carries on; else sized when loads come
      m_work_external.copyFromHost(s.work_external);
    else
      m_work_external.resize(0);
    m_body_work_ext.resize(0);
    // Stirred-mill arrays exist only once a stirred step runs (allocateStirred).
    m_tally.resize(0);
    m_lub_dissipated.resize(0);
    m_fixed_torque.resize(0);
  }

  void setBodies(const DemBodies& b) override {
    m_nb = static_cast<int>(b.size());
    if (m_nb == 0) return;
    if (ensemble()) throw std::invalid_argument("DemSolver::setBodies: an ensemble runs spheres only");
    const int ne = b.elements();
    bool ordered = !b.start.empty() && b.start[0] == 0;
    for (int k = 0; ordered && k < m_nb; ++k) ordered = b.start[k] < b.start[k + 1];
    if (!ordered || static_cast<int>(b.start.size()) != m_nb + 1 || ne > m_n ||
        b.offset.size() != 3 * std::size_t(ne) || b.pos.size() != 3 * std::size_t(m_nb) ||
        b.vel.size() != b.pos.size() || b.ang_mom.size() != b.pos.size() || b.quat.size() != 4 * std::size_t(m_nb) ||
        b.inertia.size() != 6 * std::size_t(m_nb) || b.radius.size() != std::size_t(m_nb))
      throw std::invalid_argument("DemSolver::setBodies: inconsistent body arrays");
    std::vector<Vec3<T>> pos(m_nb), vel(m_nb), L(m_nb), omega(m_nb), offset(ne);
    std::vector<Quat<T>> q(m_nb);
    std::vector<Sym3<T>> inv_inertia(m_nb);
    std::vector<T> inv_mass(m_nb);
    for (int k = 0; k < m_nb; ++k) {
      pos[k] = get3(b.pos, k);
      vel[k] = get3(b.vel, k);
      L[k] = get3(b.ang_mom, k);
      q[k] = {T(b.quat[4 * k]), T(b.quat[4 * k + 1]), T(b.quat[4 * k + 2]), T(b.quat[4 * k + 3])};
      const double* I = &b.inertia[6 * k];
      const Sym3<double> inv = symInverse(Sym3<double>{I[0], I[1], I[2], I[3], I[4], I[5]});
      inv_inertia[k] = {T(inv.xx), T(inv.yy), T(inv.zz), T(inv.xy), T(inv.xz), T(inv.yz)};
      inv_mass[k] = T(1.0 / b.mass[k]);
      omega[k] = angularVelocity(q[k], inv_inertia[k], L[k]);
    }
    for (int e = 0; e < ne; ++e) offset[e] = get3(b.offset, e);
    // Per particle (current numbering = host numbering right after setState): body id, the
    // contact mass, and inv_mass 0 so the particle kicks leave the elements to their bodies.
    std::vector<int> id, body_of(m_n, -1);
    std::vector<T> contact_mass, inv_mass_p;
    m_id.copyToHost(id);
    m_mass.copyToHost(contact_mass);
    m_inv_mass.copyToHost(inv_mass_p);
    for (int i = 0; i < m_n; ++i) {
      const int h = id[i];
      if (h >= ne) continue;
      const int k = static_cast<int>(std::upper_bound(b.start.begin(), b.start.end(), h) - b.start.begin()) - 1;
      body_of[i] = k;
      contact_mass[i] = T(b.mass[k]);
      inv_mass_p[i] = T(0);
    }
    m_body_pos.copyFromHost(pos);
    m_body_vel.copyFromHost(vel);
    m_body_L.copyFromHost(L);
    m_body_omega.copyFromHost(omega);
    m_body_q.copyFromHost(q);
    m_body_inv_inertia.copyFromHost(inv_inertia);
    m_body_inv_mass.copyFromHost(inv_mass);
    m_body_force.resize(m_nb, core::zero3<T>());
    m_body_torque.resize(m_nb, core::zero3<T>());
    m_body_start.copyFromHost(b.start);
    m_elem_offset.copyFromHost(offset);
    m_body_of.copyFromHost(body_of);
    m_contact_mass.copyFromHost(contact_mass);
    m_inv_mass.copyFromHost(inv_mass_p);
    m_index_of_host.resize(m_n, 0);
    // Host copies in double: a checkpoint round trip must not perturb them through T.
    m_body_radius = b.radius;
    m_body_mass_host = b.mass;
    m_body_inertia_host = b.inertia;
    m_has_body_external = false;
    if (b.work_external.size() == static_cast<std::size_t>(m_nb)) m_body_work_ext.copyFromHost(b.work_external);
    // The elements start exactly on their bodies.
    backend::parallelFor(Space{}, m_n, InvertIds{m_id.data(), m_index_of_host.data()});
    placeElements();
  }

  void getBodies(DemBodies& b) const override {
    b = DemBodies{};
    if (m_nb == 0) return;
    std::vector<Vec3<T>> pos, vel, L, offset;
    std::vector<Quat<T>> q;
    m_body_pos.copyToHost(pos);
    m_body_vel.copyToHost(vel);
    m_body_L.copyToHost(L);
    m_body_q.copyToHost(q);
    m_body_start.copyToHost(b.start);
    m_elem_offset.copyToHost(offset);
    for (int k = 0; k < m_nb; ++k) {
      b.pos.insert(b.pos.end(), {double(pos[k].x), double(pos[k].y), double(pos[k].z)});
      b.vel.insert(b.vel.end(), {double(vel[k].x), double(vel[k].y), double(vel[k].z)});
      b.ang_mom.insert(b.ang_mom.end(), {double(L[k].x), double(L[k].y), double(L[k].z)});
      b.quat.insert(b.quat.end(), {double(q[k].w), double(q[k].x), double(q[k].y), double(q[k].z)});
    }
    b.mass = m_body_mass_host;
    b.inertia = m_body_inertia_host;
    for (const Vec3<T>& o : offset) b.offset.insert(b.offset.end(), {double(o.x), double(o.y), double(o.z)});
    b.radius = m_body_radius;
    if (m_body_work_ext.size() == static_cast<std::size_t>(m_nb)) m_body_work_ext.copyToHost(b.work_external);
  }

  void getState(DemHostState& s) const override {
    std::vector<Vec3<T>> pos, vel, omega, pair_xi, wall_xi;
    std::vector<T> radius, mass, inv_inertia;
    std::vector<int> id, start, list, wall_key;
    std::vector<double> dissipated, work_in, work_external;
    m_pos.copyToHost(pos);
    m_vel.copyToHost(vel);
    m_omega.copyToHost(omega);
    m_radius.copyToHost(radius);
    m_mass.copyToHost(mass);
    m_inv_inertia.copyToHost(inv_inertia);
    m_id.copyToHost(id);
    m_nbr_start.copyToHost(start);
    m_nbr_list.copyToHost(list);
    m_pair_xi.copyToHost(pair_xi);
    m_wall_key.copyToHost(wall_key);
    m_wall_xi.copyToHost(wall_xi);
    m_dissipated.copyToHost(dissipated);
    m_work_in.copyToHost(work_in);
    const bool has_work_external = m_work_external.size() == static_cast<std::size_t>(m_n) && m_n > 0;
    if (has_work_external) m_work_external.copyToHost(work_external);
    std::vector<Vec3<T>> force, torque, ext_force, ext_torque;
    m_force.copyToHost(force);
    m_torque.copyToHost(torque);
    if (m_has_external) {
      m_ext_force.copyToHost(ext_force);
      m_ext_torque.copyToHost(ext_torque);
    }
    const std::size_t n = pos.size();
    s.force.resize(3 * n);
    s.torque.resize(3 * n);
    s.pos.resize(3 * n);
    s.vel.resize(3 * n);
    s.omega.resize(3 * n);
    s.radius.resize(n);
    s.mass.resize(n);
    s.inertia.resize(n);
    s.dissipated.resize(n);
    s.work_in.resize(n);
    s.work_external.assign(has_work_external ? n : 0, 0.0);
    s.hist_id.assign(n * kHistorySlots, kNoPartner);
    s.hist_xi.assign(3 * n * kHistorySlots, 0.0);
    std::vector<int> used(n, 0);
    // A checkpoint's table: each spring with the lower host number of its pair, seen from it.
    auto record = [&](int owner, std::int64_t key, Vec3<T> xi) {
      if (used[owner] >= kHistorySlots) return;  // > 16 contacts: the rest restart unloaded
      const std::size_t e = static_cast<std::size_t>(owner) * kHistorySlots + used[owner]++;
      s.hist_id[e] = key;
      put3(s.hist_xi, e, xi);
    };
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t h = static_cast<std::size_t>(id[i]);
      put3(s.pos, h, pos[i]);
      put3(s.vel, h, vel[i]);
      put3(s.omega, h, omega[i]);
      s.radius[h] = double(radius[i]);
      s.mass[h] = double(mass[i]);
      s.inertia[h] = inv_inertia[i] > T(0) ? 1.0 / double(inv_inertia[i]) : 0.0;
      s.dissipated[h] = dissipated[i];
      s.work_in[h] = work_in[i];
      if (has_work_external) s.work_external[h] = work_external[i];
      put3(s.force, h, m_has_external ? force[i] - ext_force[h] : force[i]);
      put3(s.torque, h, m_has_external ? torque[i] - ext_torque[h] : torque[i]);
      for (int q = 0; q < kWallSlots && wall_key[i * kWallSlots + q] != kNoPartner; ++q)
        record(id[i], wallKey(wall_key[i * kWallSlots + q]), wall_xi[i * kWallSlots + q]);
      for (int slot = start[i]; slot < start[i + 1]; ++slot) {
        const Vec3<T> xi = pair_xi[slot];
        if (!loaded(xi)) continue;
        const int a = id[i], b = id[list[slot]];
        if (a < b)
          record(a, b, xi);
        else
          record(b, a, -xi);
      }
    }
  }

  // The forces of the given state, for the first half-kick. The springs are left as given: a
  // force evaluation with dt = 0 still moves a sliding contact's spring (onto -F_t/k_t with the
  // damping included), and a restart must continue from the checkpoint's springs.
  void initialize(const DrumState& walls) override {
    requireSingleScene();
    initializeDrum(walls);
  }
  void initialize(const std::vector<DrumState>& drums) override { initializeDrum(drums); }

  template <class Drums>
  void initializeDrum(const Drums& walls) {
    rebuildNeighbours();
    forcesKeepingHistory(walls);
    takeRestoredForces();
    if (m_nb > 0) {
      bodyLoads();
      placeElements();  // omega from (q, L) on every element before the first step
    }
  }

  void initialize(const StirrerState& walls) override {
    allocateStirred();
    rebuildNeighbours();
    forcesKeepingHistory(walls);
    takeRestoredForces();
    if (m_nb > 0) {
      bodyLoads();
      placeElements();
    }
  }

  void step(const StirrerState& walls, double dt_in) override { stepWith(walls, T(dt_in), dt_in); }

  // The forces and sums at the present state (a step of 0) for the observers, leaving the
  // contact history as it was: the dt = 0 pass would project and Coulomb-cap every spring with
  // v(t) instead of the step's half-step velocity, and count the touching pairs whose spring is
  // still zero as collisions begun. A restart then continues the checkpointed run exactly (the
  // stirred bed's kinetic energy was 1.8e-7 off after 6 steps before this pass kept them), and
  // a fresh run counts its first collisions in its first step.
  template <class Walls>
  void forcesKeepingHistory(const Walls& walls) {
    backend::Array<Space, Vec3<T>> pair_xi(m_pair_xi.size()), wall_xi(m_wall_xi.size());
    backend::Array<Space, int> wall_key(m_wall_key.size());
    backend::Array<Space, CollisionTally> tally(m_tally.size());
    copyAll(m_pair_xi, pair_xi);
    copyAll(m_wall_xi, wall_xi);
    copyAll(m_wall_key, wall_key);
    copyAll(m_tally, tally);
    computeForces(walls, T(0));
    m_pair_xi.swap(pair_xi);
    m_wall_xi.swap(wall_xi);
    m_wall_key.swap(wall_key);
    m_tally.swap(tally);
  }

  StirredSums stirredSums() const override {
    StirredSums s;
    if (m_fixed_torque.size() != static_cast<std::size_t>(m_n)) return s;
    s.stirrer_torque = backend::reduceSum<double>(Space{}, m_n, ReadReal<T>{m_drum_torque.data()});
    s.outer_torque = backend::reduceSum<double>(Space{}, m_n, ReadReal<T>{m_fixed_torque.data()});
    if (lubricated())
      s.lubrication_dissipated = backend::reduceSum<double>(Space{}, m_n, ReadDouble<T>{m_lub_dissipated.data()});
    if (m_tally.size() != static_cast<std::size_t>(m_n)) return s;  // no collision statistics asked for
    double v[11];
    for (int f = 0; f < 11; ++f) v[f] = backend::reduceSum<double>(Space{}, m_n, ReadTally{m_tally.data(), f});
    for (int q = 0; q < kModeCount; ++q) {
      s.totals.dissipated[q] = v[q];
      s.totals.energy[q] = v[6 + q];
    }
    s.totals.dissipated_normal = v[4];
    s.totals.dissipated_wall = v[5];
    s.totals.collisions = v[10];
    return s;
  }

  void collisionTallies(std::vector<CollisionTally>& out) const override { toHostOrder(m_tally, out); }

  void stirredAccounts(std::vector<CollisionTally>& tallies, std::vector<double>& lubrication) const override {
    toHostOrder(m_tally, tallies);
    lubrication.clear();
    if (m_lub_dissipated.size() == static_cast<std::size_t>(m_n)) toHostOrder(m_lub_dissipated, lubrication);
  }

  // allocateStirred (at initialize) keeps arrays that already have one entry per bead.
  void setStirredAccounts(const std::vector<CollisionTally>& tallies, const std::vector<double>& lubrication) override {
    const std::size_t n = static_cast<std::size_t>(m_n);
    if (m_setup.collision_stats && tallies.size() == n) fromHostOrder(tallies, m_tally);
    if (lubricated() && lubrication.size() == n) fromHostOrder(lubrication, m_lub_dissipated);
  }

  void step(const DrumState& walls, double dt_in) override {
    requireSingleScene();
    stepWith(walls, T(dt_in), dt_in);
  }
  // Each case by its own step (0: a case that has ended rests).
  void step(const std::vector<DrumState>& drums, const std::vector<double>& dt) override {
    if (!ensemble() || dt.size() != drums.size() || static_cast<int>(dt.size()) != m_slabs.count)
      throw std::invalid_argument("DemSolver: one drum state and one time step per ensemble scene expected");
    double largest = 0;
    bool changed = false;
    for (std::size_t k = 0; k < dt.size(); ++k) {
      changed = changed || m_host_dt[k] != T(dt[k]);
      m_host_dt[k] = T(dt[k]);
      largest = std::max(largest, dt[k]);
    }
    if (changed) m_scene_dt.copyFromHost(m_host_dt);  // only when a case starts or ends
    stepWith(drums, SceneTable<T>{m_scene_dt.data(), m_slabs}, largest);
  }

  // One step with the walls' state at its end; dt is the step (T) or an ensemble's per case
  // (SceneTable; spheres only, no bodies or external loads), dt_report its largest value.
  template <class Walls, class Dt>
  void stepWith(const Walls& walls, Dt dt, double dt_report) {
    constexpr bool kPlain = std::is_same_v<Dt, T>;
    ++m_steps;
    // The body loads of the last contact pass are current, unless a new held external load came
    // since: then they are summed again before KickDrift clears the element forces.
    if (m_body_loads_stale) {
      bodyLoads();
      m_body_loads_stale = false;
    }
    backend::parallelFor(Space{}, m_n, KickDrift<T, Dt>{view(), dt});
    m_sums_cleared = true;
    if constexpr (kPlain) {
      if (m_nb > 0) {
        backend::parallelFor(Space{}, m_nb, BodyKickDrift<T>{bodyView(), dt});
        placeElements();
      }
    }
    if (movedPastHalfSkin(dt_report)) rebuildNeighbours();
    computeForces(walls, dt);
    if constexpr (kPlain) {
      if (m_has_body_external)
        backend::parallelFor(Space{}, m_nb,
                             BodyExternalWork<T>{bodyView(), m_body_ext_force.data(), m_body_ext_torque.data(),
                                                 m_body_work_ext.data(), dt});
    }
    backend::parallelFor(Space{}, m_n, Kick<T, Dt>{view(), dt});
    if constexpr (kPlain) {
      if (m_nb > 0) {
        bodyLoads();
        backend::parallelFor(Space{}, m_nb, BodyKick<T>{bodyView(), dt});
        placeElements();
      }
    }
  }

  DemSums sums() const override {
    DemSums s = sumsOver([](const auto& f) { return f; });
    if (m_body_work_ext.size() == static_cast<std::size_t>(m_nb) && m_nb > 0)
      s.work_external = backend::reduceSum<double>(Space{}, m_nb, ReadDouble<T>{m_body_work_ext.data()});
    return s;
  }

  std::vector<DemSums> sceneSums(const std::vector<bool>& wanted) const override {
    std::vector<DemSums> out;
    const std::vector<int>& start = m_setup.ensemble.start;
    for (int k = 0; k < m_setup.ensemble.scenes(); ++k) {
      if (!wanted.empty() && !wanted.at(static_cast<std::size_t>(k))) {
        out.emplace_back();
        continue;
      }
      const int lo = start[k], hi = start[k + 1];
      out.push_back(sumsOver([&](const auto& f) {
        return HostRange<std::decay_t<decltype(f)>>{f, m_id.data(), lo, hi};
      }));
    }
    return out;
  }

  std::map<std::string, std::size_t> memoryBytes() const override {
    return {
        {"dem.particles", m_pos.bytes() + m_vel.bytes() + m_omega.bytes() + m_force.bytes() + m_torque.bytes() +
                              m_radius.bytes() + m_mass.bytes() + m_inv_mass.bytes() + m_inv_inertia.bytes() +
                              m_id.bytes()},
        {"dem.contact_history",
         m_pair_xi.bytes() + m_wall_key.bytes() + m_wall_xi.bytes() + m_overflow.bytes() + m_old_xi.bytes()},
        {"dem.energy_accounting", m_dissipated.bytes() + m_work_in.bytes() + m_elastic.bytes() + m_drum_torque.bytes() +
                                      m_fixed_torque.bytes() + m_work_external.bytes()},
        {"dem.external_loads",
         m_ext_force.bytes() + m_ext_torque.bytes() + m_ext_force_old.bytes() + m_ext_torque_old.bytes()},
        {"dem.partner_scatter", m_scatter.bytes()},
        {"dem.reorder_scratch", m_scratch.bytes() + m_old_of_new.bytes()},
        {"dem.collision_stats", m_tally.bytes()},
        {"dem.bodies", m_body_pos.bytes() + m_body_vel.bytes() + m_body_L.bytes() + m_body_omega.bytes() +
                           m_body_q.bytes() + m_body_force.bytes() + m_body_torque.bytes() + m_body_inv_mass.bytes() +
                           m_body_inv_inertia.bytes() + m_body_start.bytes() + m_elem_offset.bytes() +
                           m_index_of_host.bytes() + m_body_of.bytes() + m_contact_mass.bytes() +
                           m_body_ext_force.bytes() + m_body_ext_torque.bytes() + m_body_work_ext.bytes()},
        {"dem.lubrication", m_lub_dissipated.bytes()},
        {"dem.ensemble", m_scene_params.bytes() + m_scene_drums.bytes() + m_scene_dt.bytes() + m_scene_skin.bytes()},
        {"neighbors", m_cells.bytes() + m_nbr_count.bytes() + m_nbr_start.bytes() + m_nbr_list.bytes() +
                          m_old_start.bytes() + m_old_list.bytes() + m_pos_ref.bytes()}};
  }

  std::int64_t neighbourRebuilds() const override { return m_rebuilds; }

  void setExternalForces(const std::vector<double>& force, const std::vector<double>& torque) override {
    if (m_nb > 0) {
      setBodyExternalForces(force, torque);
      return;
    }
    if (force.empty() && !m_has_external) return;
    std::vector<Vec3<T>>&f = m_host_vec_a, &t = m_host_vec_b;
    f.assign(m_n, core::zero3<T>());
    t.assign(m_n, core::zero3<T>());
    if (!force.empty()) {
      if (force.size() != 3 * static_cast<std::size_t>(m_n) || torque.size() != force.size())
        throw std::invalid_argument("DemSolver::setExternalForces: expected 3 values per ball");
      for (int i = 0; i < m_n; ++i) {
        f[i] = get3(force, i);
        t[i] = get3(torque, i);
      }
    }
    // The old load leaves the current force and the new one enters it (ReplaceHeldLoad); the
    // old arrays are kept for that in the scratch pair.
    m_ext_force.swap(m_ext_force_old);
    m_ext_torque.swap(m_ext_torque_old);
    m_ext_force.copyFromHost(f);
    m_ext_torque.copyFromHost(t);
    const bool had = m_has_external;
    backend::parallelFor(Space{}, m_n,
                         ReplaceHeldLoad<T>{view(), m_id.data(), had ? m_ext_force_old.data() : nullptr,
                                            m_ext_torque_old.data(), m_ext_force.data(), m_ext_torque.data()});
    if (m_work_external.size() != static_cast<std::size_t>(m_n)) m_work_external.resize(m_n, 0.0);
    m_has_external = !force.empty();
  }

  void ballKinematics(BallKinematics& out) const override {
    const int n = m_nb > 0 ? m_nb : m_n;
    out.pos.resize(3 * static_cast<std::size_t>(n));
    out.vel.resize(out.pos.size());
    out.omega.resize(out.pos.size());
    std::vector<Vec3<T>>&x = m_host_vec_a, &v = m_host_vec_b, &w = m_host_vec_c;
    if (m_nb > 0) {  // bodies are stored in body order
      m_body_pos.copyToHost(x);
      m_body_vel.copyToHost(v);
      m_body_omega.copyToHost(w);
    } else {  // particles in cell order: slot i holds host number id[i]
      m_pos.copyToHost(x);
      m_vel.copyToHost(v);
      m_omega.copyToHost(w);
      m_id.copyToHost(m_host_id);
    }
    for (int i = 0; i < n; ++i) {
      const std::size_t k = 3 * static_cast<std::size_t>(m_nb > 0 ? i : m_host_id[i]);
      const Vec3<T> xi = x[i], vi = v[i], wi = w[i];
      out.pos[k] = double(xi.x), out.pos[k + 1] = double(xi.y), out.pos[k + 2] = double(xi.z);
      out.vel[k] = double(vi.x), out.vel[k + 1] = double(vi.y), out.vel[k + 2] = double(vi.z);
      out.omega[k] = double(wi.x), out.omega[k + 1] = double(wi.y), out.omega[k + 2] = double(wi.z);
    }
  }

 private:
  static Vec3<T> toVec(const std::array<double, 3>& a) { return {T(a[0]), T(a[1]), T(a[2])}; }

  // A per-particle array in cell order (slot i holds host number id[i]) to host numbering, and
  // back: what checkpoints and per-bead outputs exchange with the solver.
  template <class V, class Array>
  void toHostOrder(const Array& a, std::vector<V>& out) const {
    std::vector<V> v;
    std::vector<int> id;
    a.copyToHost(v);
    m_id.copyToHost(id);
    out.assign(v.size(), V{});
    for (std::size_t i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(id[i])] = v[i];
  }
  template <class V, class Array>
  void fromHostOrder(const std::vector<V>& in, Array& a) const {
    std::vector<int> id;
    m_id.copyToHost(id);
    std::vector<V> now(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) now[i] = in[static_cast<std::size_t>(id[i])];
    a.copyFromHost(now);
  }

  // The error a diverged step stops the run with: the first particle that moved more than 3e14 m
  // (or to NaN/Inf) since the last neighbour build, by host number, with its position then and
  // now, its velocity and the solver step.
  core::SimulationError divergence(T dt) const {
    std::vector<Vec3<T>> pos, ref, vel;
    std::vector<int> id;
    m_pos.copyToHost(pos);
    m_pos_ref.copyToHost(ref);
    m_vel.copyToHost(vel);
    m_id.copyToHost(id);
    // The particle that moved farthest since the list was built (a non-finite one first): the
    // one stepWith's test (plain, or scaled by an ensemble case's skin) tripped on.
    std::size_t bad = 0;
    T worst = T(-1);
    for (std::size_t i = 0; i < pos.size(); ++i) {
      const T d2 = core::norm2(pos[i] - ref[i]);
      const T key = d2 == d2 && d2 <= std::numeric_limits<T>::max() ? d2 : std::numeric_limits<T>::infinity();
      if (key > worst) {
        worst = key;
        bad = i;
      }
    }
    std::ostringstream m;
    const int host = id.empty() ? 0 : id[bad];
    m << "DEM: particle " << host;
    if (ensemble()) {  // which case, and its own ball number
      const std::vector<int>& start = m_setup.ensemble.start;
      const auto k = std::upper_bound(start.begin(), start.end(), host) - start.begin() - 1;
      m << " (case " << k << " of the ensemble, its ball " << host - start[static_cast<std::size_t>(k)] << ")";
    }
    if (m_nb > 0) {
      std::vector<int> body_of;
      m_body_of.copyToHost(body_of);
      if (body_of[bad] >= 0) m << " (element of DCDEM body " << body_of[bad] << ")";
    }
    m << " diverged at solver step " << m_steps << ": position (" << pos[bad].x << ", " << pos[bad].y << ", "
      << pos[bad].z << ") m, at the last neighbour "
      << "build (" << ref[bad].x << ", " << ref[bad].y << ", " << ref[bad].z << ") m, velocity (" << vel[bad].x << ", "
      << vel[bad].y << ", " << vel[bad].z << ") m/s. Likely cause: dt = " << double(dt)
      << " s is too large for the stiffest contact or lubrication film (use the automatic time step, or a "
         "larger dt_divisor)";
    return core::SimulationError(m.str());
  }
  static void put3(std::vector<double>& v, std::size_t i, Vec3<T> a) {
    v[3 * i] = double(a.x);
    v[3 * i + 1] = double(a.y);
    v[3 * i + 2] = double(a.z);
  }

  ParticleView<T> view() {
    return {m_pos.data(),         m_vel.data(),
            m_omega.data(),       m_force.data(),
            m_torque.data(),      m_radius.data(),
            m_mass.data(),        m_inv_mass.data(),
            m_inv_inertia.data(), m_nb > 0 ? m_contact_mass.data() : m_mass.data()};
  }

  static Vec3<T> get3(const std::vector<double>& v, int i) { return {T(v[3 * i]), T(v[3 * i + 1]), T(v[3 * i + 2])}; }

  BodyView<T> bodyView() {
    return {m_body_pos.data(),         m_body_vel.data(),   m_body_L.data(),      m_body_omega.data(),
            m_body_q.data(),           m_body_force.data(), m_body_torque.data(), m_body_inv_mass.data(),
            m_body_inv_inertia.data(), m_body_start.data()};
  }

  void bodyLoads() {
    BodyLoads<T> loads{bodyView(), m_index_of_host.data(), m_elem_offset.data(), m_force.data(), m_torque.data()};
    if (m_has_body_external) {
      loads.ext_force = m_body_ext_force.data();
      loads.ext_torque = m_body_ext_torque.data();
    }
    backend::parallelFor(Space{}, m_nb, loads);
  }

  // DCDEM bodies take the external load per body (3 values per body, body order), held until
  // the next call and added to the summed element loads (BodyLoads), so a load is never split
  // over elements. Its work is booked per body at each contact pass (BodyExternalWork).
  void setBodyExternalForces(const std::vector<double>& force, const std::vector<double>& torque) {
    if (force.empty() && !m_has_body_external) return;
    if (!force.empty() && (force.size() != 3 * static_cast<std::size_t>(m_nb) || torque.size() != force.size()))
      throw std::invalid_argument("DemSolver::setExternalForces: expected 3 values per body");
    std::vector<Vec3<T>>&f = m_host_vec_a, &t = m_host_vec_b;
    f.assign(m_nb, core::zero3<T>());
    t.assign(m_nb, core::zero3<T>());
    for (int k = 0; k < m_nb && !force.empty(); ++k) {
      f[k] = get3(force, k);
      t[k] = get3(torque, k);
    }
    m_body_ext_force.copyFromHost(f);
    m_body_ext_torque.copyFromHost(t);
    if (m_body_work_ext.size() != static_cast<std::size_t>(m_nb)) m_body_work_ext.resize(m_nb, 0.0);
    m_has_body_external = !force.empty();
    m_body_loads_stale = true;
  }

  void placeElements() {
    backend::parallelFor(Space{}, m_n,
                         PlaceElements<T>{bodyView(), m_body_of.data(), m_id.data(), m_elem_offset.data(), m_pos.data(),
                                          m_vel.data(), m_omega.data()});
  }

  // A checkpoint's springs: wall springs straight into the wall tables; pair springs into the
  // "old" spring table, which the first rebuild carries onto the neighbour list.
  // A checkpoint's forces replace the ones initialize() evaluated (DemHostState::force): slot
  // i holds host particle id[i]. Used once.
  void takeRestoredForces() {
    if (m_restored_force.size() != static_cast<std::size_t>(m_n)) return;
    backend::parallelFor(Space{}, m_n,
                         TakeHostOrdered<T>{m_id.data(), m_restored_force.data(), m_restored_torque.data(),
                                            m_force.data(), m_torque.data()});
    m_restored_force.resize(0);
    m_restored_torque.resize(0);
  }

  void seedHistory(const DemHostState& s) {
    const std::size_t n = s.size();
    std::vector<int> wall_key(n * kWallSlots, kNoPartner), start(n + 1, 0), partner;
    std::vector<Vec3<T>> wall_xi(n * kWallSlots, core::zero3<T>()), xi;
    std::vector<int> overflow(n, 0);
    if (s.hist_id.size() == n * kHistorySlots && s.hist_xi.size() == 3 * n * kHistorySlots) {
      for (std::size_t i = 0; i < n; ++i) {
        int walls = 0;
        for (int k = 0; k < kHistorySlots; ++k) {
          const std::size_t e = i * kHistorySlots + k;
          const std::int64_t key = s.hist_id[e];
          const Vec3<T> v{T(s.hist_xi[3 * e]), T(s.hist_xi[3 * e + 1]), T(s.hist_xi[3 * e + 2])};
          if (key == kNoPartner) continue;
          if (key < 0) {
            if (walls < kWallSlots) {
              wall_key[i * kWallSlots + walls] = static_cast<int>(-1 - key);
              wall_xi[i * kWallSlots + walls] = v;
              ++walls;
            } else {
              overflow[i] = 1;
            }
          } else {
            partner.push_back(static_cast<int>(key));
            xi.push_back(v);
          }
        }
        start[i + 1] = static_cast<int>(partner.size());
      }
    }
    m_wall_key.copyFromHost(wall_key);
    m_wall_xi.copyFromHost(wall_xi);
    m_overflow.copyFromHost(overflow);
    m_old_start.copyFromHost(start);
    m_old_list.copyFromHost(partner);
    m_old_xi.copyFromHost(xi);
    m_old_is_seed = true;
  }

  // Renumbers the particles in cell order (the order the cell sort just produced) and returns
  // the old index of each new particle (the sorted order itself).
  const int* reorderParticles() {
    const int* order = m_cells.view().order;
    gather(m_pos, order);
    gather(m_vel, order);
    gather(m_omega, order);
    gather(m_radius, order);
    gather(m_mass, order);
    gather(m_inv_mass, order);
    gather(m_inv_inertia, order);
    gather(m_dissipated, order);
    gather(m_work_in, order);
    if (m_work_external.size() == static_cast<std::size_t>(m_n)) gather(m_work_external, order);
    gather(m_id, order);
    gather(m_overflow, order);
    if (m_nb > 0) {
      gather(m_body_of, order);
      gather(m_contact_mass, order);
    }
    gatherSlots(m_wall_key, order, kWallSlots);
    gatherSlots(m_wall_xi, order, kWallSlots);
    if (m_tally.size() == static_cast<std::size_t>(m_n)) gather(m_tally, order);
    if (m_lub_dissipated.size() == static_cast<std::size_t>(m_n)) gather(m_lub_dissipated, order);
    // Keep the order, then tell the cell list its particles now are in sorted order.
    backend::parallelFor(Space{}, m_n, Copy<int>{order, m_old_of_new.data()});
    m_cells.renumberedInOrder();
    if (m_nb > 0) backend::parallelFor(Space{}, m_n, InvertIds{m_id.data(), m_index_of_host.data()});
    return m_old_of_new.data();
  }

  template <class U>
  static void copyAll(const backend::Array<Space, U>& from, backend::Array<Space, U>& to) {
    backend::parallelFor(Space{}, static_cast<int>(from.size()), Copy<U>{from.data(), to.data()});
  }

  // The renumbering's scratch: n entries of the widest per-particle type. At a rebuild the
  // slot springs (m_pair_xi) are dead from the moment the loaded ones are set aside until the
  // new list is built over them (12 B per slot, several slots per particle in a bed), so the
  // gathers borrow that buffer; a dedicated one (m_scratch) exists only while it is too small
  // (a sparse scene, the first rebuild after setState). Saves 32 B per particle (float; 88 B
  // more with collision statistics) against a scratch array of each type.
  std::size_t reorderScratchBytes() const {
    std::size_t widest = std::max(sizeof(Vec3<T>), sizeof(double));
    if (m_tally.size() == static_cast<std::size_t>(m_n)) widest = std::max(widest, sizeof(CollisionTally));
    return widest * static_cast<std::size_t>(m_n);
  }
  bool canBorrowSlotSprings() const { return m_pair_xi.bytes() >= reorderScratchBytes(); }
  template <class U>
  U* reorderScratch() {
    static_assert(alignof(U) <= alignof(double), "the scratch is double-aligned");
    if (canBorrowSlotSprings()) return reinterpret_cast<U*>(static_cast<void*>(m_pair_xi.data()));
    const std::size_t words = (reorderScratchBytes() + sizeof(double) - 1) / sizeof(double);
    if (m_scratch.size() < words) m_scratch.resize(words, 0.0);
    return reinterpret_cast<U*>(static_cast<void*>(m_scratch.data()));
  }

  template <class U>
  void gather(backend::Array<Space, U>& a, const int* order) {
    U* scratch = reorderScratch<U>();
    backend::parallelFor(Space{}, m_n, GatherRows<U>{a.data(), scratch, order, 1});
    backend::parallelFor(Space{}, m_n, Copy<U>{scratch, a.data()});
  }

  // A table of `width` entries per particle (the wall springs) renumbered column by column
  // through the n-sized scratch: 64 B per particle less than a table-sized scratch (float).
  template <class U>
  void gatherSlots(backend::Array<Space, U>& table, const int* order, int width) {
    U* scratch = reorderScratch<U>();
    for (int k = 0; k < width; ++k) {
      backend::parallelFor(Space{}, m_n, GatherSlot<U>{table.data(), scratch, order, width, k});
      backend::parallelFor(Space{}, m_n, PutSlot<U>{scratch, table.data(), width, k});
    }
  }

  // A rebuild: the loaded springs set aside (compactly, in the numbering they were made in;
  // a checkpoint's table is already that), the particles renumbered in cell order, the new
  // list built over the old one, and each new slot's spring looked up in the table.
  void rebuildNeighbours() {
    ++m_rebuilds;
    if (!m_old_is_seed) keepLoadedSprings();
    m_cells.build(m_pos.data(), m_n);
    const int* old_of_new = reorderParticles();
    if (m_nbr_start.size() != static_cast<std::size_t>(m_n) + 1) m_nbr_start.resize(m_n + 1, 0);
    if (ensemble())
      buildList(SceneTable<T>{m_scene_skin.data(), m_slabs});
    else
      buildList(T(m_setup.skin));
    const SpringTable<T> old{m_old_start.data(), m_old_list.data(), m_old_xi.data()};
    backend::parallelFor(
        Space{}, m_n, TransferPairSprings<T>{old, old_of_new, m_nbr_start.data(), m_nbr_list.data(), m_pair_xi.data()});
    m_old_is_seed = false;
    m_scatter.listChanged(m_nbr_start.data(), m_nbr_list.data());
    // The next rebuild borrows the slot springs: a dedicated scratch is no longer needed.
    if (m_scratch.size() > 0 && canBorrowSlotSprings()) m_scratch.resize(0);
  }

  // The loaded springs of the current list into the old table (m_old_start/list/xi), which
  // grows with 25% to spare like the list, so a rebuild allocates only when the bed packs
  // tighter than ever before. Before: the whole previous list and its springs were kept
  // (16 B per slot); now 16 B per loaded pair.
  // Runs only after a rebuild since setState (m_old_is_seed false), so the list and the old
  // table's starts (sized by seedHistory) exist.
  void keepLoadedSprings() {
    backend::parallelFor(Space{}, m_n, CountLoadedSprings<T>{m_nbr_start.data(), m_pair_xi.data(), m_nbr_count.data()});
    const std::size_t total = backend::exclusiveScan(Space{}, m_nbr_count.data(), m_old_start.data(), m_n);
    if (m_old_list.size() < total) {
      const std::size_t size = core::withSpare(total);
      m_old_list.resize(size, 0);
      m_old_xi.resize(size, core::zero3<T>());
    }
    backend::parallelFor(Space{}, m_n,
                         CompactLoadedSprings<T>{m_nbr_start.data(), m_nbr_list.data(), m_pair_xi.data(),
                                                 m_old_start.data(), m_old_list.data(), m_old_xi.data()});
  }

  // Has any particle moved half its skin since the list was built (throws on a diverged one)?
  bool movedPastHalfSkin(double dt_report) const {
    if (ensemble()) {  // each case against its own skin
      const T moved = backend::reduceMax<T>(
          Space{}, m_n, T(0),
          ScaledDisplacementSq<T>{m_pos.data(), m_pos_ref.data(), SceneTable<T>{m_scene_skin.data(), m_slabs}});
      if (!(moved < T(1e29))) throw divergence(T(dt_report));
      return moved > T(1);
    }
    const T half_skin = T(0.5 * m_setup.skin);
    const T moved2 = backend::reduceMax<T>(Space{}, m_n, T(0), DisplacementSq<T>{m_pos.data(), m_pos_ref.data()});
    if (!(moved2 < T(1e29))) throw divergence(T(dt_report));
    return moved2 > half_skin * half_skin;
  }

  // The half neighbour list of the current numbering: count, scan, write (the skin one value,
  // or an ensemble's per case).
  template <class Skin>
  void buildList(Skin skin) {
    BuildNeighbourList<T, Skin> build{m_cells.view(), m_pos.data(), m_radius.data(), m_pos_ref.data(),
                                      m_nbr_count.data(), nullptr, nullptr, skin, T(m_max_radius)};
    build.range_factor = T(lubricated() ? m_setup.lubrication_outer : 0.0);
    if (m_nb > 0) build.body_of = m_body_of.data();
    backend::parallelFor(Space{}, m_n, build);
    const std::size_t total = backend::exclusiveScan(Space{}, m_nbr_count.data(), m_nbr_start.data(), m_n);
    if (m_nbr_list.size() < total) {
      // Grows with room to spare, so a bed that packs a little denser does not reallocate.
      const std::size_t size = core::withSpare(total);
      m_nbr_list.resize(size, 0);
      m_pair_xi.resize(size, core::zero3<T>());
    }
    build.start = m_nbr_start.data();
    build.list = m_nbr_list.data();
    backend::parallelFor(Space{}, m_n, build);
  }

  // The particle sums, each through pick(functor): all particles (pick returns the functor) or
  // one ensemble scene's (a HostRange mask).
  template <class Pick>
  DemSums sumsOver(const Pick& pick) const {
    DemSums s;
    ParticleView<T> p = const_cast<DemSolver*>(this)->view();
    const Vec3<T> g = toVec(m_setup.gravity);
    s.kinetic = backend::reduceSum<double>(Space{}, m_n, pick(KineticEnergy<T>{p}));
    s.potential = backend::reduceSum<double>(Space{}, m_n, pick(PotentialEnergy<T>{p, g}));
    s.dissipated = backend::reduceSum<double>(Space{}, m_n, pick(ReadDouble<T>{m_dissipated.data()}));
    s.work_in = backend::reduceSum<double>(Space{}, m_n, pick(ReadDouble<T>{m_work_in.data()}));
    if (m_work_external.size() == static_cast<std::size_t>(m_n))
      s.work_external = backend::reduceSum<double>(Space{}, m_n, pick(ReadDouble<T>{m_work_external.data()}));
    s.elastic = backend::reduceSum<double>(Space{}, m_n, pick(ReadReal<T>{m_elastic.data()}));
    s.drum_torque = backend::reduceSum<double>(Space{}, m_n, pick(ReadReal<T>{m_drum_torque.data()}));
    s.max_speed = backend::reduceMax<double>(Space{}, m_n, 0.0, pick(Speed<T>{m_vel.data()}));
    s.mass = backend::reduceSum<double>(Space{}, m_n, pick(ReadReal<T>{m_mass.data()}));
    if (s.mass > 0) {
      s.com_x = backend::reduceSum<double>(Space{}, m_n, pick(MassMoment<T>{p, 0})) / s.mass;
      s.com_y = backend::reduceSum<double>(Space{}, m_n, pick(MassMoment<T>{p, 1})) / s.mass;
    }
    if (m_nbr_start.size() == static_cast<std::size_t>(m_n) + 1)
      s.pair_contacts =
          backend::reduceSum<double>(Space{}, m_n, pick(PairContactCount<T>{p, m_nbr_start.data(), m_nbr_list.data()}));
    return s;
  }

  bool ensemble() const { return m_setup.ensemble.scenes() > 0; }
  // One drum for all would give every case of an ensemble the first case's walls and law.
  void requireSingleScene() const {
    if (ensemble()) throw std::invalid_argument("DemSolver: an ensemble steps with one drum state per case");
  }

  // The ensemble's per-scene laws and slabs, checked once. The slabs must be further apart than
  // a neighbour cell, or a pair could be listed across scenes.
  void setEnsemble(const DemEnsemble& e, double cell) {
    const int k = e.scenes();
    const auto n = static_cast<std::size_t>(k);
    bool ordered = e.start[0] == 0;
    for (int q = 0; ordered && q < k; ++q) ordered = e.start[q] <= e.start[q + 1];
    if (!ordered || e.alpha.size() != n || e.friction.size() != n || !(e.pitch > cell))
      throw std::invalid_argument(
          "DemSolver: inconsistent ensemble (scene ranges, one law per scene, slab pitch "
          "longer than a neighbour cell)");
    std::vector<HertzParams<T>> params(n);
    for (std::size_t q = 0; q < n; ++q) params[q] = {m_law.k_coef, T(e.alpha[q]), T(e.friction[q])};
    m_scene_params.copyFromHost(params);
    m_slabs = SlabLayout<T>{T(e.origin), T(e.pitch), T(1.0 / e.pitch), T(e.lead), k};
    m_host_drums.assign(n, DrumWalls<T>{});
    m_scene_drums.copyFromHost(m_host_drums);
    m_host_dt.assign(n, T(0));
    m_scene_dt.copyFromHost(m_host_dt);
    std::vector<T> skin(n, T(m_setup.skin));
    if (e.skin.size() == n)
      for (std::size_t q = 0; q < n; ++q) skin[q] = T(std::min(e.skin[q], m_setup.skin));
    m_scene_skin.copyFromHost(skin);
  }

  // Every scene's drum walls for this step, through a table in the execution space's memory
  // (K x ~0.5 kB copied per step; sized once, so nothing is allocated in the step loop).
  EnsembleDrumWalls<T> ensembleWalls(const std::vector<DrumState>& drums) {
    if (!ensemble() || static_cast<int>(drums.size()) != m_slabs.count)
      throw std::invalid_argument("DemSolver: one drum state per ensemble scene expected");
    for (std::size_t q = 0; q < drums.size(); ++q) m_host_drums[q] = drumWalls(drums[q]);
    m_scene_drums.copyFromHost(m_host_drums);
    return {m_scene_drums.data(), m_slabs};
  }

  static DrumWalls<T> drumWalls(const DrumState& w) {
    if (w.lifter_count > kMaxLifters)
      throw core::InputError("drum: " + std::to_string(w.lifter_count) + " lifters, at most " +
                             std::to_string(kMaxLifters) + " are supported");
    DrumWalls<T> d{};
    d.radius = T(w.radius);
    d.z_back = T(w.z_back);
    d.v_back = T(w.v_back);
    d.omega = T(w.omega);
    d.lifter_count = w.lifter_count;
    d.lifter_height = T(w.lifter_height);
    d.lifter_width = T(w.lifter_width);
    const double spacing = 2.0 * std::acos(-1.0) / std::max(1, w.lifter_count);
    for (int k = 0; k < w.lifter_count; ++k) {
      const double a = w.phi + w.phase0 + k * spacing;
      d.lifter_cos[k] = T(std::cos(a));
      d.lifter_sin[k] = T(std::sin(a));
    }
    return d;
  }

  // One contact pass for any walls (drum, stirrer), law and pair hook: clears the sums and runs
  // ContactForces through the backend's partner sink. External loads only exist in wet runs.
  template <class Walls, class Law, class Extra = NoPairExtra<T>, class Dt = T>
  void launchContacts(const Walls& walls, Dt dt, Law law, Extra extra = Extra{}, T* fixed_wall_torque = nullptr) {
    if (!m_sums_cleared) backend::parallelFor(Space{}, m_n, ClearContactSums<T>{m_force.data(), m_torque.data()});
    m_sums_cleared = false;
    const PartnerTargets<T> targets{m_force.data(), m_torque.data(), m_dissipated.data()};
    const WallHistory<T> wall_hist{m_wall_key.data(), m_wall_xi.data(), m_overflow.data()};
    m_scatter.run(m_n, targets, [&](auto sink) {
      return ContactForces<T, Law, decltype(sink), Walls, Extra, Dt>{view(),
                                                                     m_nbr_start.data(),
                                                                     m_nbr_list.data(),
                                                                     m_pair_xi.data(),
                                                                     wall_hist,
                                                                     m_work_in.data(),
                                                                     m_elastic.data(),
                                                                     m_has_external ? m_ext_force.data() : nullptr,
                                                                     m_ext_torque.data(),
                                                                     m_id.data(),
                                                                     m_work_external.data(),
                                                                     m_drum_torque.data(),
                                                                     walls,
                                                                     law,
                                                                     T(m_setup.wall_mass_factor),
                                                                     toVec(m_setup.gravity),
                                                                     dt,
                                                                     sink,
                                                                     extra,
                                                                     fixed_wall_torque};
    });
  }

  // The drum's tangential law is a template parameter: one branch per step, none per pair.
  template <class Launch>
  void withDrumLaw(const Launch& launch) {
    if (m_setup.dualsphysics_tangential)
      launch(HertzDualSphysicsTangential<T>{m_law});
    else if (m_setup.tanh_smoothing)
      launch(HertzMindlin<T, FrictionSmoothing::kTanh>{m_law});
    else
      launch(HertzMindlin<T, FrictionSmoothing::kNone>{m_law});
  }

  void computeForces(const DrumState& walls, T dt) {
    const DrumWalls<T> drum = drumWalls(walls);
    withDrumLaw([&](auto law) { launchContacts(drum, dt, law); });
  }

  // An ensemble: every case's drum and law; dt one step for all (T: the initial forces, dt = 0)
  // or each case's own (SceneTable).
  template <class Dt>
  void computeForces(const std::vector<DrumState>& drums, Dt dt) {
    const EnsembleDrumWalls<T> walls = ensembleWalls(drums);
    withDrumLaw([&](auto law) {
      launchContacts(walls, dt, EnsembleLaw<decltype(law), HertzParams<T>, T>{m_scene_params.data(), m_slabs});
    });
  }

  bool lubricated() const { return m_setup.lubrication_viscosity > 0; }

  void allocateStirred() {
    const std::size_t n = static_cast<std::size_t>(m_n);
    if (m_setup.collision_stats && m_tally.size() != n) m_tally.resize(n, CollisionTally{});
    if (m_fixed_torque.size() != n) m_fixed_torque.resize(n, T(0));
    if (lubricated() && m_lub_dissipated.size() != n) m_lub_dissipated.resize(n, 0.0);
  }

  static StirrerWalls<T> stirrerWalls(const StirrerState& w) {
    if (w.disk_count > kMaxDisks || static_cast<int>(w.disk_z.size()) != w.disk_count)
      throw core::InputError("stirrer: " + std::to_string(w.disk_count) + " disks, at most " +
                             std::to_string(kMaxDisks) + " are supported");
    if (w.hole_count > kMaxHoles)
      throw core::InputError("stirrer: " + std::to_string(w.hole_count) + " holes per disk, at most " +
                             std::to_string(kMaxHoles) + " are supported");
    StirrerWalls<T> s{};
    s.radius = T(w.radius);
    s.length = T(w.length);
    s.shaft_radius = T(w.shaft_radius);
    s.omega = T(w.omega);
    s.disk_count = w.disk_count;
    s.disk_radius = T(w.disk_radius);
    s.disk_half_thickness = T(0.5 * w.disk_thickness);
    for (int k = 0; k < w.disk_count; ++k) s.disk_z[k] = T(w.disk_z[k]);
    s.hole_count = w.hole_count;
    s.hole_radius = T(w.hole_radius);
    s.hole_ring_radius = T(w.hole_ring_radius);
    const double spacing = 2.0 * std::acos(-1.0) / std::max(1, w.hole_count);
    for (int m = 0; m < w.hole_count; ++m) {
      s.hole_cos[m] = T(std::cos(w.phi + m * spacing));
      s.hole_sin[m] = T(std::sin(w.phi + m * spacing));
    }
    return s;
  }

  template <class Law, class Extra>
  void launchStirred(const StirrerWalls<T>& walls, T dt, Law law, Extra extra) {
    launchContacts(walls, dt, law, extra, m_fixed_torque.data());
  }

  // Lubrication and collision tallies are template parameters of the pair hook: what the case
  // does not ask for costs nothing per pair (dry without statistics: the drum's plain loop).
  template <class Law>
  void launchStirredLaw(const StirrerWalls<T>& walls, T dt, Law law) {
    const JeffreyOnishi<T> lub{m_lub};
    if (lubricated() && m_setup.collision_stats)
      launchStirred(walls, dt, law, StirredPairExtra<T, true, true>{lub, m_tally.data(), m_lub_dissipated.data(), dt});
    else if (lubricated())
      launchStirred(walls, dt, law, StirredPairExtra<T, true, false>{lub, nullptr, m_lub_dissipated.data(), dt});
    else if (m_setup.collision_stats)
      launchStirred(walls, dt, law, StirredPairExtra<T, false, true>{lub, m_tally.data(), nullptr, dt});
    else
      launchStirred(walls, dt, law, NoPairExtra<T>{});
  }

  void computeForces(const StirrerState& state, T dt) {
    allocateStirred();
    const StirrerWalls<T> walls = stirrerWalls(state);
    if (m_setup.linear_law)
      launchStirredLaw(walls, dt, LinearSpringDashpot<T>{m_linear});
    else
      launchStirredLaw(walls, dt, HertzMindlin<T, FrictionSmoothing::kNone>{m_law});
  }

  DemSetup m_setup;
  LinearSpringParams<T> m_linear;
  LubricationParams<T> m_lub;
  backend::Array<Space, CollisionTally> m_tally;
  backend::Array<Space, double> m_lub_dissipated;
  backend::Array<Space, T> m_fixed_torque;
  HertzParams<T> m_law;
  // Ensemble (DemSetup::ensemble): per-scene contact parameters and drums, and the slabs.
  backend::Array<Space, HertzParams<T>> m_scene_params;
  backend::Array<Space, DrumWalls<T>> m_scene_drums;
  std::vector<DrumWalls<T>> m_host_drums;
  backend::Array<Space, T> m_scene_dt;    // each case's step; 0: the case has ended
  backend::Array<Space, T> m_scene_skin;  // each case's neighbour skin (at most the setup's, which sizes the cells)
  std::vector<T> m_host_dt;
  SlabLayout<T> m_slabs{};
  int m_n = 0;
  // The neighbour search's reach to the largest partner: the setup's (it sizes the cells) or a
  // larger radius in the state.
  double m_max_radius = 0;
  std::int64_t m_rebuilds = 0;
  std::int64_t m_steps = 0;     // steps since setState (for error messages)
  bool m_sums_cleared = false;  // KickDrift cleared the force sums since the last contact pass
  neighbors::CellList<Space, T> m_cells;
  PartnerScatter<Space, T> m_scatter;
  backend::Array<Space, Vec3<T>> m_pos, m_vel, m_omega, m_force, m_torque, m_pos_ref;
  backend::Array<Space, T> m_radius, m_mass, m_inv_mass, m_inv_inertia, m_elastic, m_drum_torque;
  backend::Array<Space, int> m_id, m_overflow;
  // Half neighbour list, compact: partners of i at m_nbr_list[m_nbr_start[i] .. m_nbr_start[i + 1]).
  backend::Array<Space, int> m_nbr_count, m_nbr_start, m_nbr_list;
  backend::Array<Space, double> m_dissipated, m_work_in, m_work_external;
  // Loads from outside (the fluid), by host number; only in coupled runs.
  backend::Array<Space, Vec3<T>> m_restored_force, m_restored_torque;  // host order, until initialize()
  bool m_has_external = false;
  backend::Array<Space, Vec3<T>> m_ext_force, m_ext_torque, m_ext_force_old, m_ext_torque_old;
  // Springs: one per half-list slot for pairs, kWallSlots per particle for walls.
  backend::Array<Space, Vec3<T>> m_pair_xi, m_wall_xi;
  backend::Array<Space, int> m_wall_key;
  // The loaded springs of the list before the last rebuild (or a checkpoint's table), read once
  // when the springs move to the new list (keepLoadedSprings).
  backend::Array<Space, int> m_old_start, m_old_list;
  backend::Array<Space, Vec3<T>> m_old_xi;
  bool m_old_is_seed = false;
  // Renumbering: the old index of each new particle, and the scratch used when the dead
  // springs cannot be borrowed (reorderScratch).
  backend::Array<Space, int> m_old_of_new;
  backend::Array<Space, double> m_scratch;
  // DCDEM rigid bodies (setBodies); none in a plain sphere run, and then no arrays.
  int m_nb = 0;
  backend::Array<Space, Vec3<T>> m_body_pos, m_body_vel, m_body_L, m_body_omega, m_body_force, m_body_torque;
  backend::Array<Space, Quat<T>> m_body_q;
  backend::Array<Space, Sym3<T>> m_body_inv_inertia;
  backend::Array<Space, T> m_body_inv_mass;
  backend::Array<Space, int> m_body_start;       // host numbers of body b's elements: [start[b], start[b + 1])
  backend::Array<Space, Vec3<T>> m_elem_offset;  // body frame, by host number
  backend::Array<Space, int> m_index_of_host;    // current index of each host number
  backend::Array<Space, int> m_body_of;          // body of each particle (current index), -1: sphere
  backend::Array<Space, T> m_contact_mass;       // body mass for elements, own mass for spheres
  std::vector<double> m_body_radius, m_body_mass_host, m_body_inertia_host;  // as given to setBodies
  // Loads from outside (the fluid) per body, and their work; only in coupled runs.
  bool m_has_body_external = false;
  bool m_body_loads_stale = false;  // a new external load since the last bodyLoads()
  backend::Array<Space, Vec3<T>> m_body_ext_force, m_body_ext_torque;
  backend::Array<Space, double> m_body_work_ext;
  // Host buffers of the per-step exchange with a coupling (setExternalForces, ballKinematics),
  // sized once and reused.
  mutable std::vector<Vec3<T>> m_host_vec_a, m_host_vec_b, m_host_vec_c;
  mutable std::vector<int> m_host_id;
};

}  // namespace millsim::dem
