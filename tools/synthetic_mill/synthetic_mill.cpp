// Synthetic mill recordings (see synthetic_mill.hpp).
#include "synthetic_mill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <random>
#include <stdexcept>
#include <vector>

namespace millsim::synth {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSuper = 2;  // supersampling factor

struct Ball {
  double x, y, r;  // mm
};

// Frame geometry at the supersampled resolution: canvas pixel (U, V) <-> mill mm (gravity frame).
struct Camera {
  double cx, cy, s, ct, st;  // canvas pixels
  void toMm(double U, double V, double& x, double& y) const {
    const double xi = (U - cx) / s, yi = -(V - cy) / s;
    x = ct * xi + st * yi;
    y = -st * xi + ct * yi;
  }
  void toCanvas(double x, double y, double& U, double& V) const {
    U = cx + s * (ct * x - st * y);
    V = cy - s * (st * x + ct * y);
  }
};

Camera camera(const MillScene& sc) {
  const double t = sc.tilt_deg * kPi / 180.0;
  // Frame pixel centre u <-> canvas: U = (u + 0.5) * k - 0.5.
  const double u0 = 0.5 * (sc.width - 1) + sc.centre_dx_px, v0 = 0.5 * (sc.height - 1) + sc.centre_dy_px;
  return {(u0 + 0.5) * kSuper - 0.5, (v0 + 0.5) * kSuper - 0.5, sc.px_per_mm * kSuper, std::cos(t), std::sin(t)};
}

// Random sequential addition of balls whose centres satisfy `allowed`.
template <class Allowed>
std::vector<Ball> placeBalls(const MillScene& sc, std::mt19937& rng, int attempts, Allowed allowed,
                             const std::vector<Ball>& avoid = {}) {
  const double R = innerRadiusMm(sc);
  std::uniform_real_distribution<double> ux(-R, R), ud(sc.ball_d_min_mm, sc.ball_d_max_mm);
  std::vector<Ball> out;
  for (int a = 0; a < attempts; ++a) {
    const Ball b{ux(rng), ux(rng), 0.5 * ud(rng)};
    if (std::hypot(b.x, b.y) > R - b.r || !allowed(b)) continue;
    bool free = true;
    for (const std::vector<Ball>* list : {static_cast<const std::vector<Ball>*>(&out), &avoid}) {
      for (const Ball& o : *list)
        if (std::hypot(o.x - b.x, o.y - b.y) < o.r + b.r) {
          free = false;
          break;
        }
      if (!free) break;
    }
    if (free) out.push_back(b);
  }
  return out;
}

// A shaded steel ball: Lambert + Blinn highlight, light from the upper left front (fixed to the
// camera, so the highlight sits at the same place on every ball as on real footage).
void drawBall(cv::Mat& img, const Camera& cam, const Ball& b, double brightness) {
  double U, V;
  cam.toCanvas(b.x, b.y, U, V);
  const double rp = b.r * cam.s;
  const int u0 = std::max(0, static_cast<int>(std::floor(U - rp))),
            u1 = std::min(img.cols - 1, static_cast<int>(std::ceil(U + rp)));
  const int v0 = std::max(0, static_cast<int>(std::floor(V - rp))),
            v1 = std::min(img.rows - 1, static_cast<int>(std::ceil(V + rp)));
  const double lx = -0.45, ly = 0.55, lz = 0.70;  // normalised below
  const double ln = std::sqrt(lx * lx + ly * ly + lz * lz);
  const double hx = lx / ln, hy = ly / ln, hz = lz / ln + 1.0;
  const double hn = std::sqrt(hx * hx + hy * hy + hz * hz);
  for (int v = v0; v <= v1; ++v) {
    cv::Vec3b* row = img.ptr<cv::Vec3b>(v);
    for (int u = u0; u <= u1; ++u) {
      const double nx = (u - U) / rp, ny = -(v - V) / rp;
      const double q = nx * nx + ny * ny;
      if (q >= 1.0) continue;
      const double nz = std::sqrt(1.0 - q);
      const double diffuse = std::max(0.0, (nx * lx + ny * ly + nz * lz) / ln);
      const double spec = std::pow(std::max(0.0, (nx * hx + ny * hy + nz * hz) / hn), 60.0);
      const double base = brightness * (0.18 + 0.62 * diffuse) * (0.55 + 0.45 * nz);
      const double val = 255.0 * std::min(1.0, base + 0.95 * spec);
      row[u] = cv::Vec3b(cv::saturate_cast<uchar>(val * 1.02), cv::saturate_cast<uchar>(val),
                         cv::saturate_cast<uchar>(val * 0.97));
    }
  }
}

}  // namespace

