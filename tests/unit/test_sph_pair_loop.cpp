// The two SPH pair loops must give every particle the same sums: the one that visits each pair
// from both sides (SphInteraction, the GPU's) and the one that visits each pair once and hands
// the partner its share (SphPairInteraction + SphPairScatter, the host's), on one thread and on
// two (partners across the chunk boundary go through the rows). Both evaluate the same pair
// terms (sph_pair.hpp), so only the order of the additions differs: relative agreement ~1e-15
// per sum, asserted at 1e-11 of the sum's scale over the particles (a lost or doubled share is
// a whole pair term, ~1e-2 of that scale). The scene has every kind of particle that takes
// part: fluid, fixed and moving walls, body particles, with random velocities, densities and
// SPS stresses, > 2048 fluid particles so two threads really split it.
//
// The host loop runs its pairs in blocks (sph_pair_batch.hpp) at every SIMD level but kScalar,
// which runs it one particle at a time: both are held to the gather loop, at every level this
// CPU has, and the block runs at the different levels must agree exactly (the same terms per
// pair, FMA contraction off, the same order of the additions).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "millsim/backend/simd.hpp"
#include "millsim/neighbors/cell_list.hpp"
#include "sph/density_diffusion.hpp"
#include "sph/eos.hpp"
#include "sph/kernels.hpp"
#include "sph/sph_kernels.hpp"
#include "sph/sph_scatter.hpp"
#include "support/simd_levels.hpp"

namespace millsim {
namespace {

using core::Vec3;
using Cells = neighbors::CellList<backend::Omp, double>;

// Particle state and sums, in cell order (as the solver renumbers them before each pass).
struct Scene {
  std::vector<Vec3<double>> pos, vel, ace, grad_c;
  std::vector<double> rho, press, drho, visc, div_r;
  std::vector<int> code;
  std::vector<sph::Sym3<double>> strain, tau;
  Cells cells;  // two segments: fluid, then walls and bodies (as the solver keeps them)

