// Case XML reader: the shipped cases parse to the paper's values, and every kind of bad input
// fails with the file:line (or --set) message a user would need to fix it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"

namespace {

using millsim::core::InputError;
using millsim::io::caseAttributePaths;
using millsim::io::defaultCaseXml;
using millsim::io::describeCaseFormat;
using millsim::io::loadCaseFile;
using millsim::io::loadCaseText;
using millsim::scene::Scene;

const std::filesystem::path kCases = std::filesystem::path(MILLSIM_SOURCE_DIR) / "cases";

std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// 1-based line of the first line of `text` that contains `needle`, so the expected lines of the
// shipped cases follow edits of their comment headers.
int lineOf(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  return -1;
}

// Lines: millsim 1, time 2, dem 3, drum 4, lifters 5.
const char* const kSmall = R"(<millsim name="small">
  <time end="1"/>
  <dem/>
  <drum diameter="0.1" length="0.04" speed_rpm="40">
    <lifters count="4" height="0.004"/>
  </drum>
</millsim>
)";

// Replaces the first occurrence of `from` in kSmall.
std::string small(const std::string& from, const std::string& to) {
  std::string s = kSmall;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

struct Failure {
  std::string what;
  int line = -1;
};

Failure failureOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return {e.what(), e.line()};
  }
  return {"(no InputError)", -1};
}

Failure textFailure(const std::string& xml, const std::vector<std::string>& overrides = {}) {
  return failureOf([&] { loadCaseText(xml, "t.xml", overrides); });
}

TEST(CaseXml, DefaultCaseIsTheFileByteForByte) {
  EXPECT_EQ(std::string(defaultCaseXml()), readFile(kCases / "ball_mill_300_balls.xml"));
}

TEST(CaseXml, EveryShippedCaseParses) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kCases)) {
    if (entry.path().extension() != ".xml") continue;
    ++count;
    SCOPED_TRACE(entry.path().string());
    Scene s;
    ASSERT_NO_THROW(s = loadCaseFile(entry.path().string()));
    EXPECT_EQ(s.name, entry.path().stem().string());  // root name matches the file name
    EXPECT_EQ(s.source, entry.path().string());
    // A balls case has its drum (or its stirred chamber), a fluid case its fluid.
    EXPECT_TRUE(s.effect_dem || s.effect_sph);
    if (s.effect_dem) {
      EXPECT_TRUE(s.has_drum || s.has_stirrer);
    }
    if (s.effect_sph) {
      EXPECT_TRUE(s.effect_dem ? s.has_slurry : s.has_fluid);
    }
  }
  EXPECT_GE(count, 7);
}