double innerRadiusMm(const MillScene& sc) { return 0.5 * sc.diameter_mm - sc.wall_mm; }

double trueSlurryY(const MillScene& sc, double x) { return sc.slurry[0] + x * (sc.slurry[1] + x * sc.slurry[2]); }

std::array<double, 2> slurrySpanMm(const MillScene& sc) {
  const double R = innerRadiusMm(sc);
  // f(x) = curve - lower arc... the surface meets the wall where x^2 + y(x)^2 = R^2.
  auto f = [&](double x) { return x * x + std::pow(trueSlurryY(sc, x), 2) - R * R; };
  auto solve = [&](double a, double b) {
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (a + b);
      ((f(a) < 0) == (f(m) < 0) ? a : b) = m;
    }
    return 0.5 * (a + b);
  };
  // Inside the drum near x = 0 (f < 0), outside at the far ends (f > 0).
  return {solve(-R, 0.0), solve(0.0, R)};
}

std::array<double, 3> trueCircle(const MillScene& sc) {
  return {0.5 * (sc.width - 1) + sc.centre_dx_px, 0.5 * (sc.height - 1) + sc.centre_dy_px,
          0.5 * sc.diameter_mm * sc.px_per_mm};
}

cv::Mat renderFrame(const MillScene& sc, int index) {
  const int W = sc.width * kSuper, H = sc.height * kSuper;
  const Camera cam = camera(sc);
  const double R = innerRadiusMm(sc), Ro = 0.5 * sc.diameter_mm;
  std::mt19937 rng(sc.seed * 7919u + static_cast<unsigned>(index) * 104729u + 17u);
  const double phi = (sc.drum_step_deg * index + 7.0) * kPi / 180.0;

  // 1. Background, rim, back plate with bolt heads, lifters.
  cv::Mat img(H, W, CV_8UC3);
  const double th = sc.surface_angle_deg * kPi / 180.0;
  const double nx = std::sin(th), ny = std::cos(th);  // upward normal of the bed surface
  // Slurry: this frame's surface = the mean surface + a random level and slope (sloshing) + two
  // waves of random phase; all zero-mean, so the mean surface is the truth a long recording gives.
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> uphase(0.0, 2.0 * kPi);
  const double level = sc.level_jitter_mm * n01(rng), tilt = sc.slope_jitter * n01(rng);
  const double ph1 = uphase(rng), ph2 = uphase(rng);
  auto slurryTop = [&](double x) {
    return trueSlurryY(sc, x) + level + tilt * x +
           sc.wave_amplitude_mm * std::sin(2 * kPi * x / sc.wave_length_mm + ph1) +
           0.5 * sc.wave_amplitude_mm * std::sin(2 * kPi * x / (0.43 * sc.wave_length_mm) + ph2);
  };
  // Dry bed: the surface is rough at the grain scale; its roughness changes every frame.
  std::vector<double> rough(512);
  {
    std::vector<double> raw(512);
    for (double& v : raw) v = n01(rng);
    for (int i = 0; i < 512; ++i) {
      double s = 0, w = 0;
      for (int k = -3; k <= 3; ++k) {
        const double wk = std::exp(-0.5 * k * k / 2.0);
        s += wk * raw[(i + k + 512) % 512];
        w += wk;
      }
      rough[i] = 1.5 * s / w;  // about 1 mm rms, correlated over a few mm
    }
  }
  cv::Mat ore_tex(H, W, CV_32F);
  if (sc.content == Content::Dry) {
    cv::Mat fine(H, W, CV_32F), coarse(H / 8, W / 8, CV_32F);
    cv::randn(fine, 0.0, 1.0);
    cv::randn(coarse, 0.0, 1.0);
    cv::GaussianBlur(fine, fine, cv::Size(0, 0), 1.2 * kSuper);
    cv::resize(coarse, coarse, cv::Size(W, H), 0, 0, cv::INTER_CUBIC);
    ore_tex = 0.9 * fine + 0.25 * coarse;
  }
  for (int v = 0; v < H; ++v) {
    cv::Vec3b* row = img.ptr<cv::Vec3b>(v);
    for (int u = 0; u < W; ++u) {
      double x, y;
      cam.toMm(u, v, x, y);
      const double r = std::hypot(x, y);
      cv::Vec3d c;
      if (r > Ro) {
        c = {92, 100, 108};
      } else if (r > R) {
        c = {178, 176, 172};
      } else {
        c = {50, 48, 46};
        // Bolt heads on the back plate, turning with the drum.
        for (int k = 0; k < 6 && std::abs(r - 0.62 * R) < 4.0; ++k) {
          const double a = phi + 2 * kPi * k / 6;
          if (std::hypot(x - 0.62 * R * std::cos(a), y - 0.62 * R * std::sin(a)) < 4.0) c = {96, 94, 92};
        }
        // Lifters: boxes on the shell.
        const double ang = r > R - sc.lifter_height_mm ? std::atan2(y, x) : 0.0;
        for (int k = 0; k < sc.lifters && r > R - sc.lifter_height_mm; ++k) {
          const double a = phi + 2 * kPi * k / sc.lifters;
          double da = std::remainder(ang - a, 2 * kPi);
          const double tang = r * std::sin(da), rad = r * std::cos(da);
          if (std::abs(da) < 0.5 && std::abs(tang) < 0.5 * sc.lifter_width_mm && rad > R - sc.lifter_height_mm)
            c = rad > R - sc.lifter_height_mm + 1.0 ? cv::Vec3d(74, 76, 78) : cv::Vec3d(120, 122, 124);
        }
        if (sc.content == Content::Dry) {
          const double along = -x * ny + y * nx;  // coordinate along the surface
          const int bin = static_cast<int>(std::floor((along + 300.0) / 1.5)) & 511;
          if (x * nx + y * ny < sc.surface_offset_mm + rough[bin]) {
            const double t = 1.0 + 0.16 * ore_tex.at<float>(v, u);
            c = {118 * t, 140 * t, 158 * t};
          }
        } else if (sc.content == Content::Balls) {
          if (x * nx + y * ny < sc.surface_offset_mm) c = {24, 24, 26};  // deep gaps of the bed
        }
      }
      row[u] =
          cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]), cv::saturate_cast<uchar>(c[2]));
    }
  }

  // 2. Charge in front of the back plate.
  if (sc.content == Content::Balls) {
    auto below = [&](const Ball& b) { return b.x * nx + b.y * ny < sc.surface_offset_mm - 0.5 * b.r; };
    const std::vector<Ball> back = placeBalls(sc, rng, 2500, below);
    for (const Ball& b : back) drawBall(img, cam, b, 0.5);
    const std::vector<Ball> front = placeBalls(sc, rng, 4000, below);
    for (const Ball& b : front) drawBall(img, cam, b, 1.0);
  } else if (sc.content == Content::Dry) {
    auto below = [&](const Ball& b) { return b.x * nx + b.y * ny < sc.surface_offset_mm - 0.8 * b.r; };
    for (const Ball& b : placeBalls(sc, rng, 60, below)) drawBall(img, cam, b, 0.9);
  } else {
    // Slurry on the window, under the (waving) surface; droplets above it.
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<std::array<double, 3>> drops;
    for (int k = 0; k < 5; ++k) {
      const double x = -0.5 * R + u01(rng) * R;
      drops.push_back({x, slurryTop(x) + 12.0 + 40.0 * u01(rng), 1.5 + 1.5 * u01(rng)});
    }
    for (int v = 0; v < H; ++v) {
      cv::Vec3b* row = img.ptr<cv::Vec3b>(v);
      for (int u = 0; u < W; ++u) {
        double x, y;
        cam.toMm(u, v, x, y);
        if (std::hypot(x, y) > R) continue;
        bool wet = y < slurryTop(x);
        for (const auto& d : drops) wet |= std::hypot(x - d[0], y - d[1]) < d[2];
        if (wet) {
          const double t = 1.0 + 0.03 * std::sin(0.37 * u + 0.11 * v) * std::cos(0.23 * v);
          row[u] = cv::Vec3b(cv::saturate_cast<uchar>(66 * t), cv::saturate_cast<uchar>(98 * t),
                             cv::saturate_cast<uchar>(128 * t));
        }
      }
    }
    // Balls carried up the lifted (left) side above the slurry pool, clear of its surface.
    // (Balls sitting ON the surface would hide it; see docs/vision.md for what that does.)
    auto shoulder = [&](const Ball& b) {
      return b.x < -0.6 * R && b.y > slurryTop(b.x) + b.r + 2.0 && b.y < slurryTop(b.x) + 2.5 * b.r;
    };
    for (const Ball& b : placeBalls(sc, rng, 300, shoulder)) drawBall(img, cam, b, 0.9);
  }

  // 3. Light: gradient, vignetting, glare on the window (fixed to the camera).
  cv::Mat f;
  img.convertTo(f, CV_32FC3);
  const double la = sc.light_dir_deg * kPi / 180.0;
  const double rmax = std::hypot(0.5 * W, 0.5 * H);
  double gu, gv;
  cam.toCanvas(0.35 * R, 0.55 * R, gu, gv);  // glare where the drum is empty for every test angle
  const double gs = 9.0 * cam.s;
  for (int v = 0; v < H; ++v) {
    cv::Vec3f* row = f.ptr<cv::Vec3f>(v);
    for (int u = 0; u < W; ++u) {
      const double along = ((u - 0.5 * W) * std::cos(la) + (v - 0.5 * H) * std::sin(la)) / W;
      const double rr = std::hypot(u - 0.5 * W, v - 0.5 * H) / rmax;
      const double light = (1.0 + sc.light_gradient * along) * (1.0 - sc.vignetting * rr * rr);
      double glare = 0.0;
      if (sc.glare) {
        const double du = (u - gu) / gs, dv = (v - gv) / (0.6 * gs);
        glare = 150.0 * std::exp(-0.5 * (du * du + dv * dv));
      }
      row[u] = row[u] * static_cast<float>(light) + cv::Vec3f(glare, glare, glare);
    }
  }

  // 4. Down to the frame size, then motion blur, noise, JPEG.
  cv::Mat frame;
  cv::resize(f, frame, cv::Size(sc.width, sc.height), 0, 0, cv::INTER_AREA);
  if (sc.motion_blur_px > 1.0) {
    const int k = 2 * static_cast<int>(std::ceil(0.5 * sc.motion_blur_px)) + 1;
    cv::Mat kernel = cv::Mat::zeros(k, k, CV_32F);
    const double a = sc.motion_blur_dir_deg * kPi / 180.0;
    const double c = 0.5 * (k - 1);
    cv::line(kernel, cv::Point2d(c - 0.5 * sc.motion_blur_px * std::cos(a), c + 0.5 * sc.motion_blur_px * std::sin(a)),
             cv::Point2d(c + 0.5 * sc.motion_blur_px * std::cos(a), c - 0.5 * sc.motion_blur_px * std::sin(a)),
             cv::Scalar(1.0), 1, cv::LINE_AA);
    kernel /= cv::sum(kernel)[0];
    cv::filter2D(frame, frame, -1, kernel, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  }
  if (sc.noise_sigma > 0.0) {
    cv::Mat noise(frame.size(), CV_32FC3);
    cv::theRNG().state = sc.seed * 31u + static_cast<unsigned>(index) + 1u;
    cv::randn(noise, 0.0, sc.noise_sigma);
    frame += noise;
  }
  cv::Mat out;
  frame.convertTo(out, CV_8UC3);
  if (sc.jpeg_quality > 0) {
    std::vector<uchar> buf;
    cv::imencode(".jpg", out, buf, {cv::IMWRITE_JPEG_QUALITY, sc.jpeg_quality});
    out = cv::imdecode(buf, cv::IMREAD_COLOR);
  }
  return out;
}

void writeVideo(const MillScene& sc, int frames, const std::string& path, const std::string& fourcc, double fps) {
  if (fourcc.size() != 4) throw std::runtime_error("writeVideo: fourcc must have 4 characters");
  cv::VideoWriter w(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]), fps,
                    cv::Size(sc.width, sc.height), true);
  if (!w.isOpened()) throw std::runtime_error("writeVideo: OpenCV cannot write " + path + " with codec " + fourcc);
  for (int i = 0; i < frames; ++i) w.write(renderFrame(sc, i));
}

void writeImages(const MillScene& sc, int frames, const std::string& dir, const std::string& ext) {
  std::filesystem::create_directories(dir);
  for (int i = 0; i < frames; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%04d.%s", i + 1, ext.c_str());
    const std::string path = (std::filesystem::path(dir) / name).string();
    if (!cv::imwrite(path, renderFrame(sc, i))) throw std::runtime_error("writeImages: cannot write " + path);
  }
}

}  // namespace millsim::synth
