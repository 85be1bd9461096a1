// Case XML reader. The schema below is the only place that knows the format: parsing,
// validation, `--set` overrides and describeCaseFormat() all walk the same table, so a new
// attribute is one row and cannot be documented differently from how it is checked.
#include "millsim/io/case_xml.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/scene/sph_choices.hpp"

namespace millsim::io {
namespace {

using scene::Scene;
using tinyxml2::XMLAttribute;
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

constexpr const char* kRootTag = "millsim";

// ---- schema types ------------------------------------------------------------------------------

enum class Kind { Number, Integer, Flag, Choice, Text, Seed };

// Setters into the Scene are accessors returning a reference, so one function serves parsing
// (write) and the docs (read the default of a default-constructed Scene): the documented default
// can never differ from the one a run gets.
using NumberRef = double& (*)(Scene&);
using IntegerRef = int& (*)(Scene&);
using FlagRef = bool& (*)(Scene&);
using TextRef = std::string& (*)(Scene&);
using SeedRef = std::uint64_t& (*)(Scene&);

// Allowed range of a numeric attribute; open ends are strict inequalities.
struct Bounds {
  bool has_min = false;
  double min = 0.0;
  bool min_open = false;
  bool has_max = false;
  double max = 0.0;
  bool max_open = false;

  bool admits(double v) const {
    if (has_min && (min_open ? !(v > min) : !(v >= min))) return false;
    if (has_max && (max_open ? !(v < max) : !(v <= max))) return false;
    return true;
  }
};

Bounds anyValue() { return {}; }

Bounds atLeast(double lo) {
  Bounds b;
  b.has_min = true;
  b.min = lo;
  return b;
}

Bounds above(double lo) {
  Bounds b = atLeast(lo);
  b.min_open = true;
  return b;
}

// range('[', 0, 0.5, ')') reads like the interval it stands for.
Bounds range(char open, double lo, double hi, char close) {
  Bounds b = atLeast(lo);
  b.min_open = open == '(';
  b.has_max = true;
  b.max = hi;
  b.max_open = close == ')';
  return b;
}

struct AttrSpec {
  std::string element;  // dotted element path; "" is the root <millsim>
  std::string name;
  Kind kind = Kind::Number;
  std::string unit;  // SI (or the unit the Scene stores); "" when dimensionless
  Bounds bounds;
  std::vector<std::string> choices;
  bool required = false;
  std::string one_of;        // attributes of one element sharing this tag: exactly one is given
  std::string default_note;  // shown instead of the Scene default where that would mislead
  std::string description;
  NumberRef number = nullptr;
  IntegerRef integer = nullptr;
  FlagRef flag = nullptr;
  TextRef text = nullptr;
  SeedRef seed = nullptr;

  std::string path() const { return element.empty() ? name : element + "." + name; }

  AttrSpec mandatory() const {
    AttrSpec copy = *this;
    copy.required = true;
    copy.default_note = "required";
    return copy;
  }
  AttrSpec exclusive(const char* group, const char* note) const {
    AttrSpec copy = *this;
    copy.one_of = group;
    copy.default_note = note;
    return copy;
  }
  AttrSpec shownDefault(const char* note) const {
    AttrSpec copy = *this;
    copy.default_note = note;
    return copy;
  }
};

struct ElementSpec {
  std::string path;  // "" for the root, "drum.lifters" for <lifters> inside <drum>
  bool required = false;
  FlagRef present = nullptr;  // set to whether the element is in the case (effect switches)
  std::string description;
  std::string required_with = "";  // required when this element (an effect) is in the case
  std::string unless = "";         // ... but not when this element is there instead

  std::string tag() const {
    if (path.empty()) return kRootTag;
    const auto dot = path.rfind('.');
    return dot == std::string::npos ? path : path.substr(dot + 1);
  }
  std::string parent() const {
    const auto dot = path.rfind('.');
    return dot == std::string::npos ? std::string() : path.substr(0, dot);
  }
};

// A rule over more than one attribute; the message blames `element`.`name`. Runs after every
// attribute passed its own bounds, so the values it reads are valid.
struct CrossCheck {
  std::string element;
  std::string name;
  std::string rule;                        // for the docs
  std::string (*violation)(const Scene&);  // "" when the rule holds, else "must be ..."
};

AttrSpec number(const char* element, const char* name, const char* unit, Bounds bounds, NumberRef ref,
                const char* description) {
  AttrSpec s;
  s.element = element;
  s.name = name;
  s.kind = Kind::Number;
  s.unit = unit;
  s.bounds = bounds;
  s.number = ref;
  s.description = description;
  return s;
}

AttrSpec integer(const char* element, const char* name, const char* unit, Bounds bounds, IntegerRef ref,
                 const char* description) {
  AttrSpec s = number(element, name, unit, bounds, nullptr, description);
  s.kind = Kind::Integer;
  s.integer = ref;
  return s;
}

AttrSpec flag(const char* element, const char* name, FlagRef ref, const char* description) {
  AttrSpec s = number(element, name, "", anyValue(), nullptr, description);
  s.kind = Kind::Flag;
  s.flag = ref;
  return s;
}

AttrSpec choice(const char* element, const char* name, std::vector<std::string> choices, TextRef ref,
                const char* description) {
  AttrSpec s = number(element, name, "", anyValue(), nullptr, description);
  s.kind = Kind::Choice;
  s.choices = std::move(choices);
  s.text = ref;
  return s;
}

AttrSpec text(const char* element, const char* name, TextRef ref, const char* description) {
  AttrSpec s = number(element, name, "", anyValue(), nullptr, description);
  s.kind = Kind::Text;
  s.text = ref;
  return s;
}

AttrSpec seed(const char* element, const char* name, SeedRef ref, const char* description) {
  AttrSpec s = number(element, name, "", anyValue(), nullptr, description);
  s.kind = Kind::Seed;
  s.seed = ref;
  return s;
}

// Shortest text that reads back to the same double, with the exponent written the way case files
// write it ("1e8", "1e-5", not to_chars' "1e+08").
std::string formatNumber(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, res.ptr);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

// ---- the schema --------------------------------------------------------------------------------

struct Schema {
  std::vector<ElementSpec> elements;
  std::vector<AttrSpec> attributes;
  std::vector<CrossCheck> checks;