TEST(CaseXml, PaperCaseValuesLandInScene) {
  const auto path = kCases / "ball_mill_300_balls.xml";
  const Scene s = loadCaseFile(path.string());
  EXPECT_EQ(s.name, "ball_mill_300_balls");
  EXPECT_DOUBLE_EQ(s.time.end, 12.0);
  EXPECT_EQ(s.time.dt_mode, "auto");
  EXPECT_DOUBLE_EQ(s.time.dt_divisor, 50.0);
  EXPECT_DOUBLE_EQ(s.time.dt_fixed, 1e-5);
  EXPECT_DOUBLE_EQ(s.gravity[0], 0.0);
  EXPECT_DOUBLE_EQ(s.gravity[1], -9.81);
  EXPECT_DOUBLE_EQ(s.gravity[2], 0.0);
  EXPECT_DOUBLE_EQ(s.output.series_every, 0.01);
  EXPECT_DOUBLE_EQ(s.output.fields_every, 0.5);
  EXPECT_DOUBLE_EQ(s.output.checkpoint_every, 1.0);
  EXPECT_DOUBLE_EQ(s.dem.youngs_modulus, 1e8);
  EXPECT_DOUBLE_EQ(s.dem.poisson, 0.29);
  EXPECT_DOUBLE_EQ(s.dem.density, 7800.92);
  EXPECT_DOUBLE_EQ(s.dem.restitution, 0.390);
  EXPECT_DOUBLE_EQ(s.dem.friction, 0.496);
  EXPECT_EQ(s.dem.damping, "exact");
  EXPECT_EQ(s.dem.friction_smoothing, "none");
  EXPECT_DOUBLE_EQ(s.dem.impact_velocity, 2.0);
  EXPECT_DOUBLE_EQ(s.drum.diameter, 0.292);
  EXPECT_DOUBLE_EQ(s.drum.length, 0.15);
  EXPECT_DOUBLE_EQ(s.drum.speed_rpm, 24.8);
  EXPECT_DOUBLE_EQ(s.drum.critical_fraction, 0.0);
  EXPECT_DOUBLE_EQ(s.drum.start_time, 2.0);
  EXPECT_DOUBLE_EQ(s.drum.spin_up, 0.0);
  EXPECT_EQ(s.drum.lifters.count, 8);
  EXPECT_DOUBLE_EQ(s.drum.lifters.height, 0.005);
  EXPECT_DOUBLE_EQ(s.drum.lifters.width, 0.005);
  EXPECT_DOUBLE_EQ(s.charge.filling, 0.3);
  EXPECT_DOUBLE_EQ(s.charge.top_size, 0.035);
  EXPECT_DOUBLE_EQ(s.charge.min_size, 0.015);
  EXPECT_DOUBLE_EQ(s.charge.size_step, 0.005);
  EXPECT_DOUBLE_EQ(s.charge.bond_exponent, 3.8);
  EXPECT_EQ(s.charge.seed, 1u);
  EXPECT_EQ(s.charge.count_override, 0);
  EXPECT_DOUBLE_EQ(s.compaction.duration, 2.0);
  EXPECT_DOUBLE_EQ(s.compaction.length_factor, 3.0);
  EXPECT_TRUE(s.angle.enabled);
  EXPECT_DOUBLE_EQ(s.angle.start_time, 4.0);
  EXPECT_EQ(s.angle.frames, 100);
  EXPECT_DOUBLE_EQ(s.angle.pixels_per_mm, 2.0);
  EXPECT_DOUBLE_EQ(s.angle.threshold, 0.5);
  EXPECT_EQ(s.angle.smoothing_px, 5);
  EXPECT_DOUBLE_EQ(s.angle.fit_offset_mm, 60.0);
  EXPECT_DOUBLE_EQ(s.angle.fit_length_mm, 0.0);
  EXPECT_TRUE(s.effect_dem);
  EXPECT_FALSE(s.effect_sph);

  const std::string text = readFile(path);
  const std::vector<std::pair<std::string, std::string>> keys = {{"millsim", "<millsim "},
                                                                 {"time", "<time "},
                                                                 {"gravity", "<gravity "},
                                                                 {"output", "<output "},
                                                                 {"dem", "<dem "},
                                                                 {"drum", "<drum "},
                                                                 {"drum.lifters", "<lifters "},
                                                                 {"charge", "<charge "},
                                                                 {"compaction", "<compaction "},
                                                                 {"angle_of_repose", "<angle_of_repose "}};
  EXPECT_EQ(s.element_lines.size(), keys.size());
  for (const auto& [key, needle] : keys) {
    ASSERT_TRUE(s.element_lines.count(key)) << key;
    EXPECT_EQ(s.element_lines.at(key), lineOf(text, needle)) << key;
  }
}

TEST(CaseXml, TheThreeDrumsDifferInSizeAndSpeed) {
  struct Expected {
    const char* file;
    double diameter, rpm, min_size;
  };
  for (const Expected& e : {Expected{"ball_mill_300_balls.xml", 0.292, 24.8, 0.015},
                            Expected{"ball_mill_400_balls.xml", 0.392, 21.1, 0.020},
                            Expected{"ball_mill_500_balls.xml", 0.492, 18.7, 0.025}}) {
    SCOPED_TRACE(e.file);
    const Scene s = loadCaseFile((kCases / e.file).string());
    EXPECT_DOUBLE_EQ(s.drum.diameter, e.diameter);
    EXPECT_DOUBLE_EQ(s.drum.speed_rpm, e.rpm);
    EXPECT_DOUBLE_EQ(s.charge.min_size, e.min_size);
    EXPECT_DOUBLE_EQ(s.charge.top_size, 0.035);
    EXPECT_DOUBLE_EQ(s.time.end, 12.0);
    EXPECT_DOUBLE_EQ(s.drum.start_time, 2.0);
    EXPECT_DOUBLE_EQ(s.compaction.duration, 2.0);
  }
}

