#pragma once
// Plain description of a case: what the user asked for, in SI units, with no behaviour.
// Built from a case XML (src/io/case_xml.cpp) or from code. Physics never sees a Scene: the
// simulation turns it into the parameter structs of each law.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace millsim::scene {

struct TimeParams {
  double end = 12.0;             // s, simulated time at which the run stops
  std::string dt_mode = "auto";  // "auto": dt = t_contact / dt_divisor; "fixed": dt = dt_fixed
  double dt_fixed = 1e-5;        // s
  double dt_divisor = 50.0;      // N in dt = t_c / N (t_c: Hertz contact time of the stiffest pair)
};

struct OutputParams {
  double series_every = 0.01;     // s between rows of series.csv
  double fields_every = 0.5;      // s between HDF5 field snapshots (<= 0: none)
  double checkpoint_every = 1.0;  // s between checkpoints (<= 0: only at the end)
};

// Contact material and law of the DEM spheres (walls are the same steel, as in the paper).
struct DemParams {
  double youngs_modulus = 1e8;              // Pa (paper: reduced from steel's 2e11 for speed)
  double poisson = 0.29;                    // -
  double density = 7800.92;                 // kg/m3 (paper, measured)
  double restitution = 0.390;               // - (paper's calibrated value)
  double friction = 0.496;                  // - kinetic (Coulomb) friction coefficient
  std::string damping = "exact";            // "exact" (Antypov & Elliott 2011) | "dualsphysics"
  std::string friction_smoothing = "none";  // "none" | "tanh" (paper eq. 55: tanh(8 |v_t|))
  // "spring": Mindlin-type spring with history and Coulomb limit; "dualsphysics": DualSPHysics's
  // history-free DEM tangential law as coded (src/dem/contact/hertz.hpp), for reproducing the paper.
  std::string tangential = "spring";
  double impact_velocity = 2.0;   // m/s, reference speed for the contact time in dt = t_c / N
  std::string law = "hertz";      // "hertz" | "linear" (seed 004's linear spring-dashpot)
  double linear_stiffness = 1e5;  // N/m, k_n of the linear law
  // Verlet skin of the neighbour list in smallest radii (DCDEM: in element spacings): the list is
  // rebuilt when a particle has moved half of it. Larger: fewer rebuilds, longer lists.
  double skin = 0.2;
  // Balls as analytic spheres, or as the paper's DCDEM bodies: particles at element_spacing
  // filling each ball, contacts element on element (src/dem/rigid_body.hpp).
  std::string representation = "sphere";  // "sphere" | "dcdem"
  double element_spacing = 0.005;         // m, dp of the DCDEM balls (paper: 0.005)
};

struct LifterParams {
  int count = 8;          // evenly spaced (paper: eight)
  double height = 0.005;  // m, radial (paper: 5 mm)
  double width = 0.005;   // m, tangential (not in the paper: see docs/cases.md)
};

struct DrumParams {
  double diameter = 0.292;         // m, inner (paper: outer 300 mm, inner 8 mm smaller)
  double length = 0.1;             // m, inner length between end plates
  double speed_rpm = 24.8;         // rpm; used when critical_fraction <= 0
  double critical_fraction = 0.0;  // > 0: speed = fraction * Nc, Nc = 60/(2pi) sqrt(g/(R - r_mean))
  double start_time = 2.0;         // s, rotation starts (after compaction)
  double spin_up = 0.0;            // s, linear ramp to full speed
  LifterParams lifters;
};

// Ball charge: Bond equilibrium distribution y = (x / B)^3.8 over classes min..top in steps.
struct ChargeParams {
  double filling = 0.30;     // ball volume / mill volume
  double top_size = 0.035;   // m (B, makeup size)
  double min_size = 0.015;   // m
  double size_step = 0.005;  // m
  double bond_exponent = 3.8;
  std::uint64_t seed = 1;
  int count_override = 0;  // > 0: this many balls instead of the filling (tests)
};