  const ElementSpec* element(const std::string& path) const {
    for (const auto& e : elements)
      if (e.path == path) return &e;
    return nullptr;
  }
  const AttrSpec* attribute(const std::string& element, const std::string& name) const {
    for (const auto& a : attributes)
      if (a.element == element && a.name == name) return &a;
    return nullptr;
  }
  std::vector<const AttrSpec*> attributesOf(const std::string& element) const {
    std::vector<const AttrSpec*> out;
    for (const auto& a : attributes)
      if (a.element == element) out.push_back(&a);
    return out;
  }
  std::vector<const ElementSpec*> childrenOf(const std::string& path) const {
    std::vector<const ElementSpec*> out;
    for (const auto& e : elements)
      if (!e.path.empty() && e.parent() == path) out.push_back(&e);
    return out;
  }
};

Schema buildSchema() {
  Schema s;
  // One row per element/attribute reads as a table: keep the formatter out of it.
  // clang-format off
  s.elements = {
      {"", true, nullptr, "Root of a case."},
      {"time", true, nullptr, "How long to simulate and how the time step is chosen."},
      {"gravity", false, nullptr, "Gravity vector; the drum axis is z."},
      {"output", false, nullptr, "What is written and how often."},
      {"dem", false, [](Scene& sc) -> bool& { return sc.effect_dem; },
       "Contact material and law of the balls (walls are the same steel). Its presence enables "
       "the DEM effect: a case without this element has no balls."},
      {"drum", false, [](Scene& sc) -> bool& { return sc.has_drum; },
       "The rotating drum: geometry and speed. Required with <dem> unless the case has a <stirrer>.", "dem",
       "stirrer"},
      {"drum.lifters", false, nullptr, "Box lifters on the drum shell, evenly spaced."},
      {"charge", false, nullptr,
       "Ball charge: Bond equilibrium distribution y = (x / B)^bond_exponent over the classes "
       "min_size..top_size in size_step steps."},
      {"compaction", false, nullptr,
       "The piston phase before rotation: balls are placed loosely in a longer drum and the back "
       "plate moves to its final position while gravity settles the charge."},
      {"angle_of_repose", false, nullptr,
       "Dynamic angle of repose measured from rendered front views, as the paper measured it "
       "from camera frames."},
      {"sph", false, [](Scene& sc) -> bool& { return sc.effect_sph; },
       "Weakly compressible SPH fluid (DualSPHysics formulation). Its presence enables the SPH "
       "effect."},
      {"fluid", false, [](Scene& sc) -> bool& { return sc.has_fluid; },
       "Box filled with fluid particles at spacing sph.dp. Required with <sph> in a fluid-only case."},
      {"slurry", false, [](Scene& sc) -> bool& { return sc.has_slurry; },
       "Wet mill (<dem> and <sph>): slurry poured into the voids of the settled charge when the drum starts "
       "(drum.start_time). Required with both."},
      {"tank", false, [](Scene& sc) -> bool& { return sc.has_tank; },
       "Rectangular tank of boundary particles (DBC) around [min, max], open at the top unless "
       "closed; may rotate about z through its centre."},
      {"probes", false, nullptr, "Points where the fluid pressure is written to series.csv."},
      {"stirrer", false, [](Scene& sc) -> bool& { return sc.has_stirrer; },
       "Horizontal stirred media mill (seed 004, LabStar LS1-like): a still chamber (cylinder about z, end "
       "plates at z = 0 and chamber_length) and a stirrer turning about +z (a shaft over the whole length with "
       "disk_count evenly spaced perforated disks). Replaces <drum>; the beads come from <beads>."},
      {"beads", false, nullptr, "Grinding beads of the stirred mill, placed at random sites of a close-packed lattice."},
      {"lubrication", false, nullptr,
       "Pairwise hydrodynamic lubrication (Jeffrey-Onishi, seed 004 eqs. 5-11) between beads and with the walls "
       "(stirred mill). viscosity = 0: no lubrication at all."},
      {"collisions", false, [](Scene& sc) -> bool& { return sc.has_collisions; },
       "Collision analysis of the stirred mill: Beinert typology, 9 regions, coarse-grained velocity field. "
       "Without it (or with enabled=\"false\") no per-contact tallies are kept and those outputs are not "
       "written."},
  };

  s.attributes = {
      text("", "name", [](Scene& sc) -> std::string& { return sc.name; },
           "Case name, used in outputs and messages.")
          .shownDefault("file stem"),

      number("time", "end", "s", above(0),
             [](Scene& sc) -> double& { return sc.time.end; },
             "Simulated time at which the run stops.")
          .mandatory(),
      choice("time", "dt", {"auto", "fixed"},
             [](Scene& sc) -> std::string& { return sc.time.dt_mode; },
             "Time step rule: auto = Hertz contact time / dt_divisor, fixed = dt_fixed."),
      number("time", "dt_divisor", "", atLeast(5),
             [](Scene& sc) -> double& { return sc.time.dt_divisor; },
             "N in dt = t_c / N, t_c the Hertz contact time of the stiffest pair at "
             "dem.impact_velocity."),
      number("time", "dt_fixed", "s", above(0),
             [](Scene& sc) -> double& { return sc.time.dt_fixed; },
             "Time step when dt=\"fixed\"."),

      number("gravity", "x", "m/s^2", anyValue(),
             [](Scene& sc) -> double& { return sc.gravity[0]; },
             "Gravity, x component."),
      number("gravity", "y", "m/s^2", anyValue(),
             [](Scene& sc) -> double& { return sc.gravity[1]; },
             "Gravity, y component (up is +y)."),
      number("gravity", "z", "m/s^2", anyValue(),
             [](Scene& sc) -> double& { return sc.gravity[2]; },
             "Gravity, z component (along the drum axis)."),

      number("output", "series_every", "s", above(0),
             [](Scene& sc) -> double& { return sc.output.series_every; },
             "Interval between rows of series.csv."),
      number("output", "fields_every", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.output.fields_every; },
             "Interval between HDF5 field snapshots; 0: none."),
      number("output", "checkpoint_every", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.output.checkpoint_every; },
             "Interval between checkpoints; 0: only at the end."),

      number("dem", "youngs_modulus", "Pa", above(0),
             [](Scene& sc) -> double& { return sc.dem.youngs_modulus; },
             "Young's modulus of balls and walls (paper: 1e8, reduced from steel's 2e11 for "
             "speed)."),
      number("dem", "poisson", "", range('[', 0, 0.5, ')'),
             [](Scene& sc) -> double& { return sc.dem.poisson; },
             "Poisson ratio (paper: 0.29)."),
      number("dem", "density", "kg/m^3", above(0),
             [](Scene& sc) -> double& { return sc.dem.density; },
             "Ball density (paper: 7800.92, measured)."),
      number("dem", "restitution", "", range('(', 0, 1, ']'),
             [](Scene& sc) -> double& { return sc.dem.restitution; },
             "Coefficient of restitution of every contact (paper's calibrated value: 0.390)."),
      number("dem", "friction", "", atLeast(0),
             [](Scene& sc) -> double& { return sc.dem.friction; },
             "Kinetic (Coulomb) friction coefficient (paper's calibrated value: 0.496)."),
      choice("dem", "damping", {"exact", "dualsphysics"},
             [](Scene& sc) -> std::string& { return sc.dem.damping; },
             "Normal damping: exact = gives the restitution exactly (Antypov & Elliott 2011); "
             "dualsphysics = DualSPHysics' formula, whose real restitution differs."),
      choice("dem", "friction_smoothing", {"none", "tanh"},
             [](Scene& sc) -> std::string& { return sc.dem.friction_smoothing; },
             "Tangential force near zero slip: none = plain Coulomb limit; tanh = scaled by "
             "tanh(8 |v_t|) as in the paper's eq. 55."),
      choice("dem", "tangential", {"spring", "dualsphysics"},
             [](Scene& sc) -> std::string& { return sc.dem.tangential; },
             "Tangential law: spring = spring with history and Coulomb limit (k_t = 2/7 of the normal "
             "stiffness; friction_smoothing applies); dualsphysics = DualSPHysics's DEM law as coded (no "
             "history: min(mu F_n tanh(8 v_t), (k_n dt - gamma_n) v_t / 3.5), in practice a viscous drag; "
             "drum cases)."),
      number("dem", "impact_velocity", "m/s", above(0),
             [](Scene& sc) -> double& { return sc.dem.impact_velocity; },
             "Reference impact speed for the contact time t_c in dt = t_c / dt_divisor."),
      choice("dem", "representation", {"sphere", "dcdem"},
             [](Scene& sc) -> std::string& { return sc.dem.representation; },
             "Balls as analytic spheres, or as DCDEM rigid bodies the way the paper's DualSPHysics set-up "
             "builds them: particles on a cubic lattice of element_spacing filling each ball, contacts "
             "particle on particle (bumpy surfaces, R* = element_spacing / 4). Drum cases, dry or wet (the "
             "fluid sees each ball as its shell, as for spheres)."),
      number("dem", "element_spacing", "m", above(0),
             [](Scene& sc) -> double& { return sc.dem.element_spacing; },
             "Particle spacing dp of the DCDEM balls (paper: 0.005); used with representation=\"dcdem\"."),

