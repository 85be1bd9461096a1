// Video and image-folder input for the vision pipeline (see frame_source.hpp).
#include "millsim/vision/frame_source.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "millsim/core/error.hpp"
#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

namespace fs = std::filesystem;

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" || ext == ".tiff";
}

// Natural order: digit runs compare as numbers, so frame2.png < frame10.png.
bool naturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t i1 = i, j1 = j;
      while (i1 < a.size() && std::isdigit(static_cast<unsigned char>(a[i1]))) ++i1;
      while (j1 < b.size() && std::isdigit(static_cast<unsigned char>(b[j1]))) ++j1;
      std::string da = a.substr(i, i1 - i), db = b.substr(j, j1 - j);
      da.erase(0, std::min(da.find_first_not_of('0'), da.size()));
      db.erase(0, std::min(db.find_first_not_of('0'), db.size()));
      if (da.size() != db.size()) return da.size() < db.size();
      if (da != db) return da < db;
      i = i1;
      j = j1;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

// OpenCV logs backend failures to stderr over several lines; the InputError thrown instead says
// it in one. Restores the previous level when reading is done.
class QuietOpenCvLog {
 public:
  QuietOpenCvLog() : m_previous(cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT)) {}
  ~QuietOpenCvLog() { cv::utils::logging::setLogLevel(m_previous); }
  QuietOpenCvLog(const QuietOpenCvLog&) = delete;
  QuietOpenCvLog& operator=(const QuietOpenCvLog&) = delete;

 private:
  cv::utils::logging::LogLevel m_previous;
};

void openVideo(cv::VideoCapture& cap, const std::string& path) {
  // FFmpeg only (Debian's OpenCV has it; it reads mp4 and avi): CAP_ANY would also try the
  // image-sequence backend, which reads "%d" in a name, and GStreamer, which prints pages of
  // warnings to stderr for a file it cannot play instead of failing quietly.
  cap.open(path, cv::CAP_FFMPEG);
}

}  // namespace

std::vector<int> evenlySpacedIndices(int total, int count) {
  std::vector<int> idx;
  if (total <= 0) return idx;
  if (count <= 0 || count >= total) {
    for (int i = 0; i < total; ++i) idx.push_back(i);
    return idx;
  }
  for (int i = 0; i < count; ++i) idx.push_back(static_cast<int>(static_cast<long long>(i) * total / count));
  return idx;
}

FrameSequence readVideoFrames(const std::string& path, int count) {
  if (!fs::exists(path)) throw core::InputError(path + ": no such video file");
  if (fs::is_directory(path)) throw core::InputError(path + ": is a folder; use --images for a folder of frames");
  const QuietOpenCvLog quiet;
  cv::VideoCapture cap;
  openVideo(cap, path);
  if (!cap.isOpened())
    throw core::InputError(path + ": cannot open as a video (not a video file, or no decoder for its codec)");
  int total = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_COUNT));
  FrameSequence seq;
  seq.source = path;
  cv::Mat frame;
  if (total <= 0) {
    // Container without a frame count: count by decoding, then read again.
    total = 0;
    while (cap.grab()) ++total;
    cap.release();
    openVideo(cap, path);
  }
  if (total <= 0) throw core::InputError(path + ": the video has no decodable frames (unsupported codec?)");
  const std::vector<int> want = evenlySpacedIndices(total, count);
  std::size_t next = 0;
  for (int i = 0; i < total && next < want.size(); ++i) {
    if (!cap.grab()) break;  // the container's frame count was an estimate; keep what decoded
    if (i != want[next]) continue;
    if (!cap.retrieve(frame) || frame.empty()) {
      throw core::InputError(path + ": cannot decode frame " + std::to_string(i) + " (unsupported codec?)");
    }
    seq.frames.push_back(detail::toImageRgb(frame));
    seq.indices.push_back(i);
    ++next;
  }
  if (seq.frames.empty())
    throw core::InputError(path + ": no frame could be decoded (unsupported codec or damaged file)");
  seq.total = total;
  return seq;
}

FrameSequence readImageFolder(const std::string& dir, int count) {
  if (!fs::exists(dir)) throw core::InputError(dir + ": no such folder");
  if (!fs::is_directory(dir)) throw core::InputError(dir + ": not a folder (use --video for a video file)");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && isImageFile(entry.path())) names.push_back(entry.path().filename().string());
  }
  if (names.empty()) throw core::InputError(dir + ": no images (.png .jpg .jpeg .bmp .tif .tiff) in the folder");
  std::sort(names.begin(), names.end(), naturalLess);
  FrameSequence seq;
  seq.source = dir;
  seq.total = static_cast<int>(names.size());
  for (int i : evenlySpacedIndices(seq.total, count)) {
    const std::string file = (fs::path(dir) / names[i]).string();
    cv::Mat img;
    {
      const QuietOpenCvLog quiet;
      img = cv::imread(file, cv::IMREAD_COLOR);
    }
    if (img.empty()) throw core::InputError(file + ": cannot read as an image");
    if (!seq.frames.empty() && (img.cols != seq.frames.front().width || img.rows != seq.frames.front().height)) {
      throw core::InputError(file + ": is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                             " but the first image is " + std::to_string(seq.frames.front().width) + "x" +
                             std::to_string(seq.frames.front().height));
    }
    seq.frames.push_back(detail::toImageRgb(img));
    seq.indices.push_back(i);
  }
  return seq;
}

}  // namespace millsim::vision
