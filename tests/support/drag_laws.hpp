#pragma once
// Drag laws the body tests compare with.

namespace millsim::testing {

// Haberman & Sayre (1958; Happel & Brenner, Low Reynolds Number Hydrodynamics, sec. 7-4): the
// creeping-flow drag of a sphere of radius a on the axis of a tube of radius R0, lambda = a / R0,
// is 6 pi mu a U K with
//   K = (1 - 0.75857 l^5) / (1 - 2.1050 l + 2.0865 l^3 - 1.7068 l^5 + 0.72603 l^6).
inline double habermanSayre(double l) {
  const double l3 = l * l * l, l5 = l3 * l * l;
  return (1 - 0.75857 * l5) / (1 - 2.1050 * l + 2.0865 * l3 - 1.7068 * l5 + 0.72603 * l5 * l);
}

}  // namespace millsim::testing
