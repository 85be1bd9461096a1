#pragma once
// The DEM step as MILLSIM_HD functors over particle indices, run by backend::parallelFor on
// OpenMP or CUDA: the same code on both. Each pair is evaluated once, by its lower-index particle
// from the half neighbour list (partners j > i); the reaction on j goes through a sink
// (partner_scatter.hpp) that the backend chooses. Particles are renumbered in cell order at each
// neighbour rebuild (reorder_kernels.hpp) so a pair's two sides lie close in memory.
#include "dem/contact/hertz.hpp"
#include "dem/walls/drum_walls.hpp"
#include "millsim/core/vec3.hpp"
#include "millsim/neighbors/cell_grid.hpp"

namespace millsim::dem {

using core::Vec3;

// Contact history in a DemHostState (checkpoints): per particle, kHistorySlots entries of partner
// key (a higher-numbered particle, or -1 - wall id) and tangential spring, as the lower-numbered
// side of the pair sees it. In the solver, pair springs live with the half neighbour list (one
// per slot) and wall springs in a small per-particle table of kWallSlots.
inline constexpr int kHistorySlots = 16;
inline constexpr int kWallSlots = 4;  // cylinder + end plate + lifter face + lifter top at once
inline constexpr int kNoPartner = -2147483647 - 1;

MILLSIM_HD inline int wallKey(int wall) { return -1 - wall; }

template <class T>
struct ParticleView {
  Vec3<T>* pos;
  Vec3<T>* vel;
  Vec3<T>* omega;
  Vec3<T>* force;
  Vec3<T>* torque;
  const T* radius;
  const T* mass;
  const T* inv_mass;
  const T* inv_inertia;
};

// Half-kick of velocity Verlet: v += dt/2 a, w += dt/2 alpha.
template <class T>
struct Kick {
  ParticleView<T> p;
  T dt;
  MILLSIM_HD void operator()(int i) const {
    const T h = T(0.5) * dt;
    p.vel[i] += (h * p.inv_mass[i]) * p.force[i];
    p.omega[i] += (h * p.inv_inertia[i]) * p.torque[i];
  }
};

// First half-kick and drift: v += dt/2 a(t), x += dt v.
template <class T>
struct KickDrift {
  ParticleView<T> p;
  T dt;
  MILLSIM_HD void operator()(int i) const {
    Kick<T>{p, dt}(i);
    p.pos[i] += dt * p.vel[i];
  }
};

// Squared displacement since the neighbour list was built, or +inf for a non-finite position
// (so one reduction both triggers rebuilds and detects NaN).
template <class T>
struct DisplacementSq {
  const Vec3<T>* pos;
  const Vec3<T>* ref;
  MILLSIM_HD T operator()(int i) const {
    const Vec3<T> d = pos[i] - ref[i];
    const T d2 = core::norm2(d);
    return d2 == d2 ? d2 : T(1e30);
  }
};

// Half Verlet neighbour list from the cell list, stored compact (CSR): j > i is listed when the
// gap is below `skin`. Run twice per rebuild: with list == nullptr it only counts (count[i]),
// then, with start[] the exclusive scan of the counts, it writes list[start[i] ..]. Compact rows
// keep the per-slot springs contiguous, so the force pass streams them (a fixed-capacity row
// per particle left most of each row empty and made the spring loads miss the cache).
template <class T>
struct BuildNeighbourList {
  neighbors::CellListView<T> cells;
  const Vec3<T>* pos;
  const T* radius;
  Vec3<T>* pos_ref;
  int* count;        // pass 1 output
  const int* start;  // pass 2 input
  int* list;         // pass 2 output (nullptr in pass 1)
  T skin;
  MILLSIM_HD void operator()(int i) const {
    const Vec3<T> xi = pos[i];
    const T ri = radius[i];
    int c = 0;
    const int base = list ? start[i] : 0;
    cells.forEachCandidate(xi, [&](int j) {
      if (j <= i) return;
      const T reach = ri + radius[j] + skin;
      if (core::norm2(xi - pos[j]) < reach * reach) {
        if (list) list[base + c] = j;
        ++c;
      }
    });
    if (!list) count[i] = c;
    pos_ref[i] = xi;
  }
};

// Tangential springs of the wall contacts: kWallSlots per particle, keyed by wall id, used slots
// first (kNoPartner after them).
template <class T>
struct WallHistory {
  int* key;
  Vec3<T>* xi;
  int* overflow;  // set when a particle touches more than kWallSlots walls at once
};

// The force pass, per particle i: gravity, the drum walls and every pair (i, j > i) of the half
// list, each evaluated once with the contact law. The force on i is summed in registers; the
// reaction on j (and half the pair's dissipation) goes to the sink. The pair's elastic energy is
// booked to i alone: only its total is used, and one scattered add less per pair is measurable.
template <class T, class Law, class Sink>
struct ContactForces {
  ParticleView<T> p;
  const int* nbr_start;  // particle i's partners: nbr_list[nbr_start[i] .. nbr_start[i + 1])
  const int* nbr_list;
  Vec3<T>* pair_xi;  // one tangential spring per neighbour-list slot
  WallHistory<T> wall_hist;
  double* work_in;  // accumulated work done by the walls on the particle, J
  T* elastic_out;   // elastic energy of the contacts i owns (pairs it evaluates, walls), J
  // External force and torque per host number (nullptr: none) and the work they do, J.
  const Vec3<T>* ext_force;
  const Vec3<T>* ext_torque;
  const int* id;
  double* work_external;
  T* drum_torque;   // torque of this particle's wall contacts on the drum about +z, N m
  DrumWalls<T> walls;
  Law law;
  T wall_mass_factor;
  Vec3<T> gravity;
  T dt;
  Sink sink;