      number("drum", "diameter", "m", above(0),
             [](Scene& sc) -> double& { return sc.drum.diameter; },
             "Inner diameter (paper: outer 300/400/500 mm, inner 8 mm smaller)."),
      number("drum", "length", "m", above(0),
             [](Scene& sc) -> double& { return sc.drum.length; },
             "Inner length between the end plates."),
      number("drum", "speed_rpm", "rpm", atLeast(0),
             [](Scene& sc) -> double& { return sc.drum.speed_rpm; },
             "Rotation speed. Give exactly one of speed_rpm and critical_fraction.")
          .exclusive("speed", "required: this or critical_fraction"),
      number("drum", "critical_fraction", "", range('(', 0, 2, ']'),
             [](Scene& sc) -> double& { return sc.drum.critical_fraction; },
             "Rotation speed as a fraction of the critical speed Nc = 60/(2 pi) sqrt(g / (R - "
             "r_mean)) (paper: 0.3). Give exactly one of speed_rpm and critical_fraction.")
          .exclusive("speed", "required: this or speed_rpm"),
      number("drum", "start_time", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.drum.start_time; },
             "Rotation starts (after the compaction)."),
      number("drum", "spin_up", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.drum.spin_up; },
             "Linear ramp to full speed; 0: full speed at once."),

      integer("drum.lifters", "count", "", atLeast(0),
              [](Scene& sc) -> int& { return sc.drum.lifters.count; },
              "Number of lifters, evenly spaced; 0: smooth shell (paper: 8)."),
      number("drum.lifters", "height", "m", atLeast(0),
             [](Scene& sc) -> double& { return sc.drum.lifters.height; },
             "Radial height, < drum.diameter / 4 (paper: 5 mm)."),
      number("drum.lifters", "width", "m", atLeast(0),
             [](Scene& sc) -> double& { return sc.drum.lifters.width; },
             "Tangential width (not in the paper: see docs/cases.md)."),

      number("charge", "filling", "", range('(', 0, 0.7, ']'),
             [](Scene& sc) -> double& { return sc.charge.filling; },
             "Ball volume / drum volume (paper: 0.3)."),
      number("charge", "top_size", "m", above(0),
             [](Scene& sc) -> double& { return sc.charge.top_size; },
             "Largest ball diameter, the makeup size B (paper: 35 mm)."),
      number("charge", "min_size", "m", above(0),
             [](Scene& sc) -> double& { return sc.charge.min_size; },
             "Smallest ball diameter, <= top_size."),
      number("charge", "size_step", "m", above(0),
             [](Scene& sc) -> double& { return sc.charge.size_step; },
             "Step between ball classes (paper: 5 mm)."),
      number("charge", "bond_exponent", "", above(0),
             [](Scene& sc) -> double& { return sc.charge.bond_exponent; },
             "Exponent of Bond's equilibrium distribution (paper: 3.8)."),
      seed("charge", "seed", [](Scene& sc) -> std::uint64_t& { return sc.charge.seed; },
           "Seed of the random ball placement."),
      integer("charge", "count", "", atLeast(0),
              [](Scene& sc) -> int& { return sc.charge.count_override; },
              "> 0: this many balls of the classes instead of the filling (tests); 0: from the "
              "filling."),

      number("compaction", "duration", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.compaction.duration; },
             "Piston phase (paper: 2 s); the plate stops at 0.75 duration, then the charge "
             "settles."),
      number("compaction", "length_factor", "", atLeast(1),
             [](Scene& sc) -> double& { return sc.compaction.length_factor; },
             "Length of the drum the balls are generated in / final length."),

      flag("angle_of_repose", "enabled", [](Scene& sc) -> bool& { return sc.angle.enabled; },
           "Measure the angle at the end of the run."),
      number("angle_of_repose", "start_time", "s", atLeast(0),
             [](Scene& sc) -> double& { return sc.angle.start_time; },
             "Frames before this time are not used (transient after the start)."),
      integer("angle_of_repose", "frames", "", atLeast(2),
              [](Scene& sc) -> int& { return sc.angle.frames; },
              "Frames evenly spaced over [start_time, time.end]."),
      number("angle_of_repose", "pixels_per_mm", "px/mm", above(0),
             [](Scene& sc) -> double& { return sc.angle.pixels_per_mm; },
             "Resolution of the rendered front view."),
      number("angle_of_repose", "threshold", "", range('(', 0, 1, ')'),
             [](Scene& sc) -> double& { return sc.angle.threshold; },
             "Fraction of the frames a pixel must be covered in to count as charge."),
      integer("angle_of_repose", "smoothing_px", "px", atLeast(0),
              [](Scene& sc) -> int& { return sc.angle.smoothing_px; },
              "Half-width of the box filter applied to the thresholded map."),
      number("angle_of_repose", "fit_offset_mm", "mm", atLeast(0),
             [](Scene& sc) -> double& { return sc.angle.fit_offset_mm; },
             "The line fit starts this far right of the highest edge point."),
      number("angle_of_repose", "fit_length_mm", "mm", atLeast(0),
             [](Scene& sc) -> double& { return sc.angle.fit_length_mm; },
             "Length of the line fit; 0: to the toe of the charge."),

      integer("sph", "dimension", "", range('[', 2, 3, ']'),
              [](Scene& sc) -> int& { return sc.sph.dimension; },
              "2: the x-y plane (up is +y, quantities per metre of depth); 3: full 3D."),
      number("sph", "dp", "m", above(0), [](Scene& sc) -> double& { return sc.sph.dp; },
             "Particle spacing (paper's wet mill: 0.005).")
          .mandatory(),
      choice("sph", "kernel", scene::sph_choices::kKernel, [](Scene& sc) -> std::string& { return sc.sph.kernel; },
             "Smoothing kernel: Wendland C2 or cubic spline (paper eqs. 6-7)."),
      number("sph", "coefh", "", above(0), [](Scene& sc) -> double& { return sc.sph.coefh; },
             "h = coefh dp sqrt(dimension) (DualSPHysics rule; paper's wet mill: 0.8); h must be >= dp."),
      number("sph", "coefsound", "", above(0), [](Scene& sc) -> double& { return sc.sph.coefsound; },
             "c0 = coefsound sqrt(|g| hswl) (DualSPHysics default 20, so c0 >= 10 sqrt(g H))."),
      number("sph", "hswl", "m", atLeast(0), [](Scene& sc) -> double& { return sc.sph.hswl; },
             "Still-water height for the speed of sound; 0: the height of <fluid>."),
      number("sph", "rho0", "kg/m^3", above(0), [](Scene& sc) -> double& { return sc.sph.rho0; },
             "Reference density (paper's slurry: 1400)."),
      number("sph", "gamma", "", above(0), [](Scene& sc) -> double& { return sc.sph.gamma; },
             "Tait exponent (eq. 28)."),
      choice("sph", "viscosity", scene::sph_choices::kViscosity,
             [](Scene& sc) -> std::string& { return sc.sph.viscosity; },
             "artificial: Monaghan (eq. 21, alpha); laminar: Lo & Shao (eq. 23, nu); laminar_sps: Lo & Shao + SPS "
             "turbulence (eqs. 23-27, nu, Cs = 0.12, C_I = 0.0066); laminar_central: the same nu with pair forces "
             "along the line of centres (Monaghan-Cleary-Gingold): the right torque on turning bodies (Lo & Shao "
             "gives a sphere 2/3 of it) and angular momentum conserved, at a third of the viscous time step."),
      number("sph", "alpha", "", atLeast(0), [](Scene& sc) -> double& { return sc.sph.alpha; },
             "Artificial viscosity coefficient."),
      number("sph", "visco_bound_factor", "", atLeast(0),
             [](Scene& sc) -> double& { return sc.sph.visco_bound_factor; },
             "alpha multiplier for fluid-boundary pairs (paper's wet mill: 0.1)."),
      number("sph", "nu", "m^2/s", atLeast(0), [](Scene& sc) -> double& { return sc.sph.nu; },
             "Kinematic viscosity for laminar, laminar_sps and laminar_central (paper's slurry: 8.1e-6)."),
      choice("sph", "wall_velocity", scene::sph_choices::kWallVelocity,
             [](Scene& sc) -> std::string& { return sc.sph.wall_velocity; },
             "Wall particles in the viscous terms: dbc, their own velocity (DualSPHysics and the paper; the fluid "
             "slips about a spacing past the wall); no_slip, 2 v_wall minus the mean velocity of the fluid next to "
             "them (Adami et al. 2012): no slip at the wall surface, for viscous flows; no_slip_ghost (with "
             "sph.boundary = mdbc), 2 v_wall minus the fluid velocity at the wall particle's ghost node (exact "
             "for a linear shear profile; docs/validation.md compares the two)."),
      choice("sph", "boundary", scene::sph_choices::kBoundary, [](Scene& sc) -> std::string& { return sc.sph.boundary; },
             "Wall densities: dbc, by the continuity equation (the paper, DualSPHysics's default; the wall holds the "
             "fluid about a spacing off its surface); mdbc, from the fluid at each wall particle's mirror image "
             "across the wall (English et al. 2022, first-order consistent), which closes that gap."),
      choice("sph", "ddt", scene::sph_choices::kDdt, [](Scene& sc) -> std::string& { return sc.sph.ddt; },
             "Density diffusion: none, Molteni & Colagrossi 2009, Fourtakas et al. 2019 (eqs. 17-20)."),
      number("sph", "ddt_value", "", atLeast(0), [](Scene& sc) -> double& { return sc.sph.ddt_value; },
             "delta of the density diffusion term."),
      choice("sph", "integrator", scene::sph_choices::kIntegrator,
             [](Scene& sc) -> std::string& { return sc.sph.integrator; },
             "Verlet (an Euler step every verlet_steps) or symplectic position Verlet (eqs. 30-39)."),
      integer("sph", "verlet_steps", "", atLeast(1), [](Scene& sc) -> int& { return sc.sph.verlet_steps; },
              "Ns: an Euler step every Ns Verlet steps."),
      number("sph", "cfl", "", range('(', 0, 1, ']'), [](Scene& sc) -> double& { return sc.sph.cfl; },
             "Courant number of the variable time step (eqs. 40-41) when time.dt = auto; with a laminar viscosity the "
             "step also stays below the viscous term's stability limit, and with ddt below the density diffusion's "
             "(summary.json: sph.dt_viscous_limit_s, sph.dt_ddt_limit_s)."),
      choice("sph", "shifting", {"none", "full"}, [](Scene& sc) -> std::string& { return sc.sph.shifting; },
             "Fickian particle shifting (eqs. 44-45), off where div r < shift_tfs (free surface)."),
      number("sph", "shift_coef", "", atLeast(0), [](Scene& sc) -> double& { return sc.sph.shift_coef; },
             "A_s of the shifting (paper: 2)."),
      number("sph", "shift_tfs", "", atLeast(0), [](Scene& sc) -> double& { return sc.sph.shift_tfs; },
             "Free-surface threshold of div r; 0: 1.5 in 2D, 2.75 in 3D.")
          .shownDefault("0 (1.5 / 2.75)"),
      number("sph", "rhop_out_min", "kg/m^3", above(0), [](Scene& sc) -> double& { return sc.sph.rhop_out_min; },
             "Fluid particles below this density are excluded (counted in summary.json)."),
      number("sph", "rhop_out_max", "kg/m^3", above(0), [](Scene& sc) -> double& { return sc.sph.rhop_out_max; },
             "Fluid particles above this density are excluded; must be > rhop_out_min."),
      number("sph", "parts_out_max", "", range('[', 0, 1, ']'),
             [](Scene& sc) -> double& { return sc.sph.parts_out_max; },
             "The run stops when more than this fraction of the fluid is excluded (paper: 1%)."),
      integer("sph", "boundary_layers", "", atLeast(0), [](Scene& sc) -> int& { return sc.sph.boundary_layers; },
              "Layers of boundary particles; 0: ceil(2h / dp), enough to cover the kernel.")
          .shownDefault("0 (auto)"),
      choice("sph", "initial_density", {"hydrostatic", "rho0"},
             [](Scene& sc) -> std::string& { return sc.sph.initial_density; },
             "Initial fluid density: hydrostatic below the top of <fluid>, or rho0 everywhere."),

      number("fluid", "x_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.x_min; }, "Box, x from.")
          .mandatory(),
      number("fluid", "y_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.y_min; }, "Box, y from.")
          .mandatory(),
      number("fluid", "z_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.z_min; },
             "Box, z from (3D)."),
      number("fluid", "x_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.x_max; }, "Box, x to.")
          .mandatory(),
      number("fluid", "y_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.y_max; }, "Box, y to.")
          .mandatory(),
      number("fluid", "z_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.fluid.z_max; },
             "Box, z to (3D)."),

      number("tank", "x_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.x_min; },
             "Inner box, x from.")
          .mandatory(),
      number("tank", "y_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.y_min; },
             "Inner box, y from (the floor).")
          .mandatory(),
      number("tank", "z_min", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.z_min; },
             "Inner box, z from (3D)."),
      number("tank", "x_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.x_max; },
             "Inner box, x to.")
          .mandatory(),
      number("tank", "y_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.y_max; },
             "Inner box, y to (wall height).")
          .mandatory(),
      number("tank", "z_max", "m", anyValue(), [](Scene& sc) -> double& { return sc.tank.z_max; },
             "Inner box, z to (3D)."),
      flag("tank", "closed", [](Scene& sc) -> bool& { return sc.tank.closed; }, "A roof at y_max."),
      number("tank", "rotation_rpm", "rpm", anyValue(), [](Scene& sc) -> double& { return sc.tank.rotation_rpm; },
             "Rotation about +z through the tank centre (sloshing); 0: fixed."),
      number("tank", "spin_up", "s", atLeast(0), [](Scene& sc) -> double& { return sc.tank.spin_up; },
             "Linear ramp to full rotation speed."),

      number("slurry", "filling", "", range('(', 0, 0.9, ']'), [](Scene& sc) -> double& { return sc.slurry.filling; },
             "Slurry volume / drum volume (paper: 0.2: the charge fills half the mill, the balls 30%)."),

      choice("dem", "law", {"hertz", "linear"}, [](Scene& sc) -> std::string& { return sc.dem.law; },
             "Contact law: hertz (Hertz-Mindlin, the drum's) or linear (seed 004's linear spring-dashpot, stirred "
             "mill only)."),
      number("dem", "linear_stiffness", "N/m", above(0),
             [](Scene& sc) -> double& { return sc.dem.linear_stiffness; },
             "k_n of the linear law (k_t = 2/7 k_n); see docs/cases.md for the stirred mill's choice."),
      number("dem", "skin", "r_min", range('(', 0, 20, ']'), [](Scene& sc) -> double& { return sc.dem.skin; },
             "Verlet skin of the neighbour list, in smallest radii (DCDEM balls: in element spacings); the list is "
             "rebuilt when a particle has moved half of it. See docs/performance.md for the stirred mill's choice."),

      number("stirrer", "chamber_diameter", "m", above(0),
             [](Scene& sc) -> double& { return sc.stirrer.chamber_diameter; }, "Inner diameter of the chamber."),
      number("stirrer", "chamber_length", "m", above(0),
             [](Scene& sc) -> double& { return sc.stirrer.chamber_length; }, "Inner length of the chamber."),
      number("stirrer", "shaft_diameter", "m", above(0),
             [](Scene& sc) -> double& { return sc.stirrer.shaft_diameter; }, "Shaft diameter."),
      integer("stirrer", "disk_count", "", range('[', 0, 16, ']'),
              [](Scene& sc) -> int& { return sc.stirrer.disk_count; },
              "Disks, centred at chamber_length (k + 1/2) / disk_count."),
      number("stirrer", "disk_diameter", "m", above(0),
             [](Scene& sc) -> double& { return sc.stirrer.disk_diameter; }, "Disk diameter, < chamber_diameter."),
      number("stirrer", "disk_thickness", "m", above(0),
             [](Scene& sc) -> double& { return sc.stirrer.disk_thickness; }, "Disk thickness."),
      integer("stirrer", "hole_count", "", range('[', 0, 32, ']'),
              [](Scene& sc) -> int& { return sc.stirrer.hole_count; }, "Axial holes per disk, evenly spaced."),
      number("stirrer", "hole_diameter", "m", atLeast(0),
             [](Scene& sc) -> double& { return sc.stirrer.hole_diameter; }, "Hole diameter."),
      number("stirrer", "hole_ring_diameter", "m", atLeast(0),
             [](Scene& sc) -> double& { return sc.stirrer.hole_ring_diameter; },
             "Diameter of the circle through the hole centres."),
      text("stirrer", "speeds_rpm", [](Scene& sc) -> std::string& { return sc.stirrer.speeds_rpm; },
           "Speed program: rpm values separated by blanks, each held for `hold` (seed: 1000 to 4000 in 500 rpm "
           "steps)."),
      number("stirrer", "hold", "s", above(0), [](Scene& sc) -> double& { return sc.stirrer.hold; },
             "Time at each speed (after its ramp); the run ends after the last hold or at time.end if sooner."),
      number("stirrer", "ramp", "s", atLeast(0), [](Scene& sc) -> double& { return sc.stirrer.ramp; },
             "Linear ramp from the previous speed (from rest for the first)."),
      number("stirrer", "average_from", "", range('[', 0, 1, ')'),
             [](Scene& sc) -> double& { return sc.stirrer.average_from; },
             "Power and torques are averaged over the part of each hold after this fraction (steady state)."),
      number("stirrer", "idle_power_W", "W", atLeast(0),
             [](Scene& sc) -> double& { return sc.stirrer.idle_power_W; },
             "No-load power P_0 at every speed; net power P_n = P - P_0 (DEM beads only: 0)."),

      integer("beads", "count", "", above(0), [](Scene& sc) -> int& { return sc.beads.count; },
              "Number of beads (seed: ~128 000)."),
      number("beads", "diameter", "m", above(0), [](Scene& sc) -> double& { return sc.beads.diameter; },
             "Bead diameter (smallest when diameter_max is given; seed: 1.8 mm)."),
      number("beads", "diameter_max", "m", atLeast(0), [](Scene& sc) -> double& { return sc.beads.diameter_max; },
             "Largest diameter (uniform in [diameter, diameter_max]); 0: all of `diameter`."),
      number("beads", "lattice_factor", "", atLeast(1),
             [](Scene& sc) -> double& { return sc.beads.lattice_factor; },
             "Spacing of the placement lattice / largest diameter."),
      seed("beads", "seed", [](Scene& sc) -> std::uint64_t& { return sc.beads.seed; }, "Seed of the placement."),

      number("lubrication", "viscosity", "Pa s", atLeast(0),
             [](Scene& sc) -> double& { return sc.lubrication.viscosity; },
             "Fluid viscosity eta_f of the lubrication forces; 0: off (no lubrication stage, no arrays)."),
      number("lubrication", "inner", "", above(0), [](Scene& sc) -> double& { return sc.lubrication.inner; },
             "Inner cutoff / d_ij: closer gaps (and overlaps) are evaluated at it (seed: 0.001)."),
      number("lubrication", "outer", "", above(0), [](Scene& sc) -> double& { return sc.lubrication.outer; },
             "Outer cutoff / d_ij: no force beyond (seed: 0.05); must exceed inner."),

      flag("collisions", "enabled", [](Scene& sc) -> bool& { return sc.collisions.enabled; },
           "Keep the statistics (false: as if the element were absent; e.g. for timing runs)."),
      number("collisions", "start", "s", atLeast(0), [](Scene& sc) -> double& { return sc.collisions.start; },
             "Collision statistics and velocity field from this time on."),
      number("collisions", "sample_every", "s", above(0),
             [](Scene& sc) -> double& { return sc.collisions.sample_every; },
             "Interval between velocity-field samples."),
      integer("collisions", "grid_radial", "", atLeast(2), [](Scene& sc) -> int& { return sc.collisions.grid_radial; },
              "Velocity-field cells across the chamber diameter (x and y)."),
      integer("collisions", "grid_axial", "", atLeast(1), [](Scene& sc) -> int& { return sc.collisions.grid_axial; },
              "Velocity-field cells along the axis."),

      text("probes", "points", [](Scene& sc) -> std::string& { return sc.probes.points; },
           "Named points 'name:x,y[,z];...' (m) whose Shepard-interpolated fluid pressure goes to series.csv "
           "as p_<name>_Pa."),
  };

  s.checks = {
      {"dem", "tangential", "`dem.tangential` = dualsphysics: drum cases only",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_dem || sc.dem.tangential != "dualsphysics" || !sc.has_stirrer) return {};
         return "dualsphysics is for drum cases (the stirred mill uses the spring law)";
       }},
      {"dem", "element_spacing", "DCDEM balls: `dem.element_spacing` <= `charge.min_size` / 3; drum cases only",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_dem || sc.dem.representation != "dcdem") return {};
         if (sc.has_stirrer) return "DCDEM balls are for drum cases (the stirred mill's beads are spheres)";
         // A ball of radius >= 1.5 dp holds its centre and six neighbours (an inertia tensor that
         // is not singular); a smaller one would be a single element.
         if (sc.dem.element_spacing > sc.charge.min_size / 3 * (1 + 1e-12))
           return "must be <= charge.min_size / 3 = " + formatNumber(sc.charge.min_size / 3) +
                  " (m): the smallest ball needs elements across it";
         return {};
       }},
      {"sph", "rhop_out_max", "`sph.rhop_out_min` < `sph.rhop_out_max`",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_sph || sc.sph.rhop_out_min < sc.sph.rhop_out_max) return {};
         return "must be > sph.rhop_out_min = " + formatNumber(sc.sph.rhop_out_min) + " (kg/m^3)";
       }},
      {"sph", "rho0", "`sph.rhop_out_min` < `sph.rho0` < `sph.rhop_out_max`",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_sph || (sc.sph.rho0 > sc.sph.rhop_out_min && sc.sph.rho0 < sc.sph.rhop_out_max)) return {};
         return "must lie between sph.rhop_out_min and sph.rhop_out_max";
       }},
      {"sph", "wall_velocity", "`sph.wall_velocity` = no_slip_ghost needs `sph.boundary` = mdbc",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_sph || sc.sph.wall_velocity != "no_slip_ghost" || sc.sph.boundary == "mdbc") return {};
         return "no_slip_ghost takes the velocity at mDBC ghost nodes: it needs sph.boundary = mdbc";
       }},
      {"sph", "coefh", "h = `sph.coefh` dp sqrt(`sph.dimension`) >= dp",
       [](const Scene& sc) -> std::string {
         if (!sc.effect_sph || sc.sph.coefh * std::sqrt(double(sc.sph.dimension)) >= 1.0) return {};
         return "gives h = " + formatNumber(sc.sph.coefh * std::sqrt(double(sc.sph.dimension))) +
                " dp, smaller than dp: must be >= " + formatNumber(1.0 / std::sqrt(double(sc.sph.dimension)));
       }},
      {"fluid", "x_max", "`fluid.x_min` < `fluid.x_max`, `fluid.y_min` < `fluid.y_max` (and z in 3D)",
       [](const Scene& sc) -> std::string {
         if (!sc.has_fluid) return {};
         if (!(sc.fluid.x_min < sc.fluid.x_max) || !(sc.fluid.y_min < sc.fluid.y_max) ||
             (sc.sph.dimension == 3 && !(sc.fluid.z_min < sc.fluid.z_max)))
           return "the box is empty: each max must exceed its min";
         return {};
       }},
      {"tank", "x_max", "`tank.x_min` < `tank.x_max`, `tank.y_min` < `tank.y_max` (and z in 3D)",
       [](const Scene& sc) -> std::string {
         if (!sc.has_tank) return {};
         if (!(sc.tank.x_min < sc.tank.x_max) || !(sc.tank.y_min < sc.tank.y_max) ||
             (sc.sph.dimension == 3 && !(sc.tank.z_min < sc.tank.z_max)))
           return "the box is empty: each max must exceed its min";
         return {};
       }},
      {"drum.lifters", "height", "`drum.lifters.height` < `drum.diameter` / 4",
       [](const Scene& sc) -> std::string {
         const double limit = sc.drum.diameter / 4.0;
         if (sc.drum.lifters.height < limit) return {};
         return "must be < drum.diameter / 4 = " + formatNumber(limit) + " (m)";
       }},
      {"stirrer", "disk_diameter",
       "`stirrer.shaft_diameter` < `stirrer.disk_diameter` < `stirrer.chamber_diameter`; the holes lie inside the "
       "disk (`hole_ring_diameter` + `hole_diameter` < `disk_diameter`, `hole_ring_diameter` - `hole_diameter` > "
       "`shaft_diameter`)",
       [](const Scene& sc) -> std::string {
         if (!sc.has_stirrer) return {};
         const auto& st = sc.stirrer;
         if (!(st.shaft_diameter < st.disk_diameter && st.disk_diameter < st.chamber_diameter))
           return "must lie between stirrer.shaft_diameter and stirrer.chamber_diameter";
         if (st.hole_count > 0 && !(st.hole_ring_diameter + st.hole_diameter < st.disk_diameter &&
                                    st.hole_ring_diameter - st.hole_diameter > st.shaft_diameter))
           return "must hold the holes: hole_ring_diameter +- hole_diameter must lie within (shaft, disk) diameters";
         return {};
       }},
      {"stirrer", "speeds_rpm", "`stirrer.speeds_rpm`: one or more numbers >= 0",
       [](const Scene& sc) -> std::string {
         if (!sc.has_stirrer) return {};
         std::istringstream in(sc.stirrer.speeds_rpm);
         double v = 0;
         int n = 0;
         while (in >> v) {
           if (!(v >= 0)) return "must hold rpm values >= 0";
           ++n;
         }
         if (!in.eof() || n == 0) return "must be rpm values separated by blanks, e.g. \"1000 1500 2000\"";
         return {};
       }},
      {"lubrication", "outer", "`lubrication.inner` < `lubrication.outer` <= 0.5",
       [](const Scene& sc) -> std::string {
         if (sc.lubrication.inner < sc.lubrication.outer && sc.lubrication.outer <= 0.5) return {};
         return "must be > lubrication.inner and <= 0.5";
       }},
      {"stirrer", "chamber_diameter", "<stirrer> and <drum> exclude each other; <stirrer> needs dem.law = linear or hertz",
       [](const Scene& sc) -> std::string {
         if (sc.has_stirrer && sc.has_drum) return "<stirrer> replaces <drum>: give one of them";
         return {};
       }},
      {"charge", "min_size", "`charge.min_size` <= `charge.top_size`",
       [](const Scene& sc) -> std::string {
         if (sc.charge.min_size <= sc.charge.top_size) return {};
         return "must be <= charge.top_size = " + formatNumber(sc.charge.top_size) + " (m)";
       }},
  };
  // clang-format on
  return s;
}

