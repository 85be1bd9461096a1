// Issue 4, Done-when 7: bad SPH parameters stop with one line naming file:line, the element and
// the attribute, and what is expected.
#include <gtest/gtest.h>

#include <string>

#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"
#include "sph/sph_engine.hpp"

namespace millsim {
namespace {

// Lines: millsim 1, time 2, sph 3, fluid 4, tank 5, probes 6.
std::string fluidCase(const std::string& sph_attrs, const std::string& probes = "bottom:0.05,0.005") {
  return "<millsim name=\"t\">\n"
         "  <time end=\"0.01\"/>\n"
         "  <sph dp=\"0.01\" " + sph_attrs + "/>\n"
         "  <fluid x_min=\"0\" y_min=\"0\" x_max=\"0.1\" y_max=\"0.1\"/>\n"
         "  <tank x_min=\"0\" y_min=\"0\" x_max=\"0.2\" y_max=\"0.15\"/>\n"
         "  <probes points=\"" + probes + "\"/>\n"
         "</millsim>\n";
}

std::string failure(const std::string& xml) {
  try {
    const scene::Scene s = io::loadCaseText(xml, "t.xml");
    sim::RunOptions opt;
    opt.write_outputs = false;
    sim::Simulation simulation(s, opt);  // set-up checks (probes, geometry) happen here
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SphCaseErrors, EachBadParameterNamesFileLineAndRule) {
  EXPECT_EQ(failure(fluidCase("dimension=\"2\"")), "(no error)");
  const std::string dp0 = "<millsim name=\"t\">\n  <time end=\"1\"/>\n  <sph dp=\"0\"/>\n"
                          "  <fluid x_min=\"0\" y_min=\"0\" x_max=\"0.1\" y_max=\"0.1\"/>\n</millsim>\n";
  EXPECT_EQ(failure(dp0), "t.xml:3: <sph dp=\"0\">: must be > 0 (m)");
  const std::string dp_neg = dp0.substr(0, dp0.find("dp=\"0\"")) + "dp=\"-0.01\"" + dp0.substr(dp0.find("dp=\"0\"") + 6);
  EXPECT_EQ(failure(dp_neg), "t.xml:3: <sph dp=\"-0.01\">: must be > 0 (m)");
  EXPECT_EQ(failure(fluidCase("coefh=\"0.5\"")),
            "t.xml:3: <sph coefh=\"0.5\">: gives h = 0.7071067811865476 dp, smaller than dp: must be >= "
            "0.7071067811865475");
  EXPECT_EQ(failure(fluidCase("cfl=\"0\"")), "t.xml:3: <sph cfl=\"0\">: must be in (0, 1]");
  EXPECT_EQ(failure(fluidCase("cfl=\"1.5\"")), "t.xml:3: <sph cfl=\"1.5\">: must be in (0, 1]");
  EXPECT_EQ(failure(fluidCase("rhop_out_min=\"1300\" rhop_out_max=\"1300\"")),
            "t.xml:3: <sph rhop_out_max=\"1300\">: must be > sph.rhop_out_min = 1300 (kg/m^3)");
  // rho0 itself (the default 1000) outside the limits: the element is blamed, with the default.
  EXPECT_EQ(failure(fluidCase("rhop_out_min=\"1100\"")),
            "t.xml:3: sph.rho0 = 1000 (default): must lie between sph.rhop_out_min and sph.rhop_out_max");
}

TEST(SphCaseErrors, BadProbesAndEmptyFluid) {
  EXPECT_EQ(failure(fluidCase("", "bottom:0.05")),
            "t.xml:6: <probes points=\"bottom:0.05\">: 'bottom:0.05': expected name:x,y[,z]");
  EXPECT_EQ(failure(fluidCase("", "a:0.1,x")), "t.xml:6: <probes points=\"a:0.1,x\">: 'a:0.1,x': 'x' is not a number");
  EXPECT_EQ(failure(fluidCase("", "a:0,0;a:1,1")),
            "t.xml:6: <probes points=\"a:0,0;a:1,1\">: probe name 'a' given twice");
  EXPECT_EQ(failure(fluidCase("dp=\"0.5\"").replace(fluidCase("dp=\"0.5\"").find("dp=\"0.01\" "), 10, "")),
            "t.xml:4: <fluid>: the box holds no particle at dp = 0.500000 m (is it smaller than dp?)");
}

// A library caller's SphSetup with a name the solver does not know is refused, naming the field
// and the names it takes (a misspelt boundary ran as DBC walls before).
TEST(SphCaseErrors, UnknownSetupChoiceIsRefused) {
  sph::SphSetup s;
  s.dp = 0.01;
  s.h = 0.0113;
  s.c0 = 10;
  s.domain_lo = {0, 0, 0};
  s.domain_hi = {1, 1, 0};
  EXPECT_NO_THROW(sph::makeSphEngineOmp(s));
  auto failure = [](const sph::SphSetup& bad) {
    try {
      sph::makeSphEngineOmp(bad);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  sph::SphSetup b = s;
  b.boundary = "mDBC";
  EXPECT_EQ(failure(b), "sph: boundary = 'mDBC' is not one of: dbc, mdbc");
  b = s;
  b.kernel = "quintic";
  EXPECT_EQ(failure(b), "sph: kernel = 'quintic' is not one of: wendland, cubic");
  b = s;
  b.viscosity = "sps";
  EXPECT_EQ(failure(b), "sph: viscosity = 'sps' is not one of: artificial, laminar, laminar_sps, laminar_central");
}

// Issue 4: only what the scene calls for. A fluid-only case has no DEM arrays and no DEM stage;
// options that are off allocate nothing (no shifting arrays without shifting, no SPS stress
// without laminar_sps, no symplectic copies with Verlet).
TEST(SphScene, FluidOnlyRunHasNoDemAndNoUnusedArrays) {
  sim::RunOptions opt;
  opt.write_outputs = false;
  sim::Simulation plain(io::loadCaseText(fluidCase(""), "t.xml"), opt);
  for (const auto& [group, bytes] : plain.memoryReport()) {
    EXPECT_EQ(group.rfind("dem", 0), std::string::npos) << group;
    if (group == "sph.shifting" || group == "sph.sps") {
      EXPECT_EQ(bytes, 0u) << group;
    }
  }
  for (const auto& stage : plain.stages()) EXPECT_EQ(stage.find("dem"), std::string::npos) << stage;
  sim::Simulation full(
      io::loadCaseText(fluidCase("shifting=\"full\" viscosity=\"laminar_sps\" integrator=\"symplectic\""), "t.xml"),
      opt);
  const auto mem = full.memoryReport();
  EXPECT_GT(mem.at("sph.shifting"), 0u);
  EXPECT_GT(mem.at("sph.sps"), 0u);
  EXPECT_GT(mem.at("sph.integrator"), plain.memoryReport().at("sph.integrator"));  // 3 copies instead of 2
}

}  // namespace
}  // namespace millsim
