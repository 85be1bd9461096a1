#pragma once
// Where a test body's centre falls in the fluid lattice's cell.
#include <array>

namespace millsim::testing {

// A generic offset of a body's centre from a lattice cell corner, in dp: no symmetry, no ties
// between lattice distances. At the corner itself the lattice cut of a = 3 dp holds 136 points
// where the sphere's volume is 113.1 dp^3, an effective (volume-matched) radius of 1.063 a, at
// 4 dp 280 points, 1.015 a; at this offset the cut at a holds 112 and 267 points, 0.997 a and
// 0.999 a (docs/validation.md, "Where the centre falls"). The turning, towed and settling
// sphere tests place their body here; their shells and fluid are cut by sph::latticeCut.
inline constexpr std::array<double, 3> kGenericLatticeOffset{0.31, 0.17, 0.43};

}  // namespace millsim::testing