TEST(CaseXml, MinimalDrumIsSmall) {
  const Scene s = loadCaseFile((kCases / "minimal_drum.xml").string());
  EXPECT_DOUBLE_EQ(s.drum.diameter, 0.1);
  EXPECT_DOUBLE_EQ(s.drum.length, 0.04);
  EXPECT_DOUBLE_EQ(s.drum.critical_fraction, 0.3);
  EXPECT_EQ(s.charge.count_override, 20);
  EXPECT_DOUBLE_EQ(s.charge.min_size, 0.01);
  EXPECT_DOUBLE_EQ(s.charge.top_size, 0.01);
  EXPECT_DOUBLE_EQ(s.time.end, 1.0);
  EXPECT_DOUBLE_EQ(s.compaction.duration, 0.3);
  EXPECT_DOUBLE_EQ(s.drum.start_time, 0.3);
  EXPECT_FALSE(s.angle.enabled);
}

TEST(CaseXml, DefaultCaseTextParsesLikeTheFile) {
  const Scene a = loadCaseText(defaultCaseXml(), "<embedded>");
  const Scene b = loadCaseFile((kCases / "ball_mill_300_balls.xml").string());
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.source, "<embedded>");
  EXPECT_EQ(a.element_lines, b.element_lines);
  EXPECT_DOUBLE_EQ(a.drum.diameter, b.drum.diameter);
}

TEST(CaseXml, AbsentAttributesAndElementsKeepSceneDefaults) {
  const Scene s = loadCaseText(kSmall, "dir/t.xml");
  const Scene defaults;
  EXPECT_EQ(s.name, "small");
  EXPECT_EQ(s.source, "dir/t.xml");
  EXPECT_DOUBLE_EQ(s.time.end, 1.0);
  EXPECT_DOUBLE_EQ(s.time.dt_divisor, defaults.time.dt_divisor);
  EXPECT_DOUBLE_EQ(s.output.series_every, defaults.output.series_every);
  EXPECT_DOUBLE_EQ(s.dem.restitution, defaults.dem.restitution);
  EXPECT_DOUBLE_EQ(s.charge.filling, defaults.charge.filling);
  EXPECT_DOUBLE_EQ(s.drum.lifters.width, defaults.drum.lifters.width);
  EXPECT_EQ(s.drum.lifters.count, 4);
  EXPECT_TRUE(s.effect_dem);
  const std::map<std::string, int> lines = {{"millsim", 1}, {"time", 2}, {"dem", 3}, {"drum", 4}, {"drum.lifters", 5}};
  EXPECT_EQ(s.element_lines, lines);
}

TEST(CaseXml, NameDefaultsToFileStemAndDemToAbsent) {
  const char* const fluid_only = R"(<millsim>
  <time end="1"/>
  <sph dp="0.01"/>
  <fluid x_min="0" y_min="0" x_max="0.1" y_max="0.1"/>
</millsim>
)";
  const Scene s = loadCaseText(fluid_only, "cases/my_case.xml");
  EXPECT_EQ(s.name, "my_case");
  EXPECT_FALSE(s.effect_dem);
  EXPECT_TRUE(s.effect_sph);
  EXPECT_FALSE(s.has_drum);
  EXPECT_FALSE(s.has_tank);
}

TEST(CaseXmlErrors, NothingToSimulate) {
  std::string xml = small("<millsim name=\"small\">", "<millsim>");
  xml = xml.replace(xml.find("  <dem/>\n"), 9, "");
  EXPECT_EQ(textFailure(xml).what, "t.xml:1: <millsim>: nothing to simulate: the case has neither <dem> nor <sph>");
}

TEST(CaseXmlErrors, EffectWithoutItsGeometry) {
  const std::string no_drum = R"(<millsim>
  <time end="1"/>
  <dem/>
</millsim>
)";
  EXPECT_EQ(textFailure(no_drum).what, "t.xml:3: <dem> needs a <drum> element in the case");
  const std::string no_fluid = R"(<millsim>
  <time end="1"/>
  <sph dp="0.01"/>