  MILLSIM_HD void operator()(int i) const {
    const Vec3<T> xi_pos = p.pos[i], vi = p.vel[i], wi = p.omega[i];
    const T ri = p.radius[i], mi = p.mass[i];
    Vec3<T> f = mi * gravity;
    Vec3<T> tq = core::zero3<T>();
    T diss_rate = T(0), elastic = T(0), drum_tq = T(0), power_in = T(0);

    const int end = nbr_start[i + 1];
    for (int slot = nbr_start[i]; slot < end; ++slot) {
      const int j = nbr_list[slot];
      const Vec3<T> d = xi_pos - p.pos[j];
      const T rj = p.radius[j];
      const T reach = ri + rj;
      const T dist2 = core::norm2(d);
      if (dist2 >= reach * reach || dist2 <= T(0)) {
        pair_xi[slot] = core::zero3<T>();  // apart: the spring is released
        continue;
      }
      const T dist = std::sqrt(dist2);
      const Vec3<T> n = (T(1) / dist) * d;
      const T delta = reach - dist;
      const T ai = ri - T(0.5) * delta, aj = rj - T(0.5) * delta;
      const Vec3<T> v_rel = (vi + core::cross(wi, (-ai) * n)) - (p.vel[j] + core::cross(p.omega[j], aj * n));
      Vec3<T> s = pair_xi[slot];
      const T mj = p.mass[j];
      const ContactResult<T> c = law(n, delta, ri * rj / reach, mi * mj / (mi + mj), v_rel, s, dt);
      pair_xi[slot] = s;
      const Vec3<T> nxft = core::cross(n, c.force_t);
      f += c.force;
      tq -= ai * nxft;
      diss_rate += T(0.5) * c.dissipation_rate;
      elastic += c.elastic_energy;
      // On j: -F, and the torque -aj (n_j x F_t,j) with n_j = -n, F_t,j = -F_t.
      sink.addPartner(j, -c.force, -(aj * nxft), T(0.5) * c.dissipation_rate * dt);
    }

    int old_key[kWallSlots];
    Vec3<T> old_xi[kWallSlots];
    int n_old = 0;
    while (n_old < kWallSlots && wall_hist.key[i * kWallSlots + n_old] != kNoPartner) {
      old_key[n_old] = wall_hist.key[i * kWallSlots + n_old];
      old_xi[n_old] = wall_hist.xi[i * kWallSlots + n_old];
      ++n_old;
    }
    int n_new = 0;
    walls.forEachContact(xi_pos, ri, [&](const WallContact<T>& w) {
      const T ai = ri - w.delta;
      const Vec3<T> v_rel = vi + core::cross(wi, (-ai) * w.n) - w.velocity;
      Vec3<T> s = core::zero3<T>();
      for (int q = 0; q < n_old; ++q)
        if (old_key[q] == w.wall) s = old_xi[q];
      const ContactResult<T> c = law(w.n, w.delta, ri, wall_mass_factor * mi, v_rel, s, dt);
      if (n_new < kWallSlots) {
        wall_hist.key[i * kWallSlots + n_new] = w.wall;
        wall_hist.xi[i * kWallSlots + n_new] = s;
        ++n_new;
      } else {
        wall_hist.overflow[i] = 1;
      }
      f += c.force;
      tq += core::cross((-ai) * w.n, c.force_t);
      diss_rate += c.dissipation_rate;
      elastic += c.elastic_energy;
      // Reaction on the drum: -F at the contact point; its z-moment drives the shaft torque.
      drum_tq -= w.point.x * c.force.y - w.point.y * c.force.x;
      power_in += core::dot(c.force, w.velocity);
    });
    for (int q = n_new; q < n_old; ++q) wall_hist.key[i * kWallSlots + q] = kNoPartner;

    if (ext_force) {
      const Vec3<T> fe = ext_force[id[i]], te = ext_torque[id[i]];
      f += fe;
      tq += te;
      // Power of the external load at this instant (v, omega at the force evaluation).
      work_external[i] += double(core::dot(fe, vi) + core::dot(te, wi)) * double(dt);
    }
    sink.addOwn(i, f, tq, diss_rate * dt);
    elastic_out[i] = elastic;
    work_in[i] += double(power_in) * double(dt);
    drum_torque[i] = drum_tq;
  }
};

// Clears the sums the force pass accumulates into.
template <class T>
struct ClearContactSums {
  Vec3<T>* force;
  Vec3<T>* torque;
  MILLSIM_HD void operator()(int i) const {
    force[i] = core::zero3<T>();
    torque[i] = core::zero3<T>();
  }
};

}  // namespace millsim::dem
