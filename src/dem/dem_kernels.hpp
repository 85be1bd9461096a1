#pragma once
// The DEM step as MILLSIM_HD functors over particle indices, run by backend::parallelFor on
// OpenMP or CUDA: the same code on both. Each pair is evaluated once, by its lower-index particle
// (pass 1, which also does the walls), and its partner gathers the result from a per-slot pair
// buffer (pass 2): no atomics, and results do not depend on the thread schedule.
#include "dem/contact/hertz.hpp"
#include "dem/walls/drum_walls.hpp"
#include "millsim/core/vec3.hpp"
#include "millsim/neighbors/cell_grid.hpp"

namespace millsim::dem {

using core::Vec3;

// Contact history slots per particle: partner key (particle index >= 0, wall -1 - id) and the
// tangential spring. A particle in a dense bed has ~12 contacts; 16 leaves room.
inline constexpr int kHistorySlots = 16;
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

// Verlet neighbour list from the cell list: j is listed when the gap is below `skin`.
template <class T>
struct BuildNeighbourList {
  neighbors::CellListView<T> cells;
  const Vec3<T>* pos;
  const T* radius;
  Vec3<T>* pos_ref;
  int* count;
  int* list;
  int capacity;
  T skin;
  MILLSIM_HD void operator()(int i) const {
    const Vec3<T> xi = pos[i];
    const T ri = radius[i];
    int c = 0;
    cells.forEachCandidate(xi, [&](int j) {
      if (j == i) return;
      const T reach = ri + radius[j] + skin;
      if (core::norm2(xi - pos[j]) < reach * reach) {
        if (c < capacity) list[i * capacity + c] = j;
        ++c;
      }
    });
    count[i] = c;  // may exceed capacity: the host checks and grows the list
    pos_ref[i] = xi;
  }
};

// For each neighbour-list slot (i, k) with partner j < i: the slot m at which i appears in j's
// list. The pair is evaluated once, by its owner min(i, j); the other side reads the result there.
struct BuildMirrorIndex {
  const int* count;
  const int* list;
  int* mirror;
  int capacity;
  MILLSIM_HD void operator()(int i) const {
    const int nc = count[i] < capacity ? count[i] : capacity;
    for (int k = 0; k < nc; ++k) {
      const int j = list[i * capacity + k];
      int m = -1;
      if (j < i) {
        const int nj = count[j] < capacity ? count[j] : capacity;
        for (int s = 0; s < nj && m < 0; ++s)
          if (list[j * capacity + s] == i) m = s;
      }
      mirror[i * capacity + k] = m;
    }
  }
};

template <class T>
struct ContactOutputs {
  int* hist_id;
  Vec3<T>* hist_xi;
  double* dissipated;   // accumulated J per particle
  double* work_in;      // accumulated work done by the walls on the particle, J
  T* elastic;           // current normal elastic energy attributed to the particle, J
  T* drum_torque;       // torque of this particle's wall contacts on the drum about +z, N m
  int* history_overflow;
};

// One entry per neighbour-list slot, written by the pair's owner (the lower index) and read by
// the partner: the force on the owner, n x F_t (both torques are -a (n x F_t) with each side's
// lever a = r - delta/2), the overlap (0: no contact) and the pair's dissipation rate and elastic
// energy (booked half to each side).
template <class T>
struct PairBuffer {
  Vec3<T>* force;
  Vec3<T>* n_cross_ft;
  T* delta;
  T* dissipation_rate;
  T* elastic;
};

// Pass 1 of the forces, per particle i: gravity, the drum walls, and every pair i owns (partner
// j > i), evaluated once with the contact law; the result also goes to the pair buffer for j.
// Contact history lives with the owner only, keyed by partner (j, or -1 - wall id).
template <class T, class Law>
struct OwnedContactForces {
  ParticleView<T> p;
  const int* nbr_count;
  const int* nbr_list;
  int nbr_capacity;
  ContactOutputs<T> out;
  PairBuffer<T> pairs;
  DrumWalls<T> walls;
  Law law;
  T wall_mass_factor;
  Vec3<T> gravity;
  T dt;

