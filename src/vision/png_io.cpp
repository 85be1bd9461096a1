// PNG I/O through libpng's "simplified" API (libpng >= 1.6). It reports errors through
// png_image::message instead of longjmp, which keeps setjmp out of C++ code with destructors.
#include "millsim/vision/png_io.hpp"

#include <png.h>

#include <cstdint>
#include <vector>

#include "millsim/core/error.hpp"

namespace millsim::vision {
namespace {

// Frees libpng's internal state if we leave between begin_read and finish_read (finish_read
// frees it itself; calling png_image_free twice is harmless because it clears `opaque`).
class PngImageGuard {
 public:
  explicit PngImageGuard(png_image& image) : m_image(image) {}
  ~PngImageGuard() { png_image_free(&m_image); }
  PngImageGuard(const PngImageGuard&) = delete;
  PngImageGuard& operator=(const PngImageGuard&) = delete;

 private:
  png_image& m_image;
};

void writeBytes(const std::string& path, int width, int height, std::uint32_t format, int channels,
                const std::uint8_t* data) {
  if (width <= 0 || height <= 0) {
    throw core::InputError(path + ": cannot write an empty image as PNG");
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = format;
  const auto stride = static_cast<png_int_32>(width * channels);
  if (!png_image_write_to_file(&image, path.c_str(), 0, data, stride, nullptr)) {
    throw core::InputError(path + ": cannot write PNG: " + image.message);
  }
}

}  // namespace

void writePng(const std::string& path, const ImageU8& image) {
  writeBytes(path, image.width, image.height, PNG_FORMAT_GRAY, 1, image.pixels.data());
}

void writePng(const std::string& path, const ImageRgb& image) {
  // Copy to a packed byte buffer rather than rely on sizeof(Rgb) == 3.
  std::vector<std::uint8_t> bytes;
  bytes.reserve(image.pixels.size() * 3);
  for (const Rgb& p : image.pixels) {
    bytes.push_back(p.r);
    bytes.push_back(p.g);
    bytes.push_back(p.b);
  }
  writeBytes(path, image.width, image.height, PNG_FORMAT_RGB, 3, bytes.data());
}

ImageU8 readPngGray(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    throw core::InputError(path + ": cannot read PNG: " + image.message);
  }
  PngImageGuard guard(image);
  image.format = PNG_FORMAT_GRAY;
  // Zero-filled, because with a null background libpng composites alpha onto the buffer.
  ImageU8 out(static_cast<int>(image.width), static_cast<int>(image.height), 0);
  if (!png_image_finish_read(&image, nullptr, out.pixels.data(), 0, nullptr)) {
    throw core::InputError(path + ": cannot decode PNG: " + image.message);
  }
  return out;
}

}  // namespace millsim::vision
