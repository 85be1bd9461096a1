// millsim command line: run, validate, info, describe, angle-from-dumps, vision angle|slurry,
// compare-dam-break, compare-power (compare_power_command.cpp), calibrate (calibrate_command.cpp),
// sweep (sweep_command.cpp), study accuracy.
// Exit codes: 0 ok, 2 bad input (file:line message; for vision: bad video path, unreadable
// codec, no mill outline found), 3 the simulation went unstable (cause printed; last good state
// kept in OUT/), 1 anything else (e.g. a surface that cannot be measured).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "calibrate_command.hpp"
#include "compare_power_command.hpp"
#include "csv_table.hpp"
#include "millsim/backend/info.hpp"
#include "millsim/backend/simd.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/io/particle_dump.hpp"
#include "millsim/io/plot_png.hpp"
#include "millsim/sim/accuracy_study.hpp"
#include "millsim/sim/martin_moyce.hpp"
#include "millsim/sim/simulation.hpp"
#include "millsim/vision/angle_overlay.hpp"
#include "millsim/vision/front_view_angle.hpp"
#include "millsim/vision/png_io.hpp"
#include "millsim/vision/video_angle.hpp"
#include "millsim/vision/video_slurry.hpp"
#include "mpi_ranks.hpp"
#include "sweep_command.hpp"