// The paper's 2 s piston phase: balls are placed loosely in a longer drum and the back plate
// moves to its final position over `duration` while gravity settles the charge.
struct CompactionParams {
  double duration = 2.0;       // s (piston motion ends at duration * 0.75, then settling)
  double length_factor = 3.0;  // generation length / final length
};

struct AngleParams {
  bool enabled = true;
  double start_time = 4.0;  // s, frames before this are not used (transient after start)
  int frames = 100;         // evenly spaced over [start_time, end]
  double pixels_per_mm = 2.0;
  double threshold = 0.5;       // fraction of frames a pixel must be covered in
  int smoothing_px = 5;         // box filter half-width applied to the thresholded map
  double fit_offset_mm = 60.0;  // regression starts this far right of the highest edge point
  double fit_length_mm = 0.0;   // > 0: regression stops after this length; 0: to the toe
};

// Weakly compressible SPH (paper eqs. 1-45, the DualSPHysics formulation). Names follow
// DualSPHysics's case parameters where one exists (coefh, coefsound, hswl, RhopOut...).
struct SphParams {
  int dimension = 2;                     // 2 (x-y plane, up is +y) or 3
  double dp = 0.01;                      // m, particle spacing
  std::string kernel = "wendland";       // wendland | cubic
  double coefh = 1.0;                    // h = coefh dp sqrt(dimension)
  double coefsound = 20.0;               // c0 = coefsound sqrt(|g| hswl)
  double hswl = 0.0;                     // m, still-water height for c0; 0: the fluid's height
  double rho0 = 1000.0;                  // kg/m3
  double gamma = 7.0;                    // Tait exponent
  std::string viscosity = "artificial";  // artificial | laminar | laminar_sps | laminar_central
  double alpha = 0.1;                    // artificial viscosity coefficient
  double visco_bound_factor = 1.0;       // alpha multiplier for fluid-boundary pairs
  double nu = 1e-6;                      // m2/s, kinematic viscosity (laminar, laminar_sps, laminar_central)
  std::string wall_velocity = "dbc";     // dbc | no_slip: wall velocity in the viscous terms
  std::string boundary = "dbc";          // dbc | mdbc: wall densities by continuity or from ghost nodes
  std::string ddt = "fourtakas";         // none | molteni | fourtakas
  double ddt_value = 0.1;                // delta
  std::string integrator = "verlet";     // verlet | symplectic
  int verlet_steps = 40;                 // an Euler step every N steps
  double cfl = 0.2;                      // dt = cfl min(dt_f, dt_cv) when time.dt = auto
  std::string shifting = "none";         // none | full (Fickian, off at the free surface)
  double shift_coef = 2.0;               // A_s
  double shift_tfs = 0.0;                // free-surface threshold of div r; 0: 1.5 (2D), 2.75 (3D)
  double rhop_out_min = 700.0;           // kg/m3: fluid outside [min, max] is excluded
  double rhop_out_max = 1300.0;
  double parts_out_max = 0.01;                  // the run stops when more than this fraction is excluded
  int boundary_layers = 0;                      // DBC layers; 0: ceil(2h / dp), enough for the kernel
  std::string initial_density = "hydrostatic";  // hydrostatic | rho0
};

// A rectangular tank of boundary particles (DBC) around [min, max], open at the top unless
// closed; it may rotate about z through its centre (sloshing).
struct TankParams {
  double x_min = 0, y_min = 0, z_min = 0;
  double x_max = 1, y_max = 1, z_max = 1;
  bool closed = false;
  double rotation_rpm = 0.0;  // rpm about +z through the tank centre; 0: fixed
  double spin_up = 0.0;       // s, linear ramp to full speed
};

struct FluidBoxParams {
  double x_min = 0, y_min = 0, z_min = 0;
  double x_max = 1, y_max = 1, z_max = 1;
};

// Wet mill: slurry poured into the voids of the settled charge when the drum starts.
struct SlurryParams {
  double filling = 0.2;  // slurry volume / drum volume (paper: charge 50% of the mill, balls 30%)
};

struct ProbeParams {
  std::string points;  // "name:x,y[,z];name:x,y[,z]" (m): Shepard-interpolated pressure
};