</millsim>
)";
  EXPECT_EQ(textFailure(no_fluid).what, "t.xml:3: <sph> needs a <fluid> element in the case");
}

TEST(CaseXml, CriticalFractionInsteadOfRpm) {
  const Scene s = loadCaseText(small("speed_rpm=\"40\"", "critical_fraction=\"0.3\""), "t.xml");
  EXPECT_DOUBLE_EQ(s.drum.critical_fraction, 0.3);
}

TEST(CaseXml, NumbersAreParsedStrictlyButAcceptAPlusSign) {
  EXPECT_DOUBLE_EQ(loadCaseText(small("end=\"1\"", "end=\"+2.5e0\""), "t.xml").time.end, 2.5);
  for (const char* bad : {"1e8x", " 1", "1 ", "", "nan", "inf", "1,5", "0x10", "--1", "+-1"}) {
    SCOPED_TRACE(bad);
    const Failure f = textFailure(small("end=\"1\"", std::string("end=\"") + bad + "\""));
    EXPECT_EQ(f.what, std::string("t.xml:2: <time end=\"") + bad + "\">: expected a number (s)");
  }
}

// ---- errors: each names file:line, element, attribute and what was expected ---------------------

TEST(CaseXmlErrors, MissingFile) {
  const Failure f = failureOf([] { loadCaseFile("/nonexistent/x.xml"); });
  EXPECT_EQ(f.what, "/nonexistent/x.xml: cannot open case file");
  const Failure dir = failureOf([] { loadCaseFile(kCases.string()); });
  EXPECT_EQ(dir.what, kCases.string() + ": cannot open case file");
}

TEST(CaseXmlErrors, MalformedXmlGivesTheLineOfTheError) {
  const Failure quote = textFailure(small("<dem/>", "<dem youngs_modulus=\"1e8/>"));
  EXPECT_EQ(quote.line, 3);
  EXPECT_EQ(quote.what,
            "t.xml:3: malformed XML: cannot parse an element tag (an unclosed quote or a stray "
            "'<'?)");

  const Failure twice = textFailure(small("<dem/>", "<dem poisson=\"0.3\" poisson=\"0.2\"/>"));
  EXPECT_EQ(twice.what,
            "t.xml:3: malformed XML: cannot parse an attribute (missing quotes or '=', or the "
            "same attribute twice) in <dem>");
  EXPECT_EQ(twice.what.find("Error="), std::string::npos) << "tinyxml2's raw text leaked";

  const Failure mismatch = textFailure(small("  </drum>", "  </drun>"));
  EXPECT_EQ(mismatch.what, "t.xml:4: malformed XML: end tag does not match the open element in <drum>");

  const Failure empty = textFailure("");
  EXPECT_EQ(empty.what, "t.xml:1: malformed XML: the document is empty");
}

TEST(CaseXmlErrors, RootAndStrayContent) {
  EXPECT_EQ(textFailure("<case>\n</case>\n").what, "t.xml:1: root element is <case>, expected <millsim>");
  EXPECT_EQ(textFailure(std::string(kSmall) + "<millsim/>\n").what,
            "t.xml:8: unexpected element <millsim> after </millsim> (a case has one root)");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem>1e8</dem>")).what,
            "t.xml:3: <dem>: unexpected text '1e8' (values go in attributes)");
}

TEST(CaseXmlErrors, MissingRequiredAttribute) {
  const Failure f = textFailure(small("<time end=\"1\"/>", "<time dt=\"auto\"/>"));
  EXPECT_EQ(f.what, "t.xml:2: <time>: missing required attribute 'end'");
  EXPECT_EQ(f.line, 2);
}

TEST(CaseXmlErrors, MissingRequiredElement) {
  std::string xml = kSmall;
  xml.replace(xml.find("  <time end=\"1\"/>\n"), 18, "");
  EXPECT_EQ(textFailure(xml).what, "t.xml:1: <millsim>: missing required element <time>");
}

TEST(CaseXmlErrors, NegativeDiameter) {
  const Failure f = textFailure(small("diameter=\"0.1\"", "diameter=\"-0.3\""));
  EXPECT_EQ(f.what, "t.xml:4: <drum diameter=\"-0.3\">: must be > 0 (m)");
  EXPECT_EQ(f.line, 4);
}