const Schema& schema() {
  static const Schema kSchema = buildSchema();
  return kSchema;
}

// ---- small text helpers ------------------------------------------------------------------------

std::string joinPath(const std::string& parent, const std::string& child) {
  return parent.empty() ? child : parent + "." + child;
}

std::string joinList(const std::vector<std::string>& items, const char* sep = ", ") {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}

// Most unknown names are typos of a known one; naming it saves the user reading the whole list.
std::string didYouMean(const std::string& name, const std::vector<std::string>& known) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t above_value = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = above_value;
      }
    }
    return row[b.size()];
  };
  std::string best;
  std::size_t best_distance = 3;  // more than two edits away is a different word, not a typo
  for (const auto& k : known) {
    const std::size_t d = distance(name, k);
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

std::string unitSuffix(const std::string& unit) { return unit.empty() ? "" : " (" + unit + ")"; }

std::string boundsText(const Bounds& b) {
  if (b.has_min && b.has_max)
    return std::string(b.min_open ? "(" : "[") + formatNumber(b.min) + ", " + formatNumber(b.max) +
           (b.max_open ? ")" : "]");
  if (b.has_min) return std::string(b.min_open ? "> " : ">= ") + formatNumber(b.min);
  if (b.has_max) return std::string(b.max_open ? "< " : "<= ") + formatNumber(b.max);
  return "any";
}

std::string mustBe(const Bounds& b) { return (b.has_min && b.has_max ? "must be in " : "must be ") + boundsText(b); }

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(first, last - first + 1));
}