// Horizontal stirred media mill (seed 004, a Netzsch LabStar LS1-like chamber; docs/cases.md):
// a still chamber (cylinder about z from z = 0 to length, two end plates) and a stirrer turning
// about +z: a shaft over the whole length carrying disk_count perforated disks, evenly spaced,
// each with hole_count axial holes on a ring. The speed program holds each speed for `hold`
// after a linear `ramp` from the previous one (from rest for the first).
struct StirrerParams {
  double chamber_diameter = 0.090;  // m, inner
  double chamber_length = 0.143;    // m, inner
  double shaft_diameter = 0.038;    // m
  int disk_count = 4;
  double disk_diameter = 0.076;       // m
  double disk_thickness = 0.0075;     // m
  int hole_count = 4;                 // per disk
  double hole_diameter = 0.012;       // m
  double hole_ring_diameter = 0.058;  // m, circle through the hole centres
  std::string speeds_rpm = "1000 1500 2000 2500 3000 3500 4000";
  double hold = 0.0525;       // s at each speed (seed: 52.5 ms simulated per speed)
  double ramp = 0.0;          // s, linear ramp from the previous speed
  double average_from = 0.5;  // power averaged over the last (1 - this) of each hold
  double idle_power_W = 0.0;  // P_0 of the mill without beads (net power = P - P_0)
};

// Grinding beads for the stirred mill: `count` spheres with diameters uniform in
// [diameter, diameter_max], placed at random sites of a close-packed lattice in the free space.
struct BeadParams {
  int count = 128000;
  double diameter = 0.0018;      // m
  double diameter_max = 0.0;     // m; 0: all beads of `diameter`
  double lattice_factor = 1.02;  // lattice spacing / largest diameter
  std::uint64_t seed = 1;
};

// Pairwise hydrodynamic lubrication (Jeffrey-Onishi, seed 004 eqs. 5-11) for beads and walls.
// viscosity = 0 turns it off entirely: no lubrication stage and no extra arrays.
struct LubricationSceneParams {
  double viscosity = 0.0;  // Pa s (seed's eta_f,sim)
  double inner = 0.001;    // inner cutoff / d_ij (regularised below)
  double outer = 0.05;     // outer cutoff / d_ij
};

// Collision analysis of the stirred mill (seed 004 section 3.3): Beinert typology, 9 regions,
// coarse-grained velocity fields.
struct CollisionParams {
  bool enabled = true;         // with a <collisions> element (Scene::has_collisions): statistics on
  double start = 0.0;          // s: statistics from this time on
  double sample_every = 2e-4;  // s between velocity-field samples
  int grid_radial = 24;        // velocity field cells across the chamber diameter (x and y)
  int grid_axial = 24;         // cells along the axis
};

struct Scene {
  std::string name = "ball_mill_300_balls";
  std::string source = "<embedded>";  // file the scene came from, for messages
  // Element name -> line in the source file, so checks made after parsing (a filling that does
  // not fit, ...) can still name file:line. Keys are dotted element paths ("drum.lifters").
  std::map<std::string, int> element_lines;
  std::array<double, 3> gravity{0.0, -9.81, 0.0};
  // Effects the scene calls for; only their stages and arrays exist in a run.
  bool effect_dem = true;
  bool effect_sph = false;
  bool has_drum = true, has_tank = false, has_fluid = false, has_slurry = false;
  bool has_stirrer = false;
  bool has_collisions = false;  // <collisions>: Beinert tallies, regions, velocity field (stirred mill)
  TimeParams time;
  OutputParams output;
  DemParams dem;
  DrumParams drum;
  ChargeParams charge;
  CompactionParams compaction;
  AngleParams angle;
  SphParams sph;
  TankParams tank;
  FluidBoxParams fluid;
  ProbeParams probes;
  SlurryParams slurry;
  StirrerParams stirrer;
  BeadParams beads;
  LubricationSceneParams lubrication;
  CollisionParams collisions;
};

}  // namespace millsim::scene
