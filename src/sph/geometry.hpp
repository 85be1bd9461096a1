#pragma once
// Geometry -> particles at spacing dp, host side, set-up only. Fluid fills a box on a lattice
// whose first row sits dp/2 inside the box faces; boundary particles (DBC) stand outside the box
// faces in `layers` rows at dp/2, 3dp/2, ..., so fluid and wall particles start dp apart and the
// wall surface is the box face. In 2D z is ignored (all particles at z = 0).
#include <array>
#include <optional>
#include <vector>

#include "sph/sph_engine.hpp"

namespace millsim::sph {

struct Box {
  std::array<double, 3> lo{}, hi{};
};

// Appends fluid particles filling `box` (velocity 0, density rho0; see hydrostaticDensity).
void fillFluidBox(SphHostState& s, const Box& box, double dp, int dim, double rho0);

// Appends the walls of an open-top (or closed) tank around `box`: floor, side walls (and front
// and back walls in 3D), `layers` deep, up to box.hi.y (+ the roof when closed). `code` is
// kBoundFixed or kBoundMoving.
void addTankWalls(SphHostState& s, const Box& box, double dp, int dim, int layers, bool closed_top, int code,
                  double rho0);

// Drum walls as boundary particles (moving DBC, rotating about z): the cylinder of inner
// radius R (axis z, 0 <= z <= L) with `layers` rows outside it, the two end plates (layers
// below z = 0 and above z = L), and N box lifters of radial height h and tangential width w
// whose centre lines point at angle first_angle + k 2 pi / N. Points of a Cartesian lattice of
// spacing dp (centres at (i + 1/2) dp), the same lattice the fluid fill uses.
struct DrumGeometry {
  double radius = 0, length = 0;
  int lifters = 0;
  double lifter_height = 0, lifter_width = 0, first_angle = 0;
};
void addDrumWalls(SphHostState& s, const DrumGeometry& drum, double dp, int layers, double rho0);

// The lattice's coordinate of index m along an axis whose points are origin + m dp. Every set-up
// that cuts fluid, walls and body shells from one lattice computes its points with this one
// expression, so that a point has the same coordinates, bit for bit, whichever of them asks.
inline double latticeCoord(double origin, double dp, long m) { return origin + static_cast<double>(m) * dp; }

// The number of layers k = 0, 1, ... of the drum lattice (points at (k + 1/2) dp) inside the
// drum's length, (k + 1/2) dp < L; layer nz and beyond belong to the far end plate, k < 0 to
// the near one. One count for the fluid fill and addDrumWalls, so that no layer is left empty
// (flooring L / dp would leave one when L / dp has a fractional part of 1/2 or more).
int drumAxialLayers(double length, double dp);

// True when a point at offset (dx, dy, dz) from a body's centre lies inside the body's radius r:
// the one test that carves the fluid (carveFluid, the wet mill's fill) and keeps a shell point
// (addSphereShell), so that a point on the surface |x - c| = r is exactly one of the two.
inline bool insideRadius(double dx, double dy, double dz, double r) { return dx * dx + dy * dy + dz * dz < r * r; }

// The mDBC ghost offset of a drum wall particle at (x, y, z): its mirror image across the
// nearest wall surface (cylinder, end plate, lifter face; both for a mantle-plate corner),
// minus the particle.
std::array<double, 3> drumGhost(const DrumGeometry& drum, double x, double y, double z);

// True when x lies inside a lifter of the drum, grown by `clearance`.
bool insideLifter(const DrumGeometry& drum, double x, double y, double clearance);

// The radius at which a body of radius r centred at c is cut from the lattice lattice_origin +
// (i, j, k) dp (2D: the disc, k = 0): of the cuts between two successive distances of lattice
// points from c, the one holding the number of points closest to the body's volume / dp^3 (2D:
// area / dp^2), returned half-way (in squared distance) between those two distances, so that no
// point lies near it. Why: a cut at r itself holds as many points as a sphere of 0.95-1.07 r by
// where c falls in the cell (a = 2.5-3.5 dp; at a cell corner 136 points for a = 3 dp against
// 113.1 dp^3, at a lattice point 93), and a turning sphere's torque follows that effective
// radius cubed: 0.907-1.017 of Lamb's at a = 4 dp over five centres (docs/validation.md, "Where
// the centre falls"). Points that tie in distance are kept or dropped together, so a symmetric
// set-up stays symmetric.
double latticeCutRadius(const std::array<double, 3>& c, double r, double dp, int dim,
                        const std::array<double, 3>& lattice_origin);

// A body's cut from the fluid's lattice: the lattice's origin and latticeCutRadius. Computed
// once per body (a sort of the ~(2 r / dp + 5)^3 distances around it) and handed to both the
// fluid's carve and the shell, which must agree on it.
struct LatticeCut {
  std::array<double, 3> origin;
  double radius;
};
inline LatticeCut latticeCut(const std::array<double, 3>& c, double r, double dp, int dim,
                             const std::array<double, 3>& lattice_origin) {
  return {lattice_origin, latticeCutRadius(c, r, dp, dim, lattice_origin)};
}

// Appends the shell of a spherical body (a disc in 2D) of radius r centred at c: the points of
// a lattice of spacing dp with r_cut - layers dp <= |x - c| < r_cut, as body particles (code
// kBoundBody) of body `body`, with their offsets from c and ghosts mirrored radially across r.
// The lattice:
// - by default one with a point at c, r_cut = r, the shell symmetric about its centre; the
//   fluid around it is carved to r + dp/2 (carveFluid) and lies on another lattice;
// - given `cut` (latticeCut), the fluid's own lattice, cut.origin + (i, j, k) dp, r_cut =
//   cut.radius, with the fluid carved to r_cut (carveFluidForShell). Then the first fluid
//   particle stands dp from the outermost shell one in every direction, as fluid particles stand
//   from each other. Why: two lattices leave gaps of 1 to 2 dp, by direction, which move the
//   body's effective surface inwards by a fraction of dp: a sphere of 3 dp radius turning in a
//   shell then feels 0.73 of the analytic torque, a towed one 0.80 of Stokes' drag; on one
//   lattice ~1 (docs/validation.md, "One lattice").
void addSphereShell(SphHostState& s, const std::array<double, 3>& c, double r, double dp, int dim, int layers, int body,
                    double rho0, const std::optional<LatticeCut>& cut = std::nullopt);

// The origin of a fluid lattice whose points are lo + (i + 1/2) dp: the lattice_origin to cut a
// body's shell from it. lo = 0 for addDrumWalls and the drum's fluid; the box's lo corner for
// fillFluidBox and addTankWalls (a box whose corner is not a multiple of dp has its own lattice).
inline std::array<double, 3> cellCentredLattice(double dp, const std::array<double, 3>& lo = {0.0, 0.0, 0.0}) {
  return {lo[0] + 0.5 * dp, lo[1] + 0.5 * dp, lo[2] + 0.5 * dp};
}

// Removes the fluid particles closer than `clearance` to c (the space of a body).
void carveFluid(SphHostState& s, const std::array<double, 3>& c, double clearance);

// Removes the fluid particles inside the body that addSphereShell cuts from the fluid's lattice
// (given the same `cut`): those within cut.radius of c.
inline void carveFluidForShell(SphHostState& s, const std::array<double, 3>& c, const LatticeCut& cut) {
  carveFluid(s, c, cut.radius);
}

// Sets every particle's density to the hydrostatic value of a free surface at height
// `surface_y` (up is +y, or the axis `up_axis`): rho = rho0 (1 + rho0 g (surface_y - y) / B)^(1/gamma),
// B = c0^2 rho0 / gamma, and rho0 above the surface (boundary particles never below rho0).
void hydrostaticDensity(SphHostState& s, double surface_y, double g, double rho0, double c0, double gamma,
                        int up_axis = 1);

}  // namespace millsim::sph
