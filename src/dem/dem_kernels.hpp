#pragma once
// The DEM step as MILLSIM_HD functors over particle indices, run by backend::parallelFor on
// OpenMP or CUDA: the same code on both. Each pair is evaluated once, by its lower-index particle
// from the half neighbour list (partners j > i); the reaction on j goes through a sink
// (partner_scatter.hpp) that the backend chooses. Particles are renumbered in cell order at each
// neighbour rebuild (reorder_kernels.hpp) so a pair's two sides lie close in memory.
#include <type_traits>
#include <utility>

#include "dem/contact/hertz.hpp"
#include "dem/contact/lubrication.hpp"
#include "dem/ensemble.hpp"
#include "dem/touching_pair.hpp"
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
  // The mass a contact's damping sees: the particle's own (the same array as mass) or, for a
  // DCDEM body's element, the body's.
  const T* contact_mass;
};

// Half-kick of velocity Verlet: v += dt/2 a, w += dt/2 alpha. Dt is the step (T), or an
// ensemble's step per case (SceneTable: the particle's case's, 0 for a case that has ended).
template <class T, class Dt = T>
struct Kick {
  ParticleView<T> p;
  Dt dt;
  MILLSIM_HD void operator()(int i) const {
    const T h = T(0.5) * valueAt(dt, p.pos[i]);
    p.vel[i] += (h * p.inv_mass[i]) * p.force[i];
    p.omega[i] += (h * p.inv_inertia[i]) * p.torque[i];
  }
};

// First half-kick and drift: v += dt/2 a(t), x += dt v. The force and torque sums are used up
// here, so they are cleared for the coming contact pass in the same sweep (one pass over the
// particles less per step).
template <class T, class Dt = T>
struct KickDrift {
  ParticleView<T> p;
  Dt dt;
  MILLSIM_HD void operator()(int i) const {
    const T h = valueAt(dt, p.pos[i]);  // before the drift: the case's slab
    Kick<T>{p, h}(i);
    p.pos[i] += h * p.vel[i];
    p.force[i] = core::zero3<T>();
    p.torque[i] = core::zero3<T>();
  }
};

