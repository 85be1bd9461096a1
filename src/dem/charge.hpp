#pragma once
// Ball charge of a mill: sizes from the Bond equilibrium distribution and random non-overlapping
// placement in the (longer) generation drum. Host-side set-up, run once per case.
#include <cstdint>
#include <vector>

namespace millsim::dem {

struct BallClass {
  double diameter;        // m
  double mass_fraction;   // of the charge
  int count;
};

// Bond (1961): cumulative mass fraction passing size x is y = (x / B)^m (paper: m = 3.8, B the
// makeup size). Class i of diameter x_i takes the mass between x_(i-1) and x_i; the smallest class
// also takes everything below it (no ball is smaller than min_size).
std::vector<BallClass> bondClasses(double top, double min_size, double step, double exponent);

// Counts per class so the total ball volume is `volume` (each class rounded to the nearest ball).
void fillCounts(std::vector<BallClass>& classes, double volume);

struct Placement {
  std::vector<double> pos;     // 3 per ball
  std::vector<double> radius;
};

// Random sequential addition of balls (largest first) inside a cylinder of radius `radius`
// (axis z) over z in [0, length], no overlap between balls or with the walls. Returns false if
// some ball could not be placed within the attempt budget (the filling does not fit).
bool placeBalls(const std::vector<BallClass>& classes, double radius, double length, std::uint64_t seed,
                Placement& out);

}  // namespace millsim::dem