TEST(CaseXmlErrors, BoundsWithBothEnds) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem poisson=\"0.5\"/>")).what,
            "t.xml:3: <dem poisson=\"0.5\">: must be in [0, 0.5)");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem restitution=\"0\"/>")).what,
            "t.xml:3: <dem restitution=\"0\">: must be in (0, 1]");
  EXPECT_NO_THROW(loadCaseText(small("<dem/>", "<dem restitution=\"1\" poisson=\"0\"/>"), "t.xml"));
  // A zero skin would rebuild the neighbour list every step and miss pairs that close in it.
  EXPECT_EQ(textFailure(small("<dem/>", "<dem skin=\"0\"/>")).what,
            "t.xml:3: <dem skin=\"0\">: must be in (0, 20] (r_min)");
}

TEST(CaseXmlErrors, AttributeErrorsUseTheAttributesOwnLine) {
  const Failure f = textFailure(small("<dem/>", "<dem youngs_modulus=\"1e8\"\n       poisson=\"0.6\"/>"));
  EXPECT_EQ(f.what, "t.xml:4: <dem poisson=\"0.6\">: must be in [0, 0.5)");
}

TEST(CaseXmlErrors, UnknownAttribute) {
  const Failure f = textFailure(small("<dem/>", "<dem/>\n  <charge filing=\"0.3\"/>"));
  EXPECT_EQ(f.what,
            "t.xml:4: <charge>: unknown attribute 'filing' (expected one of: filling, top_size, "
            "min_size, size_step, bond_exponent, seed, count); did you mean 'filling'?");
  // No hint when nothing is close.
  EXPECT_EQ(textFailure(small("<dem/>", "<dem colour=\"red\"/>")).what.find("did you mean"), std::string::npos);
}

TEST(CaseXmlErrors, UnknownElement) {
  const Failure f = textFailure(small("<dem/>", "<drums/>"));
  EXPECT_EQ(f.what,
            "t.xml:3: unknown element <drums> under <millsim> (expected one of: time, gravity, "
            "output, dem, drum, charge, compaction, angle_of_repose, sph, fluid, slurry, tank, probes, stirrer, "
            "beads, lubrication, collisions); did you mean "
            "'drum'?");
  const Failure misplaced = textFailure(small("<dem/>", "<lifters/>"));
  EXPECT_NE(misplaced.what.find("; <lifters> belongs under <drum>"), std::string::npos) << misplaced.what;
  EXPECT_EQ(textFailure(small("<lifters count", "<lifters><x/></lifters><z count")).what,
            "t.xml:5: unknown element <x> under <lifters> (it takes no elements)");
}

TEST(CaseXmlErrors, DuplicateElement) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem/>\n  <dem/>")).what,
            "t.xml:4: duplicate element <dem> under <millsim> (first at line 3)");
}

TEST(CaseXmlErrors, BadChoice) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem damping=\"foo\"/>")).what,
            "t.xml:3: <dem damping=\"foo\">: expected one of exact, dualsphysics");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem damping=\"Exact\"/>")).line, 3);
}

TEST(CaseXmlErrors, BadBoolean) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem/><angle_of_repose enabled=\"yes\"/>")).what,
            "t.xml:3: <angle_of_repose enabled=\"yes\">: expected true or false");
}

TEST(CaseXmlErrors, BothOrNeitherSpeed) {
  const Failure both = textFailure(small("speed_rpm=\"40\"", "speed_rpm=\"40\" critical_fraction=\"0.3\""));
  EXPECT_EQ(both.what,
            "t.xml:4: <drum>: speed_rpm and critical_fraction are mutually exclusive (give only "
            "one)");
  EXPECT_EQ(both.line, 4);
  EXPECT_EQ(textFailure(small(" speed_rpm=\"40\"", "")).what,
            "t.xml:4: <drum>: one of speed_rpm or critical_fraction is required");
}

TEST(CaseXmlErrors, NumberWithTrailingJunk) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem youngs_modulus=\"1e8x\"/>")).what,
            "t.xml:3: <dem youngs_modulus=\"1e8x\">: expected a number (Pa)");
}