// Strict parsers: the whole string must be the value (no surrounding blanks, no trailing junk)
// and they ignore the C locale, so "1,5" is never read as 1 and a German locale reads "1.5".
// One leading '+' is accepted because people write "+9.81".
std::string_view dropPlus(std::string_view s) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  return s;
}

bool parseDouble(std::string_view s, double& out) {
  s = dropPlus(s);
  if (s.empty()) return false;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), out, std::chars_format::general);
  return res.ec == std::errc() && res.ptr == s.data() + s.size() && std::isfinite(out);
}

bool parseInt(std::string_view s, int& out) {
  s = dropPlus(s);
  long long v = 0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ec != std::errc() || res.ptr != s.data() + s.size()) return false;
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return false;
  out = static_cast<int>(v);
  return true;
}

bool parseUint64(std::string_view s, std::uint64_t& out) {
  s = dropPlus(s);
  unsigned long long v = 0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ec != std::errc() || res.ptr != s.data() + s.size()) return false;
  out = static_cast<std::uint64_t>(v);
  return true;
}

// tinyxml2's ErrorStr() is "Error=XML_ERROR_MISMATCHED_ELEMENT ErrorID=14 (0xe) Line number=2:
// XMLElement name=b"; users get a sentence and the element instead.
std::string malformedXmlText(const XMLDocument& doc) {
  std::string what;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      what = "cannot parse an element tag (an unclosed quote or a stray '<'?)";
      break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      what = "cannot parse an attribute (missing quotes or '=', or the same attribute twice)";
      break;
    case tinyxml2::XML_ERROR_PARSING_TEXT:
      what = "cannot parse text";
      break;
    case tinyxml2::XML_ERROR_PARSING_CDATA:
      what = "unterminated CDATA section";
      break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT:
      what = "unterminated comment";
      break;
    case tinyxml2::XML_ERROR_PARSING_DECLARATION:
      what = "cannot parse the <?xml ...?> line";
      break;
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN:
      what = "cannot parse a <!...> construct";
      break;
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
      what = "the document is empty";
      break;
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      what = "end tag does not match the open element";
      break;
    case tinyxml2::XML_ERROR_PARSING:
      what = "unexpected end of the document (an element left open?)";
      break;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      what = "elements nested too deeply";
      break;
    default:
      what = XMLDocument::ErrorIDToName(doc.ErrorID());
      break;
  }
  const std::string raw = doc.ErrorStr() ? doc.ErrorStr() : "";
  const auto at = raw.find("Line number=");
  const auto colon = at == std::string::npos ? std::string::npos : raw.find(": ", at);
  if (colon != std::string::npos) {
    std::string detail = raw.substr(colon + 2);
    const std::string element_prefix = "XMLElement name=";
    if (detail.rfind(element_prefix, 0) == 0) {
      what += " in <" + detail.substr(element_prefix.size()) + ">";
    } else if (!detail.empty()) {
      if (detail.size() > 60) detail = detail.substr(0, 60) + "...";
      what += " near '" + trim(detail) + "'";
    }
  }
  return what;
}