namespace {

using millsim::core::InputError;
using millsim::core::SimulationError;

millsim::scene::Scene loadScene(const std::string& path, const std::vector<std::string>& sets) {
  if (path.empty())
    return millsim::io::loadCaseText(millsim::io::defaultCaseXml(), "<embedded ball_mill_300_balls>", sets);
  return millsim::io::loadCaseFile(path, sets);
}

// What the particle count counts, for the first line of a run and of `check`.
const char* particleNoun(const millsim::scene::Scene& scene) {
  if (scene.effect_sph && !scene.effect_dem) return "SPH particles";
  return scene.dem.representation == "dcdem" ? "DCDEM ball particles" : "balls";
}

int runCommand(const std::string& case_path, const std::vector<std::string>& sets, millsim::sim::RunOptions opt) {
  const millsim::scene::Scene scene = loadScene(case_path, sets);
  millsim::sim::Simulation sim(scene, opt);
  std::fprintf(stderr, "millsim: %s: %zu %s, dt = %.3g s%s, backend %s, out %s\n", scene.name.c_str(),
               sim.particleCount(), particleNoun(scene), sim.timeStep(),
               scene.effect_sph && !scene.effect_dem && scene.time.dt_mode == "auto" ? " (first, CFL)" : "",
               opt.backend.c_str(), opt.out_dir.c_str());
  const auto& s = sim.run();
  nlohmann::ordered_json j;
  j["status"] = s.status;
  j["wall_time_s"] = s.wall_time_s;
  j["steps"] = s.steps;
  if (s.angle_valid)
    j["angle_of_repose_deg"] = s.angle_of_repose_deg;
  else
    j["angle_of_repose_deg"] = nullptr;
  j["power_W"] = s.power_W;
  j["summary"] = opt.out_dir + "/summary.json";
  std::cout << j.dump() << std::endl;
  return 0;
}

struct DumpAngleArgs {
  std::vector<std::string> dumps;
  double diameter = 0.292;
  double start_timestep = -1;
  millsim::vision::AngleOptions angle;
  std::string out;
};

// Angle of repose of another code's particle dumps through millsim's own front-view pipeline.
int angleFromDumpsCommand(const DumpAngleArgs& a) {
  millsim::vision::FrontViewAngle angle(a.diameter, a.angle);
  for (const auto& file : a.dumps)
    for (const auto& f : millsim::io::readParticleDump(file))
      if (f.timestep >= a.start_timestep) angle.addFrame(f.x, f.y, f.radius);
  const millsim::vision::AngleResult r = angle.measure();
  if (!a.out.empty()) {
    std::filesystem::create_directories(a.out);
    angle.writeImages(a.out, &r);
  }
  nlohmann::ordered_json j;
  j["angle_deg"] = r.angle_deg;
  j["stderr_deg"] = r.stderr_deg;
  j["frames"] = angle.frames();
  j["points"] = r.points_used;
  std::cout << j.dump() << std::endl;
  return 0;
}

// --- vision: recordings of the mill's front window -------------------------------------------

struct VisionArgs {
  std::string video, images, out = "vision_out", mode = "balls", points;
  int frames = 100;
  double radius_px = 0.0;
  millsim::vision::VideoAngleOptions angle;
  millsim::vision::SlurryOptions slurry;
};

millsim::vision::FrameSequence readInput(const VisionArgs& a) {
  if (!a.video.empty()) return millsim::vision::readVideoFrames(a.video, a.frames);
  return millsim::vision::readImageFolder(a.images, a.frames);
}

void prepareVision(VisionArgs& a) {
  a.angle.detection.expected_radius_px = a.radius_px;
  a.angle.angle.pixels_per_mm = a.angle.view.pixels_per_mm;
  a.angle.segmentation.mode = a.mode == "dry" ? millsim::vision::ChargeMode::Dry : millsim::vision::ChargeMode::Balls;
  std::filesystem::create_directories(a.out);
}

nlohmann::ordered_json circleJson(const millsim::vision::MillCircle& c) {
  nlohmann::ordered_json j;
  j["cx_px"] = c.cx_px;
  j["cy_px"] = c.cy_px;
  j["radius_px"] = c.radius_px;
  j["refined"] = c.refined;
  return j;
}

int visionAngleCommand(VisionArgs a) {
  prepareVision(a);
  const millsim::vision::FrameSequence seq = readInput(a);
  const millsim::vision::VideoAngleResult r = millsim::vision::measureVideoAngle(seq, a.angle);
  const std::filesystem::path out(a.out);
  millsim::vision::ImageU8 gray(r.heat.width, r.heat.height);
  for (std::size_t k = 0; k < r.heat.pixels.size(); ++k)
    gray.pixels[k] = static_cast<std::uint8_t>(std::lround(255.0f * r.heat.pixels[k]));
  millsim::vision::writePng((out / "heatmap.png").string(), gray);
  millsim::vision::writePng((out / "overlay.png").string(), r.overlay);
  millsim::vision::writePng((out / "heatmap_overlay.png").string(),
                            millsim::vision::renderAngleOverlay(r.heat, r.angle, a.angle.view.pixels_per_mm));
  std::ofstream edge(out / "angle_edge.csv");
  edge << "x_mm,y_mm\n";
  for (std::size_t k = 0; k < r.angle.fit_x_mm.size(); ++k)
    edge << r.angle.fit_x_mm[k] << "," << r.angle.fit_y_mm[k] << "\n";
  nlohmann::ordered_json j;
  j["angle_deg"] = r.angle.angle_deg;
  j["stderr_deg"] = r.angle.stderr_deg;
  j["frames"] = r.frames;
  j["points"] = r.angle.points_used;
  j["mode"] = a.mode;
  j["circle"] = circleJson(r.circle);
  j["out"] = a.out;
  std::cout << j.dump() << std::endl;
  return 0;
}

int visionSlurryCommand(VisionArgs a) {
  prepareVision(a);
  millsim::vision::VideoSlurryOptions opt;
  opt.detection = a.angle.detection;
  opt.view = a.angle.view;
  opt.slurry = a.slurry;
  millsim::vision::SlurryMeasurement m;
  if (!a.points.empty()) {
    // Picked points; frames (when given) locate the mill for pixel points and the picture.
    if (!a.video.empty() || !a.images.empty()) {
      const millsim::vision::FrameSequence seq = readInput(a);
      const millsim::vision::MillView view = millsim::vision::locateMill(seq, opt.detection, opt.view);
      m.curve = millsim::vision::fitSlurryCurve(millsim::vision::readSurfacePointsCsv(a.points, &view),
                                                opt.slurry.outlier_sigmas, opt.slurry.confidence);
      m.circle = view.circle();
      const double R = view.innerRadiusMm();
      m.overlay =
          millsim::vision::drawSlurryOverlay(seq.frames[seq.frames.size() / 2], m.curve,
                                             millsim::vision::millToFrameAffine(view), {R + opt.view.wall_mm, R});
    } else {
      m.curve = millsim::vision::fitSlurryCurve(millsim::vision::readSurfacePointsCsv(a.points, nullptr),
                                                opt.slurry.outlier_sigmas, opt.slurry.confidence);
      const double R = 0.5 * opt.view.diameter_mm - opt.view.wall_mm;
      const int n = static_cast<int>(std::lround(2 * R * opt.view.pixels_per_mm));
      m.overlay = millsim::vision::drawSlurryOverlay(millsim::vision::ImageRgb(n, n, {40, 40, 40}), m.curve,
                                                     millsim::vision::millToViewAffine(R, opt.view.pixels_per_mm), {R});
    }
  } else {
    m = millsim::vision::measureVideoSlurry(readInput(a), opt);
  }
  const std::filesystem::path out(a.out);
  millsim::vision::writeSlurryCurveCsv((out / "slurry_curve.csv").string(), m.curve);
  millsim::vision::writeSurfacePointsCsv((out / "slurry_points.csv").string(), m.curve);
  millsim::vision::writePng((out / "slurry_overlay.png").string(), m.overlay);
  nlohmann::ordered_json j;
  j["coefficients"] = m.curve.fit.coef;
  j["band_halfwidth_mm_at_0"] = m.curve.fit.halfWidth(0.0);
  j["x_range_mm"] = {m.curve.x_min_mm, m.curve.x_max_mm};
  j["points"] = m.curve.used.size();
  j["rejected"] = m.curve.rejected.size();
  j["frames"] = m.frames;
  if (m.circle.radius_px > 0) j["circle"] = circleJson(m.circle);
  j["out"] = a.out;
  std::cout << j.dump() << std::endl;
  return 0;
}

void addVisionInputOptions(CLI::App* cmd, VisionArgs& a) {
  auto* video = cmd->add_option("--video", a.video, "Video file (mp4, avi, ... anything FFmpeg decodes)");
  auto* images = cmd->add_option("--images", a.images, "Folder of frames (png, jpg, bmp, tif), natural name order");
  video->excludes(images);
  cmd->add_option("--frames", a.frames, "Evenly spaced frames to use (paper: 100)")->capture_default_str();
  cmd->add_option("--diameter-mm", a.angle.view.diameter_mm, "Real diameter of the drum outline (outer rim) [mm]")
      ->capture_default_str();
  cmd->add_option("--wall-mm", a.angle.view.wall_mm, "Outline to inner drum wall [mm] (paper: 4)")
      ->capture_default_str();
  cmd->add_option("--margin-mm", a.angle.view.margin_mm, "Ring inside the wall left out (lifters) [mm]")
      ->capture_default_str();
  cmd->add_option("--tilt-deg", a.angle.view.tilt_deg, "Camera roll: a level line rises to the right by this [deg]")
      ->capture_default_str();
  cmd->add_flag("--mirror", a.angle.view.mirror, "Flip left-right (drum filmed turning the other way)");
  cmd->add_option("--pixels-per-mm", a.angle.view.pixels_per_mm, "Scale of the analysed view")->capture_default_str();
  cmd->add_option("--radius-px", a.radius_px, "Expected outline radius in frame pixels (0: search automatically)")
      ->capture_default_str();
  cmd->add_option("--out", a.out, "Output folder")->capture_default_str();
}

int infoCommand() {
  nlohmann::ordered_json j;
  j["version"] = MILLSIM_VERSION_STRING;
  j["backends"] =
      millsim::backend::cudaCompiled() ? nlohmann::json::array({"omp", "cuda"}) : nlohmann::json::array({"omp"});
  j["omp_max_threads"] = millsim::backend::ompMaxThreads();
  // The vector width of the DEM pair blocks on this CPU (MILLSIM_SIMD can lower it).
  j["simd_cpu"] = millsim::backend::simdLevelName(millsim::backend::cpuSimdLevel());
  j["simd"] = millsim::backend::simdLevelName(millsim::backend::simdLevel());
  j["cuda_compiled"] = millsim::backend::cudaCompiled();
  j["cuda_devices"] = millsim::backend::cudaDevices();
  j["gpu"] = millsim::backend::cudaDeviceName();
  j["mpi_compiled"] = millsim::cli::mpiCompiled();
  const auto* ranks = millsim::cli::mpiSession().ranks();
  j["mpi_ranks"] = ranks ? ranks->size() : 1;
  std::cout << j.dump(2) << std::endl;
  return 0;
}

}  // namespace