TEST(CaseXmlErrors, IntegerWithDecimals) {
  EXPECT_EQ(textFailure(small("count=\"4\"", "count=\"2.5\"")).what,
            "t.xml:5: <lifters count=\"2.5\">: expected an integer");
  EXPECT_EQ(textFailure(small("count=\"4\"", "count=\"1e1\"")).line, 5);
  EXPECT_EQ(textFailure(small("count=\"4\"", "count=\"99999999999\"")).line, 5);
  EXPECT_EQ(textFailure(small("<dem/>", "<dem/><charge seed=\"-1\"/>")).what,
            "t.xml:3: <charge seed=\"-1\">: expected an integer in [0, 18446744073709551615]");
}

// DCDEM balls need elements across the smallest ball, and are not coupled to a fluid yet.
TEST(CaseXmlErrors, DcdemBallsChecks) {
  EXPECT_EQ(textFailure(small("<dem/>", "<dem representation=\"dcdem\" element_spacing=\"0.01\"/>")).what,
            "t.xml:3: <dem element_spacing=\"0.01\">: must be <= charge.min_size / 3 = 0.005 (m): the smallest ball "
            "needs elements across it");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem representation=\"dcdem\"/>"), {"dem.element_spacing=0.006"}).what,
            "--set dem.element_spacing=0.006: must be <= charge.min_size / 3 = 0.005 (m): the smallest ball needs "
            "elements across it");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem representation=\"blob\"/>")).what,
            "t.xml:3: <dem representation=\"blob\">: expected one of sphere, dcdem");
  EXPECT_EQ(loadCaseText(small("<dem/>", "<dem representation=\"dcdem\"/>"), "t.xml").dem.element_spacing, 0.005);
}

TEST(CaseXmlErrors, CrossFieldChecks) {
  EXPECT_EQ(textFailure(small("height=\"0.004\"", "height=\"0.025\"")).what,
            "t.xml:5: <lifters height=\"0.025\">: must be < drum.diameter / 4 = 0.025 (m)");
  EXPECT_EQ(textFailure(small("<dem/>", "<dem/><charge top_size=\"0.01\" min_size=\"0.02\"/>")).what,
            "t.xml:3: <charge min_size=\"0.02\">: must be <= charge.top_size = 0.01 (m)");
  // A default that a changed attribute invalidates is blamed on the element it belongs in.
  EXPECT_EQ(textFailure(small("<dem/>", "<dem/><charge top_size=\"0.01\"/>")).what,
            "t.xml:3: charge.min_size = 0.015 (default): must be <= charge.top_size = 0.01 (m)");
}

// The ghost-node no-slip velocity needs the ghost nodes mDBC keeps.
TEST(CaseXmlErrors, NoSlipGhostNeedsMdbc) {
  const std::string file = (kCases / "dam_break_2d.xml").string();
  const Failure f = failureOf([&] { loadCaseFile(file, {"sph.wall_velocity=no_slip_ghost"}); });
  EXPECT_EQ(f.what,
            "--set sph.wall_velocity=no_slip_ghost: no_slip_ghost takes the velocity at mDBC ghost nodes: it needs "
            "sph.boundary = mdbc");
  EXPECT_EQ(loadCaseFile(file, {"sph.wall_velocity=no_slip_ghost", "sph.boundary=mdbc"}).sph.wall_velocity,
            "no_slip_ghost");
}

// ---- --set overrides ---------------------------------------------------------------------------

TEST(CaseXmlOverrides, ChangeExistingValues) {
  const Scene s = loadCaseText(
      kSmall, "t.xml",
      {"time.end=2", "drum.lifters.count=6", "dem.damping=dualsphysics", "name=renamed", "gravity.y=-1.62"});
  EXPECT_DOUBLE_EQ(s.time.end, 2.0);
  EXPECT_EQ(s.drum.lifters.count, 6);
  EXPECT_EQ(s.dem.damping, "dualsphysics");
  EXPECT_EQ(s.name, "renamed");
  EXPECT_DOUBLE_EQ(s.gravity[1], -1.62);
  // Validation and lines are those of the file.
  EXPECT_EQ(s.element_lines.at("drum.lifters"), 5);
}

