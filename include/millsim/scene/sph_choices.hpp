#pragma once
// The names each SPH setup choice takes, in one place: the case parser offers them (and lists
// them in `millsim describe`), and SphSolver refuses anything else when the library is driven
// without a case file. A new kernel or viscosity form is added here once.
#include <string>
#include <vector>

namespace millsim::scene::sph_choices {

inline const std::vector<std::string> kKernel{"wendland", "cubic"};
inline const std::vector<std::string> kDdt{"none", "molteni", "fourtakas"};
inline const std::vector<std::string> kViscosity{"artificial", "laminar", "laminar_sps", "laminar_central"};
inline const std::vector<std::string> kIntegrator{"verlet", "symplectic"};
inline const std::vector<std::string> kWallVelocity{"dbc", "no_slip", "no_slip_ghost"};
inline const std::vector<std::string> kBoundary{"dbc", "mdbc"};

}  // namespace millsim::scene::sph_choices