  sph::SphView<double> view() {
    return {pos.data(),  vel.data(),    rho.data(),   code.data(),   press.data(), ace.data(), drho.data(),
            visc.data(), grad_c.data(), div_r.data(), strain.data(), tau.data(),   vel.data()};
  }
};

constexpr double kDp = 0.01, kH = 1.2 * kDp * 1.7320508075688772;

Scene makeScene(int dim) {
  Scene s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.2 * kDp, 0.2 * kDp), v(-0.5, 0.5), drho(-20, 20), t(-5, 5);
  const int nz = dim == 3 ? 10 : 1, n_side = dim == 3 ? 22 : 70;
  std::vector<Vec3<double>> pos;
  std::vector<int> code;
  for (int iz = 0; iz < nz; ++iz)
    for (int iy = 0; iy < n_side; ++iy)
      for (int ix = 0; ix < n_side; ++ix) {
        // Three wall layers at the bottom (fixed) and the left (moving), a block of body
        // particles inside the fluid, fluid elsewhere.
        int c = sph::kFluid;
        if (iy < 3)
          c = sph::kBoundFixed;
        else if (ix < 3)
          c = sph::kBoundMoving;
        else if (ix >= 8 && ix < 12 && iy >= 8 && iy < 12)
          c = sph::kBoundBody;
        pos.push_back({ix * kDp + jitter(rng), iy * kDp + jitter(rng), dim == 3 ? iz * kDp + jitter(rng) : 0.0});
        code.push_back(c);
      }
  const int n = static_cast<int>(pos.size());
  const Vec3<double> lo{-0.05, -0.05, dim == 3 ? -0.05 : -1.0};
  const Vec3<double> hi{n_side * kDp + 0.05, n_side * kDp + 0.05, dim == 3 ? nz * kDp + 0.05 : 1.0};
  s.cells.setGrid(neighbors::makeGrid<double>(lo, hi, kH, dim == 2, 2), 2);
  s.cells.build(pos.data(), n, code.data(), sph::kExcludedDensity, sph::kBoundFixed);
  const int* order = s.cells.view().order;
  const sph::TaitEos<double> eos = sph::TaitEos<double>::make(1000, 30, 7);
  for (int k = 0; k < n; ++k) {
    const int i = order[k];
    s.pos.push_back(pos[i]);
    s.code.push_back(code[i]);
    s.vel.push_back({v(rng), v(rng), dim == 3 ? v(rng) : 0.0});
    s.rho.push_back(1000 + drho(rng));
    s.press.push_back(eos.pressure(s.rho.back()));
    s.tau.push_back({t(rng), t(rng), t(rng), t(rng), t(rng), t(rng)});
  }
  s.cells.renumberedInOrder();
  s.ace.assign(n, {});
  s.grad_c.assign(n, {});
  s.drho.assign(n, 0);
  s.visc.assign(n, 0);
  s.div_r.assign(n, 0);
  s.strain.assign(n, sph::zeroSym3<double>());
  return s;
}

struct Sums {
  std::vector<Vec3<double>> ace, grad_c;
  std::vector<double> drho, div_r;
  std::vector<sph::Sym3<double>> strain;
  double visc_max = 0;
};

Sums read(const Scene& s) {
  return {s.ace, s.grad_c, s.drho, s.div_r, s.strain, *std::max_element(s.visc.begin(), s.visc.end())};
}

template <class Physics>
Sums gather(Scene& s, const Physics& phys) {
  const int n = static_cast<int>(s.pos.size());
  const sph::SphInteraction<Physics> loop{s.cells.view(0), s.cells.view(1), s.view(), phys, 4 * kH * kH};
  for (int a = 0; a < n; ++a) loop(a);
  return read(s);
}

template <class Physics>
Sums pairOnce(Scene& s, const Physics& phys, int threads, backend::SimdLevel level) {
  const int n = static_cast<int>(s.pos.size());
  const sph::SphView<double> p = s.view();
  constexpr bool kShift = Physics::kShifting, kStrain = Physics::kStrain;
  const sph::ClearPairSums<double, kShift, kStrain> clear{p};
  for (int a = 0; a < n; ++a) clear(a);
  s.visc.assign(static_cast<std::size_t>(n), 0.0);
  sph::SphPairScatter<double> scatter;
  omp_set_num_threads(threads);
  const backend::ScopedSimdLevel simd(level);
  scatter.run<kShift, kStrain>(s.cells.view(0), s.cells.view(1), s.pos.data(), p, [&](auto sink) {
    return sph::SphPairInteraction<Physics, decltype(sink)>{
        s.cells.view(0), s.cells.view(1), p, phys, 4 * kH * kH, sink};
  });
  omp_set_num_threads(1);
  return read(s);
}

double scale(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}
double scale(const std::vector<Vec3<double>>& v) {
  double m = 0;
  for (const auto& x : v) m = std::max(m, std::sqrt(core::norm2(x)));
  return m;
}

void expectSame(const Sums& a, const Sums& b, const std::vector<int>& code, bool shift, bool strain,
                const std::string& what) {
  const double tol = 1e-11;
  const double s_drho = scale(a.drho), s_ace = scale(a.ace), s_grad = scale(a.grad_c), s_div = scale(a.div_r);
  double s_strain = 0;
  for (const auto& e : a.strain)
    s_strain = std::max(
        {s_strain, std::abs(e.xx), std::abs(e.yy), std::abs(e.zz), std::abs(e.xy), std::abs(e.xz), std::abs(e.yz)});
  if (strain) {
    ASSERT_GT(s_strain, 0) << what;
  }
  ASSERT_GT(s_drho, 0) << what;
  ASSERT_GT(s_ace, 0) << what;
  int checked_body = 0;
  for (std::size_t i = 0; i < code.size(); ++i) {
    EXPECT_NEAR(a.drho[i], b.drho[i], tol * s_drho) << what << ", particle " << i << " code " << code[i];
    if (code[i] == sph::kFluid || code[i] == sph::kBoundBody) {
      checked_body += code[i] == sph::kBoundBody;
      EXPECT_LT(std::sqrt(core::norm2(a.ace[i] - b.ace[i])), tol * s_ace) << what << ", particle " << i;
    }
    if (code[i] != sph::kFluid) continue;
    if (shift) {
      EXPECT_LT(std::sqrt(core::norm2(a.grad_c[i] - b.grad_c[i])), tol * s_grad) << what << ", particle " << i;
      EXPECT_NEAR(a.div_r[i], b.div_r[i], tol * s_div) << what << ", particle " << i;
    }
    if (strain) {
      const auto& x = a.strain[i];
      const auto& y = b.strain[i];
      for (auto [u, w] : {std::pair{x.xx, y.xx}, {x.yy, y.yy}, {x.zz, y.zz}, {x.xy, y.xy}, {x.xz, y.xz}, {x.yz, y.yz}})
        EXPECT_NEAR(u, w, tol * s_strain) << what << ", particle " << i;
    }
  }
  EXPECT_GT(checked_body, 0) << what;
  EXPECT_NEAR(a.visc_max, b.visc_max, 1e-14 * a.visc_max) << what;
}

template <int Dim, class Kernel, class Ddt, class Visc, bool kShift>
void compareLoops(const Kernel& kernel, const Ddt& ddt, const Visc& visc, const std::string& what) {
  using Physics = sph::SphPairPhysics<double, Kernel, Ddt, Visc, kShift>;
  const Physics phys{kernel, ddt, visc, 1000 * std::pow(kDp, Dim), 0.01 * kH * kH, {0, 1, 0}};
  Scene s = makeScene(Dim);
  ASSERT_GT(std::count(s.code.begin(), s.code.end(), int(sph::kFluid)), 2048);
  const Sums ref = gather(s, phys);
  const Sums* first_block = nullptr;
  std::vector<Sums> runs;
  runs.reserve(8);
  for (backend::SimdLevel level : millsim::testing::hostSimdLevels()) {
    const std::string at = what + ", " + backend::simdLevelName(level);
    for (int threads : {1, 2}) {
      runs.push_back(pairOnce(s, phys, threads, level));
      expectSame(ref, runs.back(), s.code, kShift, Physics::kStrain, at + ", threads " + std::to_string(threads));
    }
    if (level == backend::SimdLevel::kScalar) continue;
    // The block levels: the same bits on one thread.
    const Sums& one = runs[runs.size() - 2];
    if (first_block == nullptr) {
      first_block = &one;
      continue;
    }
    EXPECT_TRUE(one.drho == first_block->drho) << at;
    EXPECT_TRUE(one.div_r == first_block->div_r) << at;
    EXPECT_EQ(one.visc_max, first_block->visc_max) << at;
    const auto same3 = [](const Vec3<double>& u, const Vec3<double>& w) {
      return u.x == w.x && u.y == w.y && u.z == w.z;
    };
    for (std::size_t i = 0; i < one.ace.size(); ++i) {
      const sph::Sym3<double>&u = one.strain[i], &w = first_block->strain[i];
      ASSERT_TRUE(same3(one.ace[i], first_block->ace[i])) << at << ", particle " << i;
      ASSERT_TRUE(same3(one.grad_c[i], first_block->grad_c[i])) << at << ", particle " << i;
      ASSERT_TRUE(u.xx == w.xx && u.yy == w.yy && u.zz == w.zz && u.xy == w.xy && u.xz == w.xz && u.yz == w.yz)
          << at << ", particle " << i;
    }
  }
}

TEST(SphPairLoop, PairOnceGivesTheGatherSums3dWendlandFourtakasArtificialShifting) {
  const double c0 = 30, b = c0 * c0 * 1000 / 7;
  compareLoops<3, sph::WendlandC2<3, double>, sph::DdtFourtakas2019<double>, sph::ViscosityArtificial<double>, true>(
      sph::WendlandC2<3, double>::make(kH),
      sph::DdtFourtakas2019<double>{2 * 0.1 * kH * c0, 0.01 * kH * kH, 1000, 1000 * 9.81 / b, 1.0 / 7},
      sph::ViscosityArtificial<double>{0.1, 0.01, kH, c0, 0.01 * kH * kH}, "3D Wendland Fourtakas artificial shifting");
}

TEST(SphPairLoop, PairOnceGivesTheGatherSums3dCubicMolteniLaminarSps) {
  compareLoops<3, sph::CubicSpline<3, double>, sph::DdtMolteni2009<double>, sph::ViscosityLaminarSps<double>, false>(
      sph::CubicSpline<3, double>::make(kH), sph::DdtMolteni2009<double>{2 * 0.1 * kH * 30, 0.01 * kH * kH},
      sph::ViscosityLaminarSps<double>{1e-3, 0.01 * kH * kH}, "3D cubic Molteni laminar+SPS");
}

TEST(SphPairLoop, PairOnceGivesTheGatherSums2dWendlandNoDdtLaminarShifting) {
  compareLoops<2, sph::WendlandC2<2, double>, sph::DdtNone, sph::ViscosityLaminarSps<double>, true>(
      sph::WendlandC2<2, double>::make(kH), sph::DdtNone{}, sph::ViscosityLaminarSps<double>{1e-3, 0.01 * kH * kH},
      "2D Wendland no DDT laminar+SPS shifting");
}

// The laminar term alone (viscosity = laminar, or laminar_sps with Cs = C_I = 0): the towed
// cylinder's and spin-up's configuration.
TEST(SphPairLoop, PairOnceGivesTheGatherSums2dWendlandFourtakasLaminarShifting) {
  const double c0 = 30, b = c0 * c0 * 1000 / 7;
  compareLoops<2, sph::WendlandC2<2, double>, sph::DdtFourtakas2019<double>, sph::ViscosityLaminar<double>, true>(
      sph::WendlandC2<2, double>::make(kH),
      sph::DdtFourtakas2019<double>{2 * 0.1 * kH * c0, 0.01 * kH * kH, 1000, 1000 * 9.81 / b, 1.0 / 7},
      sph::ViscosityLaminar<double>{1e-3, 0.01 * kH * kH}, "2D Wendland Fourtakas laminar shifting");
}

}  // namespace
}  // namespace millsim