TEST(CaseXmlOverrides, LastOneWins) {
  EXPECT_DOUBLE_EQ(loadCaseText(kSmall, "t.xml", {"time.end=2", "time.end=3"}).time.end, 3.0);
}

TEST(CaseXmlOverrides, CreateMissingElements) {
  std::string xml = kSmall;
  xml.replace(xml.find("  <dem/>\n"), 9, "");
  xml.replace(xml.find("    <lifters count=\"4\" height=\"0.004\"/>\n"), 41, "");
  const Scene s = loadCaseText(xml, "t.xml", {"charge.count=7", "drum.lifters.count=2", "dem.friction=0.3"});
  EXPECT_EQ(s.charge.count_override, 7);
  EXPECT_EQ(s.drum.lifters.count, 2);
  EXPECT_DOUBLE_EQ(s.dem.friction, 0.3);
  EXPECT_TRUE(s.effect_dem);  // <dem> now exists
  // Created elements have no line in the file.
  EXPECT_FALSE(s.element_lines.count("charge"));
  EXPECT_FALSE(s.element_lines.count("drum.lifters"));
}

TEST(CaseXmlOverrides, OneSpeedReplacesTheOther) {
  const Scene s = loadCaseText(kSmall, "t.xml", {"drum.critical_fraction=0.35"});
  EXPECT_DOUBLE_EQ(s.drum.critical_fraction, 0.35);
}

TEST(CaseXmlOverrides, MissingPath) {
  const Failure attr = textFailure(kSmall, {"time.ned=2"});
  EXPECT_EQ(attr.what,
            "--set time.ned=2: unknown attribute 'ned' of <time> (expected one of: end, dt, "
            "dt_divisor, dt_fixed); did you mean 'end'?");
  EXPECT_EQ(attr.line, 0);
  const Failure element = textFailure(kSmall, {"drum.lifter.count=3"});
  EXPECT_EQ(element.what.rfind("--set drum.lifter.count=3: unknown element 'drum.lifter' "
                               "(expected one of: time, gravity, output, dem, drum, drum.lifters,",
                               0),
            0u)
      << element.what;
  EXPECT_NE(element.what.find("; did you mean 'drum.lifters'?"), std::string::npos);
  EXPECT_EQ(textFailure(kSmall, {"time.end"}).what,
            "--set time.end: expected PATH=VALUE, e.g. time.end=2 (paths: docs/case-format.md)");
}

TEST(CaseXmlOverrides, BadValue) {
  const Failure f = textFailure(kSmall, {"time.end=abc"});
  EXPECT_EQ(f.what, "--set time.end=abc: expected a number (s)");
  EXPECT_EQ(f.line, 0);
  EXPECT_EQ(textFailure(kSmall, {"drum.diameter=-1"}).what, "--set drum.diameter=-1: must be > 0 (m)");
  EXPECT_EQ(textFailure(kSmall, {"dem.damping=foo"}).what,
            "--set dem.damping=foo: expected one of exact, dualsphysics");
  EXPECT_EQ(textFailure(kSmall, {"drum.lifters.height=0.03"}).what,
            "--set drum.lifters.height=0.03: must be < drum.diameter / 4 = 0.025 (m)");
}

TEST(CaseXmlOverrides, CreatedElementStillNeedsItsRequiredAttributes) {
  std::string xml = kSmall;
  xml.replace(xml.find("  <time end=\"1\"/>\n"), 18, "");
  EXPECT_EQ(textFailure(xml, {"time.dt=fixed"}).what, "--set time.dt=fixed: <time>: missing required attribute 'end'");
  EXPECT_DOUBLE_EQ(loadCaseText(xml, "t.xml", {"time.end=5"}).time.end, 5.0);
}

// ---- describeCaseFormat ------------------------------------------------------------------------