// Reads series.csv of dam-break runs, compares each front with Martin & Moyce (1952) and plots
// them together: Z/a against T = t sqrt(2 g / a).
int compareDamBreakCommand(const std::vector<std::string>& dirs, double a, double g, const std::string& png,
                           const std::vector<std::string>& labels) {
  std::vector<millsim::io::PlotSeries> series;
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    const auto csv =
        millsim::cli::readCsvTable(dirs[k] + "/series.csv", "run the dam-break case with --out " + dirs[k] + " first");
    const std::size_t ct = csv.column("time_s", "not an SPH run?"), cx = csv.column("front_x_m", "not an SPH run?");
    std::vector<double> t, x;
    for (std::size_t r = 0; r < csv.cells.size(); ++r) {
      t.push_back(csv.number(r, ct));
      x.push_back(csv.number(r, cx));
    }
    const auto c = millsim::sim::compareWithMartinMoyce(t, x, a, g);
    nlohmann::ordered_json j;
    j["run"] = dirs[k];
    j["points"] = c.points;
    j["max_error_raw"] = c.max_error_raw;
    j["mean_error_raw"] = c.mean_error_raw;
    j["time_origin_T0"] = c.shift_T;
    j["max_error_shifted_T_0.8_2.5"] = c.max_error_shifted;
    j["errors_raw"] = c.errors_raw;
    out.push_back(j);
    millsim::io::PlotSeries s;
    s.label = k < labels.size() ? labels[k] : dirs[k];
    s.rgb = millsim::io::seriesColour(k);
    const double scale = std::sqrt(2 * g / a);
    for (std::size_t i = 0; i < t.size(); ++i) {
      s.x.push_back(t[i] * scale);
      s.y.push_back(x[i] / a);
    }
    series.push_back(s);
  }
  millsim::io::PlotSeries data;
  data.label = "Martin & Moyce 1952";
  data.line = false;
  data.markers = true;
  for (const auto& p : millsim::sim::martinMoyceFront()) {
    data.x.push_back(p.T);
    data.y.push_back(p.z_over_a);
  }
  series.push_back(data);
  if (!png.empty()) {
    millsim::io::PlotAxes axes;
    axes.title = "Dam break: surge front";
    axes.x_label = "T = t sqrt(2g/a)";
    axes.y_label = "Z / a";
    axes.x_min = 0;
    axes.x_max = 3.5;
    axes.y_min = 1;
    axes.y_max = 4.5;
    millsim::io::writeLinePlot(png, axes, series);
  }
  std::cout << out.dump(2) << std::endl;
  return 0;
}

