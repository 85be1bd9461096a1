// The embedded default case: byte for byte cases/ball_mill_300_balls.xml, so a program that has no
// case file on disk (an installed binary, a test) still gets the paper's 300 mm drum.
// tests/unit/test_case_xml.cpp compares the two: edit the .xml, then paste it between the
// delimiters.
#include "millsim/io/case_xml.hpp"

namespace millsim::io {

const char* defaultCaseXml() {
  return R"millsim_case(<?xml version="1.0" encoding="UTF-8"?>
<!--
  ball_mill_300_balls: laboratory ball mill, 300 mm drum, balls only (no ore, no water).

  The balls-only calibration stage of
    B. Doroszek, P. Bortnowski, M. Ozdoba, R. Krol, "Calibrating the Digital Twin of a
    Laboratory Ball Mill for Copper Ore Milling: Integrating Computer Vision and Discrete
    Element Method and Smoothed Particle Hydrodynamics (DEM-SPH) Simulations",
    Minerals 14 (2024) 407, https://doi.org/10.3390/min14040407
  The paper calibrated restitution and friction on the dynamic angle of repose of this stage
  for the 300, 400 and 500 mm drums; the three cases differ only in the drum and ball sizes.

  From the paper:
    drum      outer diameter 300 mm, inner 8 mm smaller: 0.292 m (section 3.1);
              eight 5 mm lifters, evenly spaced (section 3.6)
    speed     30 % of the critical speed; the paper gives 24.8 rpm for this drum (section 3.6)
    balls     steel, density 7800.92 kg/m3 (measured); classes 15, 20, 25, 30 and 35 mm
              (top size 35 mm, 5 mm steps) in Bond's equilibrium charge y = (x / B)^3.8
              (section 3.5); the balls fill 30 % of the drum volume (section 3.6)
    contact   E = 1e8 Pa (reduced from steel for speed), nu = 0.29 (section 3.8);
              calibrated restitution 0.390 and kinetic friction 0.496 (section 4)
    timeline  12 s: a piston pushes the loose charge into the drum during the first 2 s,
              then 10 s of rotation; the first 2 s are not analysed (section 3.8.1)
  Our choices, not in the paper (see docs/cases.md): inner length 0.15 m, lifter width 5 mm,
  time step from the Hertz contact time (the paper used a fixed step), exact damping for the
  restitution, and the angle of repose measured from 4 s on over 100 frames.
  Format of this file: docs/case-format.md.
-->
<millsim name="ball_mill_300_balls">
  <time end="12" dt="auto" dt_divisor="50" dt_fixed="1e-5"/>
  <gravity x="0" y="-9.81" z="0"/>
  <output series_every="0.01" fields_every="0.5" checkpoint_every="1"/>
  <dem youngs_modulus="1e8" poisson="0.29" density="7800.92" restitution="0.390"
       friction="0.496" damping="exact" friction_smoothing="none" impact_velocity="2"/>
  <drum diameter="0.292" length="0.15" speed_rpm="24.8" start_time="2" spin_up="0">
    <lifters count="8" height="0.005" width="0.005"/>
  </drum>
  <charge filling="0.3" top_size="0.035" min_size="0.015" size_step="0.005" bond_exponent="3.8"
          seed="1" count="0"/>
  <compaction duration="2" length_factor="3"/>
  <angle_of_repose enabled="true" start_time="4" frames="100" pixels_per_mm="2" threshold="0.5"
                   smoothing_px="5" fit_offset_mm="60" fit_length_mm="0"/>
</millsim>
)millsim_case";
}

}  // namespace millsim::io
