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

// The mDBC ghost offset of a drum wall particle at (x, y, z): its mirror image across the
// nearest wall surface (cylinder, end plate, lifter face; both for a mantle-plate corner),
// minus the particle.
std::array<double, 3> drumGhost(const DrumGeometry& drum, double x, double y, double z);

// True when x lies inside a lifter of the drum, grown by `clearance`.
bool insideLifter(const DrumGeometry& drum, double x, double y, double clearance);

// Appends the shell of a spherical body (a disc in 2D) of radius r centred at c: the points of
// a lattice of spacing dp with r - layers dp <= |x - c| < r, as body particles (code kBoundBody)
// of body `body`, with their offsets from c and ghosts mirrored radially across r. The lattice:
// - by default one with a point at c, the shell symmetric about its centre; the fluid around it
//   is carved to r + dp/2 (carveFluid) and lies on another lattice;
// - given `lattice_origin`, the fluid's own lattice, lattice_origin + (i, j, k) dp, with the
//   fluid carved to r. Then the first fluid particle stands dp from the outermost shell one in
//   every direction, as fluid particles stand from each other. Why: two lattices leave gaps of 1
//   to 2 dp, by direction, which move the body's effective surface inwards by a fraction of dp:
//   a sphere of 3 dp radius turning in a shell then feels 0.73 of the analytic torque, a towed
//   one 0.80 of Stokes' drag; on one lattice 1.16 and 1.06 (docs/validation.md, "One lattice").
void addSphereShell(SphHostState& s, const std::array<double, 3>& c, double r, double dp, int dim, int layers, int body,
                    double rho0, const std::optional<std::array<double, 3>>& lattice_origin = std::nullopt);

// The origin of the lattice that addDrumWalls and the drum's fluid use, points at (i + 1/2) dp:
// the lattice_origin to cut a body's shell from the same lattice.
inline std::array<double, 3> cellCentredLattice(double dp) { return {0.5 * dp, 0.5 * dp, 0.5 * dp}; }

// Removes the fluid particles closer than `clearance` to c (the space of a body).
void carveFluid(SphHostState& s, const std::array<double, 3>& c, double clearance);

// Sets every particle's density to the hydrostatic value of a free surface at height
// `surface_y` (up is +y, or the axis `up_axis`): rho = rho0 (1 + rho0 g (surface_y - y) / B)^(1/gamma),
// B = c0^2 rho0 / gamma, and rho0 above the surface (boundary particles never below rho0).
void hydrostaticDensity(SphHostState& s, double surface_y, double g, double rho0, double c0, double gamma,
                        int up_axis = 1);

}  // namespace millsim::sph