  MILLSIM_HD void operator()(int i) const {
    int old_id[kHistorySlots];
    Vec3<T> old_xi[kHistorySlots];
    int new_id[kHistorySlots];
    Vec3<T> new_xi[kHistorySlots];
    // The table is kept compact (used slots first, then kNoPartner), so only the used slots
    // are read and written: a ball owns ~2-4 contacts, not 16.
    int n_old = 0;
    while (n_old < kHistorySlots && out.hist_id[i * kHistorySlots + n_old] != kNoPartner) {
      old_id[n_old] = out.hist_id[i * kHistorySlots + n_old];
      old_xi[n_old] = out.hist_xi[i * kHistorySlots + n_old];
      ++n_old;
    }
    int n_new = 0;
    bool overflow = false;
    auto spring = [&](int key) {
      for (int s = 0; s < n_old; ++s)
        if (old_id[s] == key) return old_xi[s];
      return core::zero3<T>();
    };
    auto keep = [&](int key, Vec3<T> xi) {
      if (n_new < kHistorySlots) {
        new_id[n_new] = key;
        new_xi[n_new] = xi;
        ++n_new;
      } else {
        overflow = true;
      }
    };

    const Vec3<T> xi_pos = p.pos[i], vi = p.vel[i], wi = p.omega[i];
    const T ri = p.radius[i], mi = p.mass[i];
    Vec3<T> f = mi * gravity;
    Vec3<T> tq = core::zero3<T>();
    T diss_rate = T(0), elastic = T(0), drum_tq = T(0), power_in = T(0);

    const int nc = nbr_count[i] < nbr_capacity ? nbr_count[i] : nbr_capacity;
    for (int k = 0; k < nc; ++k) {
      const int slot = i * nbr_capacity + k;
      const int j = nbr_list[slot];
      if (j < i) continue;  // owned by j
      pairs.delta[slot] = T(0);
      const Vec3<T> d = xi_pos - p.pos[j];
      const T rj = p.radius[j];
      const T reach = ri + rj;
      const T dist2 = core::norm2(d);
      if (dist2 >= reach * reach || dist2 <= T(0)) continue;
      const T dist = std::sqrt(dist2);
      const Vec3<T> n = (T(1) / dist) * d;
      const T delta = reach - dist;
      const T ai = ri - T(0.5) * delta, aj = rj - T(0.5) * delta;
      const Vec3<T> v_rel = (vi + core::cross(wi, (-ai) * n)) - (p.vel[j] + core::cross(p.omega[j], aj * n));
      const T r_star = ri * rj / reach;
      const T mj = p.mass[j];
      const T m_star = mi * mj / (mi + mj);
      Vec3<T> s = spring(j);
      const ContactResult<T> c = law(n, delta, r_star, m_star, v_rel, s, dt);
      keep(j, s);
      const Vec3<T> nxft = core::cross(n, c.force_t);
      f += c.force;
      tq -= ai * nxft;
      diss_rate += T(0.5) * c.dissipation_rate;  // the partner books the other half
      elastic += T(0.5) * c.elastic_energy;
      pairs.force[slot] = c.force;
      pairs.n_cross_ft[slot] = nxft;
      pairs.delta[slot] = delta;
      pairs.dissipation_rate[slot] = c.dissipation_rate;
      pairs.elastic[slot] = c.elastic_energy;
    }

    walls.forEachContact(xi_pos, ri, [&](const WallContact<T>& w) {
      const T ai = ri - w.delta;
      const Vec3<T> v_rel = vi + core::cross(wi, (-ai) * w.n) - w.velocity;
      const int key = wallKey(w.wall);
      Vec3<T> s = spring(key);
      const ContactResult<T> c = law(w.n, w.delta, ri, wall_mass_factor * mi, v_rel, s, dt);
      keep(key, s);
      f += c.force;
      tq += core::cross((-ai) * w.n, c.force_t);
      diss_rate += c.dissipation_rate;
      elastic += c.elastic_energy;
      // Reaction on the drum: -F at the contact point; its z-moment drives the shaft torque.
      drum_tq -= w.point.x * c.force.y - w.point.y * c.force.x;
      power_in += core::dot(c.force, w.velocity);
    });

    const int n_write = n_new > n_old ? n_new : n_old;
    for (int s = 0; s < n_write; ++s) {
      out.hist_id[i * kHistorySlots + s] = s < n_new ? new_id[s] : kNoPartner;
      out.hist_xi[i * kHistorySlots + s] = s < n_new ? new_xi[s] : core::zero3<T>();
    }
    if (overflow) out.history_overflow[i] = 1;
    p.force[i] = f;
    p.torque[i] = tq;
    out.dissipated[i] += double(diss_rate) * double(dt);
    out.work_in[i] += double(power_in) * double(dt);
    out.elastic[i] = elastic;
    out.drum_torque[i] = drum_tq;
  }
};

// Pass 2, per particle i: adds the pairs owned by lower-index partners (read at the mirror slot,
// force reversed). Each particle writes only its own sums: no atomics, same result on any
// thread schedule or on the GPU.
template <class T>
struct GatherPartnerForces {
  ParticleView<T> p;
  const int* nbr_count;
  const int* nbr_list;
  const int* mirror;
  int nbr_capacity;
  ContactOutputs<T> out;
  PairBuffer<T> pairs;
  T dt;

  MILLSIM_HD void operator()(int i) const {
    const T ri = p.radius[i];
    Vec3<T> f = core::zero3<T>(), tq = core::zero3<T>();
    T diss_rate = T(0), elastic = T(0);
    const int nc = nbr_count[i] < nbr_capacity ? nbr_count[i] : nbr_capacity;
    for (int k = 0; k < nc; ++k) {
      const int j = nbr_list[i * nbr_capacity + k];
      if (j > i) continue;
      const int e = j * nbr_capacity + mirror[i * nbr_capacity + k];
      const T delta = pairs.delta[e];
      if (delta <= T(0)) continue;
      f -= pairs.force[e];
      tq -= (ri - T(0.5) * delta) * pairs.n_cross_ft[e];
      diss_rate += T(0.5) * pairs.dissipation_rate[e];
      elastic += T(0.5) * pairs.elastic[e];
    }
    p.force[i] += f;
    p.torque[i] += tq;
    out.dissipated[i] += double(diss_rate) * double(dt);
    out.elastic[i] += elastic;
  }
};

}  // namespace millsim::dem