// ---- the reader --------------------------------------------------------------------------------

class CaseReader {
 public:
  explicit CaseReader(std::string source) : m_source(std::move(source)) {}

  Scene read(const std::string& xml, const std::vector<std::string>& overrides) {
    parseDocument(xml);
    for (const auto& o : overrides) applyOverride(o);

    Scene scene;
    scene.source = m_source;
    scene.name = std::filesystem::path(m_source).stem().string();
    // Effects switched on by an element's presence are off unless the element is read.
    for (const auto& e : schema().elements)
      if (e.present) e.present(scene) = false;

    readElement(*m_doc.RootElement(), *schema().element(""), scene);
    for (const auto& e : schema().elements)
      if (!e.required_with.empty() && m_read.count(e.required_with) && !m_read.count(e.path) &&
          (e.unless.empty() || !m_read.count(e.unless)))
        failElement(*m_read.at(e.required_with),
                    "<" + schema().element(e.required_with)->tag() + "> needs a <" + e.tag() + "> element in the case");
    if (m_read.count("sph") && !m_read.count("dem") && !m_read.count("fluid"))
      failElement(*m_read.at("sph"), "<sph> needs a <fluid> element in the case");
    if (m_read.count("sph") && m_read.count("dem") && !m_read.count("slurry"))
      failElement(*m_read.at("sph"), "<sph> with <dem> (a wet mill) needs a <slurry> element in the case");
    if (!m_read.count("dem") && !m_read.count("sph"))
      failElement(*m_doc.RootElement(), "<millsim>: nothing to simulate: the case has neither <dem> nor <sph>");
    runCrossChecks(scene);
    return scene;
  }

