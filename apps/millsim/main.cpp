// millsim command line: run, validate, info. Exit codes: 0 ok, 2 bad input (file:line message),
// 3 the simulation went unstable (cause printed; last good state kept in OUT/).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/io/particle_dump.hpp"
#include "millsim/vision/front_view_angle.hpp"
#include "millsim/sim/simulation.hpp"

namespace {

using millsim::core::InputError;
using millsim::core::SimulationError;

millsim::scene::Scene loadScene(const std::string& path, const std::vector<std::string>& sets) {
  if (path.empty()) return millsim::io::loadCaseText(millsim::io::defaultCaseXml(), "<embedded ball_mill_300_balls>", sets);
  return millsim::io::loadCaseFile(path, sets);
}

int runCommand(const std::string& case_path, const std::vector<std::string>& sets, millsim::sim::RunOptions opt) {
  const millsim::scene::Scene scene = loadScene(case_path, sets);
  millsim::sim::Simulation sim(scene, opt);
  std::fprintf(stderr, "millsim: %s: %zu balls, dt = %.3g s, backend %s, out %s\n", scene.name.c_str(),
               sim.particleCount(), sim.timeStep(), opt.backend.c_str(), opt.out_dir.c_str());
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

int infoCommand() {
  nlohmann::ordered_json j;
  j["version"] = MILLSIM_VERSION_STRING;
  j["backends"] = millsim::backend::cudaCompiled() ? nlohmann::json::array({"omp", "cuda"}) : nlohmann::json::array({"omp"});
  j["omp_max_threads"] = millsim::backend::ompMaxThreads();
  j["cuda_compiled"] = millsim::backend::cudaCompiled();
  j["cuda_devices"] = millsim::backend::cudaDevices();
  j["gpu"] = millsim::backend::cudaDeviceName();
  std::cout << j.dump(2) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"millsim: DEM-SPH simulator for grinding mills"};
  app.require_subcommand(1);
  app.set_version_flag("--version", MILLSIM_VERSION_STRING);

  std::string case_path;
  std::vector<std::string> sets;
  millsim::sim::RunOptions opt;
  auto* run = app.add_subcommand("run", "Run a case (no CASE: the embedded 300 mm balls-only mill)");
  run->add_option("case", case_path, "Case XML file")->check(CLI::ExistingFile);
  run->add_option("--out,-o", opt.out_dir, "Output directory")->capture_default_str();
  run->add_option("--backend", opt.backend, "Execution backend")->check(CLI::IsMember({"auto", "omp", "cuda"}))->capture_default_str();
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
      "angle-from-dumps", "Angle of repose from LAMMPS/LIGGGHTS text dumps (drum axis z, gravity -y), same pipeline as run");
  dump_angle->add_option("--dumps", dump_args.dumps, "Dump files (dump custom with x y z radius)")->required()->check(CLI::ExistingFile);
  dump_angle->add_option("--diameter", dump_args.diameter, "Inner drum diameter [m]")->capture_default_str();
  dump_angle->add_option("--from-timestep", dump_args.start_timestep, "Ignore frames before this timestep");
  dump_angle->add_option("--pixels-per-mm", dump_args.angle.pixels_per_mm, "Image scale")->capture_default_str();
  dump_angle->add_option("--threshold", dump_args.angle.threshold, "Heat-map threshold")->capture_default_str();
  dump_angle->add_option("--fit-offset-mm", dump_args.angle.fit_offset_mm, "Fit starts this far right of the highest point")
      ->capture_default_str();
  dump_angle->add_option("--out", dump_args.out, "Write heatmap.png, angle_overlay.png, angle_edge.csv here");
  auto* describe = app.add_subcommand("describe", "Print every case-file element and attribute (markdown)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed()) {
      opt.progress = !quiet && isatty(STDERR_FILENO);
      return runCommand(case_path, sets, opt);
    }
    if (validate->parsed()) {
      const auto scene = loadScene(case_path, sets);
      // Building the simulation also checks what parsing cannot: that the charge fits, etc.
      millsim::sim::RunOptions check;
      check.write_outputs = false;
      millsim::sim::Simulation sim(scene, check);
      std::cout << case_path << ": ok (" << scene.name << ", " << sim.particleCount() << " balls, dt = " << sim.timeStep()
                << " s)" << std::endl;
      return 0;
    }
    if (info->parsed()) return infoCommand();
    if (dump_angle->parsed()) return angleFromDumpsCommand(dump_args);
    if (describe->parsed()) {
      std::cout << millsim::io::describeCaseFormat();
      return 0;
    }
  } catch (const InputError& e) {
    std::cerr << "millsim: error: " << e.what() << std::endl;
    return 2;
  } catch (const SimulationError& e) {
    std::cerr << "\nmillsim: simulation stopped: " << e.what() << " (last good state: " << opt.out_dir
              << "/checkpoint.h5)" << std::endl;
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "millsim: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
