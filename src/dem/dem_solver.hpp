#pragma once
// DemSolver<Space, T>: owns the DEM arrays in the execution space's memory and runs the step
// functors of dem_kernels.hpp through the backend. Written once; instantiated for OpenMP in
// dem_solver_omp.cpp and for CUDA in backend/cuda/dem_solver_cuda.cu.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dem/dem_engine.hpp"
#include "dem/dem_kernels.hpp"
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

template <class T>
struct ReadInt {
  const int* v;
  MILLSIM_HD int operator()(int i) const { return v[i]; }
};

template <class Space, class T>
class DemSolver final : public DemEngine {
 public:
  explicit DemSolver(const DemSetup& setup) : m_setup(setup) {
    m_law.k_coef = T(setup.k_coef);
    m_law.alpha = T(setup.alpha);
    m_law.friction = T(setup.friction);
    const T cell = T(2 * setup.max_radius + setup.skin);
    m_cells.setGrid(neighbors::makeGrid<T>(toVec(setup.domain_lo), toVec(setup.domain_hi), cell, false));
  }

  const char* backendName() const override { return Space::kName; }
  const char* precisionName() const override { return sizeof(T) == 4 ? "float" : "double"; }

  void setState(const DemHostState& s) override {
    m_n = static_cast<int>(s.size());
    const std::size_t n = s.size();
    std::vector<Vec3<T>> pos(n), vel(n), omega(n);
    std::vector<T> radius(n), mass(n), inv_mass(n), inv_inertia(n);
    for (std::size_t i = 0; i < n; ++i) {
      pos[i] = {T(s.pos[3 * i]), T(s.pos[3 * i + 1]), T(s.pos[3 * i + 2])};
      vel[i] = {T(s.vel[3 * i]), T(s.vel[3 * i + 1]), T(s.vel[3 * i + 2])};
      omega[i] = {T(s.omega[3 * i]), T(s.omega[3 * i + 1]), T(s.omega[3 * i + 2])};
      radius[i] = T(s.radius[i]);
      mass[i] = T(s.mass[i]);
      inv_mass[i] = T(1.0 / s.mass[i]);
      inv_inertia[i] = s.inertia[i] > 0 ? T(1.0 / s.inertia[i]) : T(0);
    }
    m_pos.copyFromHost(pos);
    m_vel.copyFromHost(vel);
    m_omega.copyFromHost(omega);
    m_radius.copyFromHost(radius);
    m_mass.copyFromHost(mass);
    m_inv_mass.copyFromHost(inv_mass);
    m_inv_inertia.copyFromHost(inv_inertia);
    m_force.resize(n, core::zero3<T>());
    m_torque.resize(n, core::zero3<T>());
    m_pos_ref.resize(n, core::zero3<T>());
    std::vector<int> hid(n * kHistorySlots, kNoPartner);
    std::vector<Vec3<T>> hxi(n * kHistorySlots, core::zero3<T>());
    if (s.hist_id.size() == hid.size() && s.hist_xi.size() == 3 * hxi.size()) {
      for (std::size_t k = 0; k < hid.size(); ++k) {
        hid[k] = static_cast<int>(s.hist_id[k]);
        hxi[k] = {T(s.hist_xi[3 * k]), T(s.hist_xi[3 * k + 1]), T(s.hist_xi[3 * k + 2])};
      }
    }
    m_hist_id.copyFromHost(hid);
    m_hist_xi.copyFromHost(hxi);
    m_dissipated.copyFromHost(s.dissipated.size() == n ? s.dissipated : std::vector<double>(n, 0.0));
    m_work_in.copyFromHost(s.work_in.size() == n ? s.work_in : std::vector<double>(n, 0.0));
    m_elastic.resize(n, T(0));
    m_drum_torque.resize(n, T(0));
    m_overflow.resize(n, 0);
    m_nbr_count.resize(n, 0);
    resizePairArrays();
  }

