// millsim_synth: writes a synthetic mill recording (synthetic_mill.hpp) for trying the vision
// pipeline and for the pictures in docs/vision.md, e.g.
//   millsim_synth --content balls --angle 40 --tilt 2 --frames 30 --out balls.mp4
//   millsim_synth --content slurry --frames 24 --out frames/ --ext jpg
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "synthetic_mill.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Synthetic lab-mill recording with a known surface (balls, dry, slurry)"};
  millsim::synth::MillScene sc;
  std::string content = "balls", out, ext = "png", fourcc;
  int frames = 30;
  app.add_option("--content", content, "balls, dry or slurry")->check(CLI::IsMember({"balls", "dry", "slurry"}));
  app.add_option("--angle", sc.surface_angle_deg, "Surface angle of a ball or dry bed [deg]")->capture_default_str();
  app.add_option("--offset-mm", sc.surface_offset_mm, "Bed surface distance from the axis [mm]")->capture_default_str();
  app.add_option("--tilt", sc.tilt_deg, "Camera roll [deg, counter-clockwise]")->capture_default_str();
  app.add_option("--frames", frames, "Frames")->capture_default_str();
  app.add_option("--width", sc.width, "Frame width [px]")->capture_default_str();
  app.add_option("--height", sc.height, "Frame height [px]")->capture_default_str();
  app.add_option("--px-per-mm", sc.px_per_mm, "Camera scale")->capture_default_str();
  app.add_option("--noise", sc.noise_sigma, "Sensor noise [gray levels]")->capture_default_str();
  app.add_option("--blur", sc.motion_blur_px, "Motion blur length [px]")->capture_default_str();
  app.add_option("--jpeg", sc.jpeg_quality, "JPEG quality of each frame (0: none)")->capture_default_str();
  app.add_option("--seed", sc.seed, "Random seed")->capture_default_str();
  app.add_option("--out", out, "Output: a .mp4/.avi file, or a folder for images")->required();
  app.add_option("--ext", ext, "Image type for a folder: png or jpg")->capture_default_str();
  app.add_option("--fourcc", fourcc, "Video codec (default mp4v for .mp4, MJPG otherwise)");
  CLI11_PARSE(app, argc, argv);
  sc.content = content == "dry"      ? millsim::synth::Content::Dry
               : content == "slurry" ? millsim::synth::Content::Slurry
                                     : millsim::synth::Content::Balls;
  try {
    const bool video = out.size() > 4 && (out.substr(out.size() - 4) == ".mp4" || out.substr(out.size() - 4) == ".avi");
    if (video) {
      if (fourcc.empty()) fourcc = out.substr(out.size() - 4) == ".mp4" ? "mp4v" : "MJPG";
      millsim::synth::writeVideo(sc, frames, out, fourcc);
    } else {
      millsim::synth::writeImages(sc, frames, out, ext);
    }
  } catch (const std::exception& e) {
    std::cerr << "millsim_synth: error: " << e.what() << std::endl;
    return 1;
  }
  const auto c = millsim::synth::trueCircle(sc);
  nlohmann::ordered_json j;
  j["surface_angle_deg"] = sc.surface_angle_deg;
  j["slurry"] = sc.slurry;
  j["tilt_deg"] = sc.tilt_deg;
  j["circle_px"] = {c[0], c[1], c[2]};
  std::cout << j.dump() << std::endl;
  return 0;
}