// A new held external load replaces the old one in the force of the current state (the force
// the next step's first half-kick uses): a load held over the steps that follow then delivers
// exactly (sum of their dt) x load, with no half step of the previous load carried over.
template <class T>
struct ReplaceHeldLoad {
  ParticleView<T> p;
  const int* id;             // host number of each particle
  const Vec3<T>* old_force;  // host order; nullptr when there was none
  const Vec3<T>* old_torque;
  const Vec3<T>* new_force;
  const Vec3<T>* new_torque;
  MILLSIM_HD void operator()(int i) const {
    const int k = id[i];
    p.force[i] += new_force[k];
    p.torque[i] += new_torque[k];
    if (old_force) {
      p.force[i] -= old_force[k];
      p.torque[i] -= old_torque[k];
    }
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

// An ensemble's: the squared displacement over the particle's case's half skin squared (> 1:
// rebuild), or +inf for a non-finite position.
template <class T>
struct ScaledDisplacementSq {
  const Vec3<T>* pos;
  const Vec3<T>* ref;
  SceneTable<T> skin;
  MILLSIM_HD T operator()(int i) const {
    const T h = T(0.5) * valueAt(skin, ref[i]);
    const T d2 = DisplacementSq<T>{pos, ref}(i) / (h * h);
    return d2 == d2 ? d2 : T(1e30);
  }
};

// Half Verlet neighbour list from the cell list, stored compact (CSR): j > i is listed when the
// gap is below `skin`. Run twice per rebuild: with list == nullptr it only counts (count[i]),
// then, with start[] the exclusive scan of the counts, it writes list[start[i] ..]. Compact rows
// keep the per-slot springs contiguous, so the force pass streams them (a fixed-capacity row
// per particle left most of each row empty and made the spring loads miss the cache).
// The particles are numbered in cell order (DemSolver::reorderParticles runs before), so the
// partners j > i lie in i's own row of cells after i and in the rows after it: the search visits
// only those (about half the block), and on the host tests their distances in vectors
// (CellListView::forEachWithinAfter) at the reach to the largest partner, then each hit at its
// own. The list is the one a search of the whole block keeps, in the same order.
template <class T, class Skin = T>
struct BuildNeighbourList {
  neighbors::CellListView<T> cells;  // renumbered in cell order
  const Vec3<T>* pos;
  const T* radius;
  Vec3<T>* pos_ref;
  int* count;                    // pass 1 output
  const int* start;              // pass 2 input
  int* list;                     // pass 2 output (nullptr in pass 1)
  Skin skin;                     // T, or an ensemble's per case (SceneTable)
  T max_radius;                  // the largest radius of any particle: the search's reach
  T range_factor = T(0);         // pairs interacting at a gap (lubrication): listed within (1 + f)(r_i + r_j) + skin
  const int* body_of = nullptr;  // DCDEM: elements of one body (same id >= 0) never pair
  MILLSIM_HD void operator()(int i) const {
    const Vec3<T> xi = pos[i];
    const T ri = radius[i];
    const T skin_i = valueAt(skin, xi);
    int c = 0;
    const int base = list ? start[i] : 0;
    const int bi = body_of ? body_of[i] : -1;
    const T search = (T(1) + range_factor) * (ri + max_radius) + skin_i;
    cells.forEachWithinAfter(i, xi, search * search, pos, [&](int j, Vec3<T>, T r2) {
      if (bi >= 0 && body_of[j] == bi) return;
      const T reach = (T(1) + range_factor) * (ri + radius[j]) + skin_i;
      if (r2 < reach * reach) {
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

// ContactForces' pair hook when nothing acts beyond contact (the drum): every use is behind
// `if constexpr (Extra::kActive)`, so the drum's loop is the same code as without the hook.
// A hook (collision_stats.hpp: StirredPairExtra) provides pairRange/wallRange, pairLubrication/
// wallLubrication (forces at a gap and in contact, kLub) and pairContact/wallContact (tallies).
template <class T>
struct NoPairExtra {
  static constexpr bool kActive = false;
  static constexpr bool kLub = false;
};

// Walls with still parts (the stirred mill's chamber) book those contacts' torque apart from the
// moving ones'; Walls::kHasFixedWalls and Walls::isMoving(id) say which (DrumWalls: all moving).
template <class W, class = void>
struct HasFixedWalls : std::false_type {};
template <class W>
struct HasFixedWalls<W, std::void_t<decltype(W::kHasFixedWalls)>> : std::bool_constant<W::kHasFixedWalls> {};

// The force pass, per particle i: gravity, the drum walls and every pair (i, j > i) of the half
// list, each evaluated once with the contact law. The force on i is summed in registers; the
// reaction on j (and half the pair's dissipation) goes to the sink. The pair's elastic energy is
// booked to i alone: only its total is used, and one scattered add less per pair is measurable.
template <class T, class Law, class Sink, class Walls = DrumWalls<T>, class Extra = NoPairExtra<T>, class Dt = T>
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
  T* drum_torque;  // torque of this particle's wall contacts on the drum about +z, N m
  Walls walls;
  Law law;
  T wall_mass_factor;
  Vec3<T> gravity;
  Dt step;  // the step (T), or an ensemble's per case (SceneTable)
  Sink sink;
  Extra extra{};
  T* fixed_wall_torque = nullptr;  // HasFixedWalls: torque of the still walls about +z, N m

  // What i's own contacts add up to before they are booked: gravity, its walls, an external
  // load and, in the per-particle loop, its pairs (the batched pass books those apart).
  struct OwnSums {
    Vec3<T> f, tq;
    T diss_rate, elastic, drum_tq, power_in, fixed_tq;
  };

  // The host's batched pass (contact_batch.hpp) can take the pairs of a plain drum or stirrer:
  // one law and one step for all, and no lubrication (a film acts on pairs that do not touch).
  // A hook that only reads touching pairs (the collision statistics) is called as the block is
  // booked: kPairHook.
  static constexpr bool kPairHook = Extra::kActive;
  static constexpr bool kBatchable =
      !Extra::kLub && std::is_same_v<Dt, T> &&
      std::is_same_v<std::decay_t<decltype(lawAt(std::declval<const Law&>(), std::declval<const Vec3<T>&>()))>, Law>;

  MILLSIM_HD void operator()(int i) const {
    const Vec3<T> xi_pos = p.pos[i], vi = p.vel[i], wi = p.omega[i];
    const T ri = p.radius[i], mi = p.contact_mass[i];
    // The law and step of i's scene (an ensemble's per-scene e, mu and dt); plain ones are themselves.
    const auto law_i = lawAt(law, xi_pos);
    const T dt = valueAt(step, xi_pos);
    // An ensemble's case that has reached its end rests: no forces, no bookkeeping (its pairs
    // and walls are its own, so nothing else is touched).
    if constexpr (!std::is_same_v<Dt, T>) {
      if (dt == T(0)) return;
    }
    OwnSums a = startSums(i);

    const int end = nbr_start[i + 1];
    for (int slot = nbr_start[i]; slot < end; ++slot) {
      const int j = nbr_list[slot];
      const Vec3<T> d = xi_pos - p.pos[j];
      const T rj = p.radius[j];
      const T reach = ri + rj;
      const T dist2 = core::norm2(d);
      if (!pairTouches(dist2, reach)) {
        pair_xi[slot] = core::zero3<T>();  // apart: the spring is released
        if constexpr (Extra::kLub) {
          const T lub_reach = reach + extra.pairRange(ri, rj);
          if (dist2 < lub_reach * lub_reach && dist2 > T(0)) {
            const T dist = std::sqrt(dist2);
            const Vec3<T> n = (T(1) / dist) * d;
            const LubricationResult<T> l =
                extra.pairLubrication(i, n, dist - reach, ri, rj, vi, p.vel[j], wi, p.omega[j]);
            a.f += l.force;
            a.tq += l.torque_i;
            sink.addPartner(j, -l.force, l.torque_j, T(0));
          }
        }
        continue;
      }
      Vec3<T> s = pair_xi[slot];
      [[maybe_unused]] const bool begins = s.x == T(0) && s.y == T(0) && s.z == T(0);
      const Vec3<T> vj = p.vel[j], wj = p.omega[j];
      const TouchingPair<T> t = touchingPair(law_i, d, dist2, ri, rj, mi, p.contact_mass[j], vi - vj, wi, wj, s, dt);
      const ContactResult<T>& c = t.c;
      pair_xi[slot] = s;
      a.f += c.force;
      a.tq -= t.ai * t.nxft;
      a.diss_rate += T(0.5) * c.dissipation_rate;
      a.elastic += c.elastic_energy;
      if constexpr (Extra::kActive) {
        extra.pairContact(i, t.n, ri, rj, mi, vi - vj, wi, wj, t.v_rel, c, begins);
        if constexpr (Extra::kLub) {
          // In contact the film acts at the regularised inner cutoff (lubrication.hpp).
          const LubricationResult<T> l = extra.pairLubrication(i, t.n, -t.delta, ri, rj, vi, vj, wi, wj);
          a.f += l.force;
          a.tq += l.torque_i;
          sink.addPartner(j, -c.force - l.force, l.torque_j - (t.aj * t.nxft), T(0.5) * c.dissipation_rate * dt);
          continue;
        }
      }
      // On j: -F, and the torque -aj (n_j x F_t,j) with n_j = -n, F_t,j = -F_t.
      sink.addPartner(j, -c.force, -(t.aj * t.nxft), T(0.5) * c.dissipation_rate * dt);
    }

    wallContacts(i, law_i, dt, a);
    bookOwn(i, dt, a);
  }

  MILLSIM_HD OwnSums startSums(int i) const {
    return {p.mass[i] * gravity, core::zero3<T>(), T(0), T(0), T(0), T(0), T(0)};
  }

  // i's wall contacts (and, with lubrication, wall films) into its sums, with the wall springs'
  // history carried by wall id.
  template <class LawI>
  MILLSIM_HD void wallContacts(int i, const LawI& law_i, T dt, OwnSums& a) const {
    const Vec3<T> xi_pos = p.pos[i], vi = p.vel[i], wi = p.omega[i];
    const T ri = p.radius[i], mi = p.contact_mass[i];
    int old_key[kWallSlots];
    Vec3<T> old_xi[kWallSlots];
    int n_old = 0;
    while (n_old < kWallSlots && wall_hist.key[i * kWallSlots + n_old] != kNoPartner) {
      old_key[n_old] = wall_hist.key[i * kWallSlots + n_old];
      old_xi[n_old] = wall_hist.xi[i * kWallSlots + n_old];
      ++n_old;
    }
    int n_new = 0;
    // With lubrication the walls report gaps up to its range too (delta > -range).
    T wall_range = T(0);
    if constexpr (Extra::kLub) wall_range = extra.wallRange(ri);
    walls.forEachContact(xi_pos, ri + wall_range, [&](const WallContact<T>& w_in) {
      WallContact<T> w = w_in;
      if constexpr (Extra::kLub) {
        w.delta -= wall_range;
        const LubricationResult<T> l = extra.wallLubrication(i, w.n, -w.delta, ri, vi - w.velocity, wi);
        a.f += l.force;
        a.tq += l.torque_i;
        a.power_in += core::dot(l.force, w.velocity);
        bookWallTorque(w, l.force, a.drum_tq, a.fixed_tq);
        if (w.delta <= T(0)) return;  // a film, no contact
      }
      const T ai = ri - w.delta;
      const Vec3<T> v_rel = vi + core::cross(wi, (-ai) * w.n) - w.velocity;
      Vec3<T> s = core::zero3<T>();
      for (int q = 0; q < n_old; ++q)
        if (old_key[q] == w.wall) s = old_xi[q];
      const ContactResult<T> c = law_i(w.n, w.delta, ri, wall_mass_factor * mi, v_rel, s, dt);
      if (n_new < kWallSlots) {
        wall_hist.key[i * kWallSlots + n_new] = w.wall;
        wall_hist.xi[i * kWallSlots + n_new] = s;
        ++n_new;
      } else {
        wall_hist.overflow[i] = 1;
      }
      a.f += c.force;
      a.tq += core::cross((-ai) * w.n, c.force_t);
      a.diss_rate += c.dissipation_rate;
      a.elastic += c.elastic_energy;
      if constexpr (Extra::kActive) extra.wallContact(i, c);
      // Reaction on the drum: -F at the contact point; its z-moment drives the shaft torque.
      bookWallTorque(w, c.force, a.drum_tq, a.fixed_tq);
      a.power_in += core::dot(c.force, w.velocity);
    });
    for (int q = n_new; q < n_old; ++q) wall_hist.key[i * kWallSlots + q] = kNoPartner;
  }

  // i's sums to memory, with an external load (wet runs) added here.
  MILLSIM_HD void bookOwn(int i, T dt, OwnSums& a) const {
    if (ext_force) {
      const Vec3<T> fe = ext_force[id[i]], te = ext_torque[id[i]];
      a.f += fe;
      a.tq += te;
      // Power of the external load at this instant (v, omega at the force evaluation).
      work_external[i] += double(core::dot(fe, p.vel[i]) + core::dot(te, p.omega[i])) * double(dt);
    }
    sink.addOwn(i, a.f, a.tq, a.diss_rate * dt);
    elastic_out[i] = a.elastic;
    work_in[i] += double(a.power_in) * double(dt);
    drum_torque[i] = a.drum_tq;
    if constexpr (HasFixedWalls<Walls>::value) fixed_wall_torque[i] = a.fixed_tq;
  }

  // The z-moment of the reaction -F at the contact point: on the drum (or the stirrer), or on
  // the still walls when the walls have some.
  MILLSIM_HD static void bookWallTorque(const WallContact<T>& w, Vec3<T> force, T& moving_tq, T& fixed_tq) {
    const T m = w.point.x * force.y - w.point.y * force.x;
    if constexpr (HasFixedWalls<Walls>::value) {
      if (!Walls::isMoving(w.wall)) {
        fixed_tq -= m;
        return;
      }
    }
    (void)fixed_tq;
    moving_tq -= m;
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