 private:
  void parseDocument(const std::string& xml) {
    if (m_doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
      throw core::InputError(m_source, std::max(1, m_doc.ErrorLineNum()), "malformed XML: " + malformedXmlText(m_doc));
    const XMLElement* root = m_doc.RootElement();
    if (!root) throw core::InputError(m_source, 1, "no root element (expected <millsim>)");
    if (std::string(root->Name()) != kRootTag)
      throw core::InputError(m_source, root->GetLineNum(),
                             "root element is <" + std::string(root->Name()) + ">, expected <millsim>");
    // tinyxml2 accepts content after the root; a second root is a pasted case, not intent.
    for (const XMLNode* n = root->NextSibling(); n; n = n->NextSibling()) {
      if (const XMLElement* e = n->ToElement())
        throw core::InputError(
            m_source, e->GetLineNum(),
            "unexpected element <" + std::string(e->Name()) + "> after </millsim> (a case has one root)");
      if (n->ToText() && !trim(n->Value()).empty())
        throw core::InputError(m_source, n->GetLineNum(), "unexpected text after </millsim>");
    }
  }

  [[noreturn]] static void failOverride(const std::string& text, const std::string& message) {
    throw core::InputError("--set " + text + ": " + message);
  }

  void applyOverride(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
      failOverride(text, "expected PATH=VALUE, e.g. time.end=2 (paths: docs/case-format.md)");
    const std::string path = text.substr(0, eq);
    const std::string value = text.substr(eq + 1);
    const auto dot = path.rfind('.');
    const std::string element_path = dot == std::string::npos ? "" : path.substr(0, dot);
    const std::string name = dot == std::string::npos ? path : path.substr(dot + 1);

    const ElementSpec* element_spec = schema().element(element_path);
    if (!element_spec) {
      std::vector<std::string> known;
      for (const auto& e : schema().elements)
        if (!e.path.empty()) known.push_back(e.path);
      failOverride(text, "unknown element '" + element_path + "' (expected one of: " + joinList(known) + ")" +
                             didYouMean(element_path, known));
    }
    const AttrSpec* attr = schema().attribute(element_path, name);
    if (!attr)
      failOverride(text, "unknown attribute '" + name + "' of <" + element_spec->tag() +
                             "> (expected one of: " + joinList(attributeNames(element_path)) + ")" +
                             didYouMean(name, attributeNames(element_path)));

    XMLElement* el = m_doc.RootElement();
    std::stringstream segments(element_path);
    std::string segment;
    while (!element_path.empty() && std::getline(segments, segment, '.')) {
      XMLElement* child = el->FirstChildElement(segment.c_str());
      if (!child) {
        child = m_doc.NewElement(segment.c_str());
        el->InsertEndChild(child);
        m_created_by[child] = text;
      }
      el = child;
    }
    // Setting one speed from the command line must not clash with the other in the file.
    if (!attr->one_of.empty())
      for (const AttrSpec* other : schema().attributesOf(element_path))
        if (other != attr && other->one_of == attr->one_of) {
          el->DeleteAttribute(other->name.c_str());
          m_override_of.erase({el, other->name});
        }
    el->SetAttribute(name.c_str(), value.c_str());
    m_override_of[{el, name}] = text;
  }

  static std::vector<std::string> attributeNames(const std::string& element_path) {
    std::vector<std::string> names;
    for (const AttrSpec* a : schema().attributesOf(element_path)) names.push_back(a->name);
    return names;
  }

  // An element-level problem: file:line, or the override that created the element.
  [[noreturn]] void failElement(const XMLElement& el, const std::string& message) const {
    const auto created = m_created_by.find(&el);
    if (el.GetLineNum() == 0 && created != m_created_by.end()) failOverride(created->second, message);
    throw core::InputError(m_source, el.GetLineNum(), message);
  }

  // An attribute-level problem: `<tag attr="value">: message` at the attribute's line, or
  // `--set path=value: message` when an override put the value there.
  [[noreturn]] void failAttribute(const XMLElement& el, const XMLAttribute& attr, const std::string& message) const {
    const auto from_override = m_override_of.find({&el, attr.Name()});
    if (from_override != m_override_of.end()) failOverride(from_override->second, message);
    const int line = attr.GetLineNum() > 0 ? attr.GetLineNum() : el.GetLineNum();
    throw core::InputError(m_source, line,
                           "<" + std::string(el.Name()) + " " + attr.Name() + "=\"" + attr.Value() + "\">: " + message);
  }

  void readElement(const XMLElement& el, const ElementSpec& spec, Scene& scene) {
    const std::string tag = spec.tag();
    if (el.GetLineNum() > 0) scene.element_lines[spec.path.empty() ? kRootTag : spec.path] = el.GetLineNum();
    m_read[spec.path] = &el;
    if (spec.present) spec.present(scene) = true;

    for (const XMLNode* n = el.FirstChild(); n; n = n->NextSibling()) {
      if (!n->ToText()) continue;
      const std::string content = trim(n->Value());
      if (!content.empty())
        throw core::InputError(
            m_source, n->GetLineNum() > 0 ? n->GetLineNum() : el.GetLineNum(),
            "<" + tag + ">: unexpected text '" + content.substr(0, 40) + "' (values go in attributes)");
    }

    for (const XMLAttribute* a = el.FirstAttribute(); a; a = a->Next()) {
      const AttrSpec* attr = schema().attribute(spec.path, a->Name());
      if (!attr) {
        const int line = a->GetLineNum() > 0 ? a->GetLineNum() : el.GetLineNum();
        throw core::InputError(m_source, line,
                               "<" + tag + ">: unknown attribute '" + a->Name() +
                                   "' (expected one of: " + joinList(attributeNames(spec.path)) + ")" +
                                   didYouMean(a->Name(), attributeNames(spec.path)));
      }
      readValue(el, *a, *attr, scene);
    }

    std::map<std::string, std::vector<std::string>> groups;  // one_of tag -> attributes given
    for (const AttrSpec* attr : schema().attributesOf(spec.path)) {
      const bool given = el.Attribute(attr->name.c_str()) != nullptr;
      if (attr->required && !given) failElement(el, "<" + tag + ">: missing required attribute '" + attr->name + "'");
      if (!attr->one_of.empty()) {
        auto& group = groups[attr->one_of];
        if (given) group.push_back(attr->name);
      }
    }
    for (const auto& [group_tag, given] : groups) {
      if (given.size() == 1) continue;
      std::vector<std::string> members;
      for (const AttrSpec* attr : schema().attributesOf(spec.path))
        if (attr->one_of == group_tag) members.push_back(attr->name);
      if (given.empty()) failElement(el, "<" + tag + ">: one of " + joinList(members, " or ") + " is required");
      failElement(el, "<" + tag + ">: " + joinList(given, " and ") + " are mutually exclusive (give only one)");
    }

    const auto children = schema().childrenOf(spec.path);
    std::map<std::string, int> seen;  // tag -> line of its first occurrence
    for (const XMLElement* child = el.FirstChildElement(); child; child = child->NextSiblingElement()) {
      const std::string child_tag = child->Name();
      const ElementSpec* child_spec = schema().element(joinPath(spec.path, child_tag));
      if (!child_spec) failElement(*child, unknownElementText(child_tag, tag, spec.path, children));
      if (const auto first = seen.find(child_tag); first != seen.end())
        failElement(*child, "duplicate element <" + child_tag + "> under <" + tag + "> (first at line " +
                                std::to_string(first->second) + ")");
      seen[child_tag] = child->GetLineNum();
      readElement(*child, *child_spec, scene);
    }
    for (const ElementSpec* child_spec : children)
      if (child_spec->required && !seen.count(child_spec->tag()))
        failElement(el, "<" + tag + ">: missing required element <" + child_spec->tag() + ">");
  }

  static std::string unknownElementText(const std::string& child_tag, const std::string& tag, const std::string& path,
                                        const std::vector<const ElementSpec*>& children) {
    std::vector<std::string> names;
    for (const ElementSpec* c : children) names.push_back(c->tag());
    std::string message = "unknown element <" + child_tag + "> under <" + tag + ">";
    message += names.empty() ? " (it takes no elements)"
                             : " (expected one of: " + joinList(names) + ")" + didYouMean(child_tag, names);
    // A known element in the wrong place is a common slip: say where it belongs.
    for (const auto& e : schema().elements)
      if (!e.path.empty() && e.tag() == child_tag && e.parent() != path)
        message += "; <" + child_tag + "> belongs under <" +
                   (e.parent().empty() ? std::string(kRootTag) : schema().element(e.parent())->tag()) + ">";
    return message;
  }

  void readValue(const XMLElement& el, const XMLAttribute& a, const AttrSpec& attr, Scene& scene) const {
    const std::string_view value = a.Value();
    switch (attr.kind) {
      case Kind::Number: {
        double v = 0.0;
        if (!parseDouble(value, v)) failAttribute(el, a, "expected a number" + unitSuffix(attr.unit));
        if (!attr.bounds.admits(v)) failAttribute(el, a, mustBe(attr.bounds) + unitSuffix(attr.unit));
        attr.number(scene) = v;
        break;
      }
      case Kind::Integer: {
        int v = 0;
        if (!parseInt(value, v)) failAttribute(el, a, "expected an integer" + unitSuffix(attr.unit));
        if (!attr.bounds.admits(v)) failAttribute(el, a, mustBe(attr.bounds) + unitSuffix(attr.unit));
        attr.integer(scene) = v;
        break;
      }
      case Kind::Seed: {
        std::uint64_t v = 0;
        if (!parseUint64(value, v)) failAttribute(el, a, "expected an integer in [0, 18446744073709551615]");
        attr.seed(scene) = v;
        break;
      }
      case Kind::Flag: {
        if (value == "true")
          attr.flag(scene) = true;
        else if (value == "false")
          attr.flag(scene) = false;
        else
          failAttribute(el, a, "expected true or false");
        break;
      }
      case Kind::Choice: {
        bool known = false;
        for (const auto& c : attr.choices) known = known || value == c;
        if (!known) failAttribute(el, a, "expected one of " + joinList(attr.choices));
        attr.text(scene) = std::string(value);
        break;
      }
      case Kind::Text: {
        if (trim(value).empty()) failAttribute(el, a, "must not be empty");
        attr.text(scene) = std::string(value);
        break;
      }
    }
  }

  void runCrossChecks(const Scene& scene) const {
    for (const CrossCheck& check : schema().checks) {
      const std::string message = check.violation(scene);
      if (message.empty()) continue;
      const auto read = m_read.find(check.element);
      if (read != m_read.end()) {
        if (const XMLAttribute* a = read->second->FindAttribute(check.name.c_str()))
          failAttribute(*read->second, *a, message);
      }
      // The value is the Scene default: blame the element it belongs in, or the nearest
      // ancestor that is in the file.
      std::string path = check.element;
      while (!path.empty() && !m_read.count(path)) path = schema().element(path)->parent();
      const XMLElement* el = m_read.at(path);
      Scene defaults;
      const AttrSpec* attr = schema().attribute(check.element, check.name);
      failElement(*el, check.element + "." + check.name + " = " + formatNumber(attr->number(defaults)) +
                           " (default): " + message);
    }
  }

  std::string m_source;
  XMLDocument m_doc;
  // Values and elements put there by --set, so their errors name the override, not a line.
  std::map<std::pair<const XMLElement*, std::string>, std::string> m_override_of;
  std::map<const XMLElement*, std::string> m_created_by;
  std::map<std::string, const XMLElement*> m_read;  // element path -> element read
};

std::string markdownCell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string kindName(Kind k) {
  switch (k) {
    case Kind::Number:
      return "number";
    case Kind::Integer:
      return "integer";
    case Kind::Flag:
      return "boolean";
    case Kind::Choice:
      return "choice";
    case Kind::Text:
      return "text";
    case Kind::Seed:
      return "integer (64-bit)";
  }
  return "?";
}

std::string allowedText(const AttrSpec& a) {
  switch (a.kind) {
    case Kind::Number:
    case Kind::Integer:
      return boundsText(a.bounds);
    case Kind::Flag:
      return "`true`, `false`";
    case Kind::Choice: {
      std::vector<std::string> quoted;
      for (const auto& c : a.choices) quoted.push_back("`" + c + "`");
      return joinList(quoted);
    }
    case Kind::Text:
      return "non-empty";
    case Kind::Seed:
      return "[0, 2^64 - 1]";
  }
  return "";
}

std::string defaultText(const AttrSpec& a) {
  if (!a.default_note.empty()) return a.default_note;
  Scene defaults;
  switch (a.kind) {
    case Kind::Number:
      return formatNumber(a.number(defaults));
    case Kind::Integer:
      return std::to_string(a.integer(defaults));
    case Kind::Flag:
      return a.flag(defaults) ? "true" : "false";
    case Kind::Choice:
    case Kind::Text:
      return a.text(defaults);
    case Kind::Seed:
      return std::to_string(a.seed(defaults));
  }
  return "";
}

}  // namespace