TEST(CaseXmlDescribe, ListsEveryAttributeOfTheSchema) {
  const std::string md = describeCaseFormat();
  const auto paths = caseAttributePaths();
  for (const auto& p : paths) EXPECT_NE(md.find("| `" + p + "` |"), std::string::npos) << p;
  // The format of the brief, attribute by attribute: the schema has all of them and no others.
  // clang-format off
  const std::vector<std::string> expected = {
      "name",
      "time.end", "time.dt", "time.dt_divisor", "time.dt_fixed",
      "gravity.x", "gravity.y", "gravity.z",
      "output.series_every", "output.fields_every", "output.checkpoint_every",
      "dem.youngs_modulus", "dem.poisson", "dem.density", "dem.restitution", "dem.friction",
      "dem.damping", "dem.friction_smoothing", "dem.tangential", "dem.impact_velocity",
      "dem.representation", "dem.element_spacing",
      "drum.diameter", "drum.length", "drum.speed_rpm", "drum.critical_fraction",
      "drum.start_time", "drum.spin_up",
      "drum.lifters.count", "drum.lifters.height", "drum.lifters.width",
      "charge.filling", "charge.top_size", "charge.min_size", "charge.size_step",
      "charge.bond_exponent", "charge.seed", "charge.count",
      "compaction.duration", "compaction.length_factor",
      "angle_of_repose.enabled", "angle_of_repose.start_time", "angle_of_repose.frames",
      "angle_of_repose.pixels_per_mm", "angle_of_repose.threshold",
      "angle_of_repose.smoothing_px", "angle_of_repose.fit_offset_mm",
      "angle_of_repose.fit_length_mm",
      "sph.dimension", "sph.dp", "sph.kernel", "sph.coefh", "sph.coefsound", "sph.hswl", "sph.rho0",
      "sph.gamma", "sph.viscosity", "sph.alpha", "sph.visco_bound_factor", "sph.nu", "sph.wall_velocity",
      "sph.boundary", "sph.ddt",
      "sph.ddt_value", "sph.integrator", "sph.verlet_steps", "sph.cfl", "sph.shifting", "sph.shift_coef",
      "sph.shift_tfs", "sph.rhop_out_min", "sph.rhop_out_max", "sph.parts_out_max", "sph.boundary_layers",
      "sph.initial_density",
      "fluid.x_min", "fluid.y_min", "fluid.z_min", "fluid.x_max", "fluid.y_max", "fluid.z_max",
      "tank.x_min", "tank.y_min", "tank.z_min", "tank.x_max", "tank.y_max", "tank.z_max", "tank.closed",
      "tank.rotation_rpm", "tank.spin_up",
      "slurry.filling",
      "dem.law", "dem.linear_stiffness", "dem.skin",
      "stirrer.chamber_diameter", "stirrer.chamber_length", "stirrer.shaft_diameter", "stirrer.disk_count",
      "stirrer.disk_diameter", "stirrer.disk_thickness", "stirrer.hole_count", "stirrer.hole_diameter",
      "stirrer.hole_ring_diameter", "stirrer.speeds_rpm", "stirrer.hold", "stirrer.ramp", "stirrer.average_from",
      "stirrer.idle_power_W",
      "beads.count", "beads.diameter", "beads.diameter_max", "beads.lattice_factor", "beads.seed",
      "lubrication.viscosity", "lubrication.inner", "lubrication.outer",
      "collisions.enabled", "collisions.start", "collisions.sample_every", "collisions.grid_radial", "collisions.grid_axial",
      "probes.points"};
  // clang-format on
  EXPECT_EQ(paths, expected);
  // Defaults come from Scene, bounds and units from the schema.
  EXPECT_NE(md.find("| `dem.poisson` | number | - | 0.29 | [0, 0.5) |"), std::string::npos);
  EXPECT_NE(md.find("| `time.end` | number | s | required | > 0 |"), std::string::npos);
  EXPECT_NE(md.find("| `dem.damping` | choice | - | exact | `exact`, `dualsphysics` |"), std::string::npos);
  EXPECT_NE(md.find("`drum.lifters.height` < `drum.diameter` / 4"), std::string::npos);
}

// The reference section of the user docs is the generated table: a schema change that is not
// pasted into docs/case-format.md fails here instead of leaving the docs stale.
TEST(CaseXmlDescribe, DocsHoldTheCurrentTable) {
  const std::string doc = readFile(std::filesystem::path(MILLSIM_SOURCE_DIR) / "docs" / "case-format.md");
  EXPECT_NE(doc.find(describeCaseFormat()), std::string::npos)
      << "paste the output of `millsim describe` into docs/case-format.md";
}

}  // namespace