int runMain(int argc, char** argv);

int main(int argc, char** argv) {
  // MPI only when started by mpirun/srun (calibrate and sweep spread their runs over the ranks).
  const millsim::cli::MpiSession mpi(&argc, &argv);
  millsim::cli::setMpiSession(&mpi);
  return runMain(argc, argv);
}

int runMain(int argc, char** argv) {
  CLI::App app{"millsim: DEM-SPH simulator for grinding mills"};
  app.require_subcommand(1);
  app.set_version_flag("--version", MILLSIM_VERSION_STRING);

  std::string case_path;
  std::vector<std::string> sets;
  millsim::sim::RunOptions opt;
  auto* run = app.add_subcommand("run", "Run a case (no CASE: the embedded 300 mm balls-only mill)");
  run->add_option("case", case_path, "Case XML file")->check(CLI::ExistingFile);
  run->add_option("--out,-o", opt.out_dir, "Output directory")->capture_default_str();
  run->add_option("--backend", opt.backend, "Execution backend")
      ->check(CLI::IsMember({"auto", "omp", "cuda"}))
      ->capture_default_str();
  run->add_option("--precision", opt.precision, "Floating point precision of the particle state")
      ->check(CLI::IsMember({"double", "float"}))
      ->capture_default_str();
  run->add_option("--threads", opt.threads, "OpenMP threads (0: all)")->capture_default_str();
  run->add_option("--set", sets, "Override an attribute: element.path.attribute=value (repeatable)");
  run->add_option("--restart", opt.restart, "Continue from a checkpoint (OUT/checkpoint.h5)")->check(CLI::ExistingFile);
  bool quiet = false;
  run->add_flag("--quiet,-q", quiet, "No progress line");

  auto* validate = app.add_subcommand("validate", "Check a case file and print its parsed summary");
  validate->add_option("case", case_path, "Case XML file")->required()->check(CLI::ExistingFile);
  validate->add_option("--set", sets, "Override an attribute: element.path.attribute=value (repeatable)");

  auto* info = app.add_subcommand("info", "Version, backends, GPU");

  DumpAngleArgs dump_args;
  auto* dump_angle = app.add_subcommand(
      "angle-from-dumps",
      "Angle of repose from LAMMPS/LIGGGHTS text dumps (drum axis z, gravity -y), same pipeline as run");
  dump_angle->add_option("--dumps", dump_args.dumps, "Dump files (dump custom with x y z radius)")
      ->required()
      ->check(CLI::ExistingFile);
  dump_angle->add_option("--diameter", dump_args.diameter, "Inner drum diameter [m]")->capture_default_str();
  dump_angle->add_option("--from-timestep", dump_args.start_timestep, "Ignore frames before this timestep");
  dump_angle->add_option("--pixels-per-mm", dump_args.angle.pixels_per_mm, "Image scale")->capture_default_str();
  dump_angle->add_option("--threshold", dump_args.angle.threshold, "Heat-map threshold")->capture_default_str();
  dump_angle
      ->add_option("--fit-offset-mm", dump_args.angle.fit_offset_mm, "Fit starts this far right of the highest point")
      ->capture_default_str();
  dump_angle->add_option("--out", dump_args.out, "Write heatmap.png, angle_overlay.png, angle_edge.csv here");
  auto* compare_db = app.add_subcommand(
      "compare-dam-break", "Compare dam-break runs (their OUT dirs) with Martin & Moyce's surge front; plot them");
  std::vector<std::string> db_dirs, db_labels;
  double db_a = 0.05715, db_g = 9.81;
  std::string db_png;
  compare_db->add_option("dirs", db_dirs, "Output directories of dam-break runs")->required();
  compare_db->add_option("--a", db_a, "Column width a [m] (M&M: 0.05715)");
  compare_db->add_option("--g", db_g, "Gravity [m/s^2]");
  compare_db->add_option("--png", db_png, "Write the plot of Z/a against T here");
  compare_db->add_option("--labels", db_labels, "Legend label of each run")->delimiter(',');
  auto* study = app.add_subcommand("study", "Studies of the solvers");
  auto* study_accuracy = study->add_subcommand(
      "accuracy", "What accuracy costs in time: error and wall time over settings (CSV, Pareto PNGs)");
  bool study_quick = false;
  std::string study_out = "study", study_source = MILLSIM_SOURCE_DIR;
  study_accuracy->add_flag("--quick", study_quick, "Cheapest levels of each axis (a smoke test)");
  study_accuracy->add_option("--out", study_out, "Output directory");
  study_accuracy->add_option("--source", study_source, "Directory holding cases/ (default: the source tree)");
  std::string study_replot, study_only, study_merge;
  study_accuracy->add_option("--only", study_only,
                             "Run only PROBLEM or PROBLEM:AXIS (dam_break_2d, hertz_impact, drum_300, wet_drum; e.g. "
                             "drum_300:representation)");
  study_accuracy->add_option("--merge", study_merge,
                             "Merge the rows run into this earlier accuracy_cost.csv (same problem/axis/setting "
                             "replaced) before writing --out");
  study_accuracy->add_option("--replot", study_replot,
                             "Redraw the CSV and plots into --out from an earlier accuracy_cost.csv, running nothing");
  study->require_subcommand(1);
  auto* describe = app.add_subcommand("describe", "Print every case-file element and attribute (markdown)");

  auto* vision = app.add_subcommand("vision", "Angle of repose and slurry curve from recordings of the mill's window");
  vision->require_subcommand(1);
  VisionArgs angle_args, slurry_args;
  auto* vision_angle = vision->add_subcommand(
      "angle",
      "Dynamic angle of repose: prints JSON, writes OUT/overlay.png, heatmap.png, heatmap_overlay.png, "
      "angle_edge.csv");
  addVisionInputOptions(vision_angle, angle_args);
  vision_angle->add_option("--mode", angle_args.mode, "balls (local contrast) or dry (two-class intensity threshold)")
      ->check(CLI::IsMember({"balls", "dry"}))
      ->capture_default_str();
  vision_angle->add_option("--threshold", angle_args.angle.angle.threshold, "Heat-map threshold")
      ->capture_default_str();
  vision_angle
      ->add_option("--fit-offset-mm", angle_args.angle.angle.fit_offset_mm,
                   "Fit starts this far right of the highest point")
      ->capture_default_str();
  auto* vision_slurry = vision->add_subcommand(
      "slurry",
      "Slurry surface: quadratic fit with 95% band; writes OUT/slurry_curve.csv, slurry_points.csv, "
      "slurry_overlay.png");
  addVisionInputOptions(vision_slurry, slurry_args);
  vision_slurry->add_option("--points", slurry_args.points,
                            "Picked points CSV (header x_mm,y_mm or x_px,y_px; optional frame column)");
  vision_slurry->add_option("--point-spacing-mm", slurry_args.slurry.point_spacing_mm, "Column spacing of points")
      ->capture_default_str();
  vision_slurry->add_option("--confidence", slurry_args.slurry.confidence, "Confidence of the band")
      ->capture_default_str();

  millsim::cli::CalibrateArgs calibrate_args;
  auto* calibrate = millsim::cli::addCalibrateCommand(app, calibrate_args);
  millsim::cli::SweepArgs sweep_args;
  auto* sweep = millsim::cli::addSweepCommand(app, sweep_args);
  millsim::cli::ComparePowerArgs power_args;
  auto* compare_power = millsim::cli::addComparePowerCommand(app, power_args);

  CLI11_PARSE(app, argc, argv);
  try {
    // Under mpirun only calibrate and sweep share out work; anything else (but `info`, which
    // shows the ranks) would run N times over.
    const auto* ranks = millsim::cli::mpiSession().ranks();
    if (ranks && ranks->size() > 1 && !calibrate->parsed() && !sweep->parsed() && !info->parsed())
      throw InputError("started on " + std::to_string(ranks->size()) +
                       " MPI ranks: only `calibrate` and `sweep` spread their runs over ranks; run this command as "
                       "one process");
    if (run->parsed()) {
      opt.progress = !quiet;  // a line in place on a terminal, a line a minute into a log
      return runCommand(case_path, sets, opt);
    }
    if (validate->parsed()) {
      const auto scene = loadScene(case_path, sets);
      // Building the simulation also checks what parsing cannot: that the charge fits, etc.
      millsim::sim::RunOptions check;
      check.write_outputs = false;
      millsim::sim::Simulation sim(scene, check);
      std::cout << case_path << ": ok (" << scene.name << ", " << sim.particleCount() << " " << particleNoun(scene)
                << ", dt = " << sim.timeStep() << " s)" << std::endl;
      return 0;
    }
    if (info->parsed()) return infoCommand();
    if (calibrate->parsed()) return millsim::cli::calibrateCommand(calibrate_args);
    if (sweep->parsed()) return millsim::cli::sweepCommand(sweep_args);
    if (compare_power->parsed()) return millsim::cli::comparePowerCommand(power_args);
    if (dump_angle->parsed()) return angleFromDumpsCommand(dump_args);
    if (vision_angle->parsed() || vision_slurry->parsed()) {
      VisionArgs& a = vision_angle->parsed() ? angle_args : slurry_args;
      if (a.video.empty() && a.images.empty() && a.points.empty())
        throw InputError(std::string("vision ") + (vision_angle->parsed() ? "angle" : "slurry") +
                         ": give --video FILE or --images DIR" + (vision_slurry->parsed() ? " (or --points CSV)" : ""));
      return vision_angle->parsed() ? visionAngleCommand(a) : visionSlurryCommand(a);
    }
    if (compare_db->parsed()) return compareDamBreakCommand(db_dirs, db_a, db_g, db_png, db_labels);
    if (study_accuracy->parsed()) {
      auto rows = study_replot.empty() ? millsim::sim::runAccuracyStudy(study_quick, study_source, study_only)
                                       : millsim::sim::readAccuracyStudy(study_replot);
      if (!study_merge.empty()) rows = millsim::sim::mergeStudyRows(millsim::sim::readAccuracyStudy(study_merge), rows);
      millsim::sim::writeAccuracyStudy(rows, study_out);
      nlohmann::ordered_json j = nlohmann::ordered_json::array();
      for (const auto& r : rows)
        j.push_back({{"problem", r.problem},
                     {"axis", r.axis},
                     {"setting", r.setting},
                     {"error", r.error},
                     {"wall_s", r.wall_s}});
      std::cout << j.dump(1) << std::endl;
      return 0;
    }
    if (describe->parsed()) {
      std::cout << millsim::io::describeCaseFormat();
      return 0;
    }
  } catch (const InputError& e) {
    std::cerr << "millsim: error: " << e.what() << std::endl;
    millsim::cli::mpiSession().abortAll(2);  // the other ranks may be waiting in a collective call
    return 2;
  } catch (const SimulationError& e) {
    // Point at the last good state the run left: its checkpoint, else its last fields frame.
    const std::filesystem::path out(opt.out_dir);
    std::string kept = "nothing but series.csv and summary.json in " + opt.out_dir;
    if (std::filesystem::exists(out / "checkpoint.h5"))
      kept = (out / "checkpoint.h5").string();
    else if (std::filesystem::exists(out / "fields.xdmf"))
      kept = "the last frame of " + (out / "fields.xdmf").string();
    std::cerr << "\nmillsim: simulation stopped: " << e.what() << " (last good state: " << kept << ")" << std::endl;
    millsim::cli::mpiSession().abortAll(3);
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "millsim: error: " << e.what() << std::endl;
    millsim::cli::mpiSession().abortAll(1);
    return 1;
  }
  return 0;
}