Scene loadCaseText(const std::string& xml, const std::string& source_name, const std::vector<std::string>& overrides) {
  return CaseReader(source_name).read(xml, overrides);
}

Scene loadCaseFile(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  // A directory opens as a stream on Linux and then reads as empty; reject it up front.
  if (!std::filesystem::is_regular_file(path, ec)) throw core::InputError(path + ": cannot open case file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError(path + ": cannot open case file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw core::InputError(path + ": cannot read case file");
  return loadCaseText(text.str(), path, overrides);
}

std::string describeCaseFormat() {
  const Schema& s = schema();
  std::ostringstream md;
  md << "| Element | Path | Required | Description |\n|---|---|---|---|\n";
  for (const auto& e : s.elements) {
    std::string nested;
    for (std::string p = e.path; !p.empty(); p = s.element(p)->parent())
      nested = "<" + s.element(p)->tag() + ">" + nested;
    md << "| `" << (e.path.empty() ? "<millsim>" : "<millsim>" + nested) << "` | "
       << (e.path.empty() ? "(root)" : "`" + e.path + "`") << " | "
       << (e.required                ? "yes"
           : e.required_with.empty() ? "no"
                                     : "with <" + s.element(e.required_with)->tag() + ">" +
                                           (e.unless.empty() ? "" : " unless <" + s.element(e.unless)->tag() + ">"))
       << " | " << markdownCell(e.description) << " |\n";
  }
  md << "\n| Attribute (`--set` path) | Type | Unit | Default | Allowed | Description |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& a : s.attributes)
    md << "| `" << a.path() << "` | " << kindName(a.kind) << " | " << (a.unit.empty() ? "-" : a.unit) << " | "
       << markdownCell(defaultText(a)) << " | " << markdownCell(allowedText(a)) << " | " << markdownCell(a.description)
       << " |\n";
  md << "\nRules over more than one attribute:\n\n";
  std::map<std::string, std::vector<std::string>> groups;
  for (const auto& a : s.attributes)
    if (!a.one_of.empty()) groups[a.element + "\n" + a.one_of].push_back("`" + a.path() + "`");
  for (const auto& [key, members] : groups)
    md << "- exactly one of " << joinList(members, " and ") << " is given (a `--set` of one removes the other)\n";
  for (const auto& c : s.checks) md << "- " << c.rule << "\n";
  return md.str();
}

std::vector<std::string> caseAttributePaths() {
  std::vector<std::string> out;
  for (const auto& a : schema().attributes) out.push_back(a.path());
  return out;
}

}  // namespace millsim::io
