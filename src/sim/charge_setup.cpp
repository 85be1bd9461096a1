#include "sim/charge_setup.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <tuple>

#include "dem/dcdem_bodies.hpp"
#include "dem/dem_kernels.hpp"
#include "millsim/core/error.hpp"

namespace millsim::sim {

namespace {

core::InputError chargeError(const scene::Scene& s, const std::string& what) {
  auto it = s.element_lines.find("charge");
  return core::InputError(s.source, it == s.element_lines.end() ? 0 : it->second, "<charge>: " + what);
}

// Numbers the balls in cell order (z, then y, then x; cells of one ball-pair size) so that
// neighbours are close in memory: placement order is random in space, and in a dense bed of
// 49k balls that alone made the contact loop 1.5x slower (docs/performance.md).
void spatialOrder(dem::Placement& p, double cell) {
  const std::size_t n = p.radius.size();
  std::vector<std::size_t> order(n);
  std::vector<std::array<long, 3>> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    order[i] = i;
    for (int a = 0; a < 3; ++a) key[i][a] = static_cast<long>(std::floor(p.pos[3 * i + a] / cell));
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(key[a][2], key[a][1], key[a][0]) < std::tie(key[b][2], key[b][1], key[b][0]);
  });
  dem::Placement sorted;
  for (std::size_t k : order) {
    sorted.pos.insert(sorted.pos.end(), {p.pos[3 * k], p.pos[3 * k + 1], p.pos[3 * k + 2]});
    sorted.radius.push_back(p.radius[k]);
  }
  p = std::move(sorted);
}

}  // namespace

ChargeSetup buildCharge(const scene::Scene& s) {
  ChargeSetup c;
  const double pi = std::acos(-1.0);
  const double R = 0.5 * s.drum.diameter, L = s.drum.length;
  c.classes = dem::bondClasses(s.charge.top_size, s.charge.min_size, s.charge.size_step, s.charge.bond_exponent);
  const double mill_volume = pi * R * R * L;
  if (s.charge.count_override > 0) {
    // Same mass fractions, scaled to the requested number of balls.
    dem::fillCounts(c.classes, 1.0);
    double per_unit = 0;
    for (auto& k : c.classes) per_unit += k.mass_fraction / (pi / 6 * std::pow(k.diameter, 3));
    dem::fillCounts(c.classes, s.charge.count_override / per_unit);
    int total = 0;
    for (auto& k : c.classes) total += k.count;
    c.classes.back().count += s.charge.count_override - total;
  } else {
    dem::fillCounts(c.classes, s.charge.filling * mill_volume);
  }
  double ball_volume = 0;
  int count = 0;
  for (auto& k : c.classes) {
    ball_volume += k.count * pi / 6 * std::pow(k.diameter, 3);
    count += k.count;
  }
  if (count == 0) throw chargeError(s, "the filling gives no ball at all (mill too small for the ball sizes?)");
  const double inner_r = R - s.drum.lifters.height;
  if (s.charge.top_size >= inner_r) throw chargeError(s, "top_size does not fit inside the drum and its lifters");

  c.generation_length = s.compaction.duration > 0 ? L * s.compaction.length_factor : L;
  const double gen_volume = pi * inner_r * inner_r * c.generation_length;
  // Random sequential addition jams near 38% volume fraction; beyond ~30% it is hopeless.
  if (ball_volume > 0.30 * gen_volume) {
    std::ostringstream m;
    m << "the balls (" << ball_volume * 1e3 << " l, " << count << " balls) do not fit: they would fill "
      << 100.0 * ball_volume / gen_volume << "% of the generation volume (max 30%); lower filling or raise "
      << "<compaction length_factor>";
    throw chargeError(s, m.str());
  }
  dem::Placement placement;
  if (!dem::placeBalls(c.classes, inner_r, c.generation_length, s.charge.seed, placement))
    throw chargeError(s, "could not place all " + std::to_string(count) +
                             " balls without overlap; lower filling or raise <compaction length_factor>");

  spatialOrder(placement, 2.0 * s.charge.top_size);
  const std::size_t n = placement.radius.size();
  auto& st = c.state;
  st.pos = placement.pos;
  st.vel.assign(3 * n, 0.0);
  st.omega.assign(3 * n, 0.0);
  st.radius = placement.radius;
  st.mass.resize(n);
  st.inertia.resize(n);
  st.hist_id.assign(n * dem::kHistorySlots, dem::kNoPartner);
  st.hist_xi.assign(3 * n * dem::kHistorySlots, 0.0);
  st.dissipated.assign(n, 0.0);
  st.work_in.assign(n, 0.0);
  double mr = 0;
  c.min_radius = 1e300;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = st.radius[i];
    st.mass[i] = s.dem.density * 4.0 / 3.0 * pi * r * r * r;
    st.inertia[i] = 0.4 * st.mass[i] * r * r;
    c.total_mass += st.mass[i];
    mr += st.mass[i] * r;
    c.min_radius = std::min(c.min_radius, r);
    c.max_radius = std::max(c.max_radius, r);
  }
  c.mean_radius = mr / c.total_mass;
  return c;
}

DcdemCharge dcdemCharge(const dem::DemHostState& balls, double dp) {
  dem::BodyAssembler a;
  for (std::size_t i = 0; i < balls.size(); ++i) {
    const core::Vec3<double> c{balls.pos[3 * i], balls.pos[3 * i + 1], balls.pos[3 * i + 2]};
    std::vector<core::Vec3<double>> pts = dem::latticeBallPoints(balls.radius[i], dp);
    for (auto& p : pts) p += c;
    a.addBody(pts, 0.5 * dp, balls.mass[i], {balls.vel[3 * i], balls.vel[3 * i + 1], balls.vel[3 * i + 2]},
              {balls.omega[3 * i], balls.omega[3 * i + 1], balls.omega[3 * i + 2]}, balls.radius[i]);
  }
  return {a.state(), a.bodies()};
}

}  // namespace millsim::sim