  void getState(DemHostState& s) const override {
    std::vector<Vec3<T>> pos, vel, omega, hxi;
    std::vector<T> radius, mass, inv_inertia;
    std::vector<int> hid;
    m_pos.copyToHost(pos);
    m_vel.copyToHost(vel);
    m_omega.copyToHost(omega);
    m_radius.copyToHost(radius);
    m_mass.copyToHost(mass);
    m_inv_inertia.copyToHost(inv_inertia);
    m_hist_id.copyToHost(hid);
    m_hist_xi.copyToHost(hxi);
    m_dissipated.copyToHost(s.dissipated);
    m_work_in.copyToHost(s.work_in);
    const std::size_t n = pos.size();
    s.pos.resize(3 * n);
    s.vel.resize(3 * n);
    s.omega.resize(3 * n);
    s.radius.resize(n);
    s.mass.resize(n);
    s.inertia.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      put3(s.pos, i, pos[i]);
      put3(s.vel, i, vel[i]);
      put3(s.omega, i, omega[i]);
      s.radius[i] = double(radius[i]);
      s.mass[i] = double(mass[i]);
      s.inertia[i] = inv_inertia[i] > T(0) ? 1.0 / double(inv_inertia[i]) : 0.0;
    }
    s.hist_id.assign(hid.begin(), hid.end());
    s.hist_xi.resize(3 * hxi.size());
    for (std::size_t k = 0; k < hxi.size(); ++k) put3(s.hist_xi, k, hxi[k]);
  }

  void initialize(const DrumState& walls) override {
    rebuildNeighbours();
    computeForces(walls, T(0));
  }

  void step(const DrumState& walls, double dt_in) override {
    const T dt = T(dt_in);
    backend::parallelFor(Space{}, m_n, KickDrift<T>{view(), dt});
    const T half_skin = T(0.5 * m_setup.skin);
    const T moved2 = backend::reduceMax<T>(Space{}, m_n, T(0), DisplacementSq<T>{m_pos.data(), m_pos_ref.data()});
    if (!(moved2 < T(1e29))) throw core::SimulationError("DEM: non-finite particle position (NaN or Inf): the step diverged");
    if (moved2 > half_skin * half_skin) rebuildNeighbours();
    computeForces(walls, dt);
    backend::parallelFor(Space{}, m_n, Kick<T>{view(), dt});
  }

  DemSums sums() const override {
    DemSums s;
    ParticleView<T> p = const_cast<DemSolver*>(this)->view();
    const Vec3<T> g = toVec(m_setup.gravity);
    s.kinetic = backend::reduceSum<double>(Space{}, m_n, KineticEnergy<T>{p});
    s.potential = backend::reduceSum<double>(Space{}, m_n, PotentialEnergy<T>{p, g});
    s.dissipated = backend::reduceSum<double>(Space{}, m_n, ReadDouble<T>{m_dissipated.data()});
    s.work_in = backend::reduceSum<double>(Space{}, m_n, ReadDouble<T>{m_work_in.data()});
    s.elastic = backend::reduceSum<double>(Space{}, m_n, ReadReal<T>{m_elastic.data()});
    s.drum_torque = backend::reduceSum<double>(Space{}, m_n, ReadReal<T>{m_drum_torque.data()});
    s.max_speed = backend::reduceMax<double>(Space{}, m_n, 0.0, Speed<T>{m_vel.data()});
    s.mass = backend::reduceSum<double>(Space{}, m_n, ReadReal<T>{m_mass.data()});
    if (s.mass > 0) {
      s.com_x = backend::reduceSum<double>(Space{}, m_n, MassMoment<T>{p, 0}) / s.mass;
      s.com_y = backend::reduceSum<double>(Space{}, m_n, MassMoment<T>{p, 1}) / s.mass;
    }
    return s;
  }

  std::map<std::string, std::size_t> memoryBytes() const override {
    return {{"dem.particles", m_pos.bytes() + m_vel.bytes() + m_omega.bytes() + m_force.bytes() + m_torque.bytes() +
                                  m_radius.bytes() + m_mass.bytes() + m_inv_mass.bytes() + m_inv_inertia.bytes()},
            {"dem.contact_history", m_hist_id.bytes() + m_hist_xi.bytes() + m_overflow.bytes()},
            {"dem.energy_accounting", m_dissipated.bytes() + m_work_in.bytes() + m_elastic.bytes() + m_drum_torque.bytes()},
            {"dem.pair_buffer", m_pair_force.bytes() + m_pair_nxft.bytes() + m_pair_delta.bytes() + m_pair_diss.bytes() +
                                    m_pair_elastic.bytes()},
            {"neighbors", m_cells.bytes() + m_nbr_count.bytes() + m_nbr_list.bytes() + m_mirror.bytes() + m_pos_ref.bytes()}};
  }

  std::int64_t neighbourRebuilds() const override { return m_rebuilds; }

 private:
  static Vec3<T> toVec(const std::array<double, 3>& a) { return {T(a[0]), T(a[1]), T(a[2])}; }
  static void put3(std::vector<double>& v, std::size_t i, Vec3<T> a) {
    v[3 * i] = double(a.x);
    v[3 * i + 1] = double(a.y);
    v[3 * i + 2] = double(a.z);
  }

  ParticleView<T> view() {
    return {m_pos.data(),    m_vel.data(),  m_omega.data(),    m_force.data(),      m_torque.data(),
            m_radius.data(), m_mass.data(), m_inv_mass.data(), m_inv_inertia.data()};
  }

  void rebuildNeighbours() {
    ++m_rebuilds;
    m_cells.build(m_pos.data(), m_n);
    for (;;) {
      backend::parallelFor(Space{}, m_n,
                           BuildNeighbourList<T>{m_cells.view(), m_pos.data(), m_radius.data(), m_pos_ref.data(),
                                                 m_nbr_count.data(), m_nbr_list.data(), m_nbr_capacity, T(m_setup.skin)});
      const int most = backend::reduceMax<int>(Space{}, m_n, 0, ReadInt<T>{m_nbr_count.data()});
      if (most <= m_nbr_capacity) break;
      // Rare (a dense clump of small balls around a large one): grow outside the step loop's
      // steady state and rebuild.
      m_nbr_capacity = most + 8;
      resizePairArrays();
    }
    backend::parallelFor(Space{}, m_n, BuildMirrorIndex{m_nbr_count.data(), m_nbr_list.data(), m_mirror.data(), m_nbr_capacity});
  }

  void resizePairArrays() {
    const std::size_t slots = static_cast<std::size_t>(m_n) * m_nbr_capacity;
    m_nbr_list.resize(slots, 0);
    m_mirror.resize(slots, -1);
    m_pair_force.resize(slots, core::zero3<T>());
    m_pair_nxft.resize(slots, core::zero3<T>());
    m_pair_delta.resize(slots, T(0));
    m_pair_diss.resize(slots, T(0));
    m_pair_elastic.resize(slots, T(0));
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

  template <class Law>
  void launchForces(const DrumState& walls, T dt, Law law) {
    ContactOutputs<T> out{m_hist_id.data(), m_hist_xi.data(), m_dissipated.data(), m_work_in.data(),
                          m_elastic.data(), m_drum_torque.data(), m_overflow.data()};
    PairBuffer<T> pairs{m_pair_force.data(), m_pair_nxft.data(), m_pair_delta.data(), m_pair_diss.data(),
                        m_pair_elastic.data()};
    backend::parallelFor(Space{}, m_n,
                         OwnedContactForces<T, Law>{view(), m_nbr_count.data(), m_nbr_list.data(), m_nbr_capacity, out,
                                                    pairs, drumWalls(walls), law, T(m_setup.wall_mass_factor),
                                                    toVec(m_setup.gravity), dt});
    backend::parallelFor(Space{}, m_n,
                         GatherPartnerForces<T>{view(), m_nbr_count.data(), m_nbr_list.data(), m_mirror.data(),
                                                m_nbr_capacity, out, pairs, dt});
  }

  void computeForces(const DrumState& walls, T dt) {
    // The smoothing choice is a template parameter: one branch per step, none per pair.
    if (m_setup.tanh_smoothing)
      launchForces(walls, dt, HertzMindlin<T, FrictionSmoothing::kTanh>{m_law});
    else
      launchForces(walls, dt, HertzMindlin<T, FrictionSmoothing::kNone>{m_law});
  }

  DemSetup m_setup;
  HertzParams<T> m_law;
  int m_n = 0;
  int m_nbr_capacity = 32;
  std::int64_t m_rebuilds = 0;
  neighbors::CellList<Space, T> m_cells;
  backend::Array<Space, Vec3<T>> m_pos, m_vel, m_omega, m_force, m_torque, m_pos_ref, m_hist_xi;
  backend::Array<Space, T> m_radius, m_mass, m_inv_mass, m_inv_inertia, m_elastic, m_drum_torque;
  backend::Array<Space, int> m_hist_id, m_overflow, m_nbr_count, m_nbr_list, m_mirror;
  // One entry per neighbour-list slot: the result of a pair, written by its owner (lower index).
  backend::Array<Space, Vec3<T>> m_pair_force, m_pair_nxft;
  backend::Array<Space, T> m_pair_delta, m_pair_diss, m_pair_elastic;
  backend::Array<Space, double> m_dissipated, m_work_in;
};

}  // namespace millsim::dem
