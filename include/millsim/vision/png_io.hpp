#pragma once
// PNG input/output for the angle-of-repose pipeline (Doroszek et al. 2024, section 3.7: the
// charge is analysed from binary images of 100 frames, and the detected line is drawn over a
// frame for checking, Figure 12). Plain libpng, so the library needs no OpenCV for this step.
#include <string>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

// 8-bit grayscale PNG. Throws core::InputError ("<path>: ...") if the file cannot be written
// or the image is empty (PNG has no zero-size images).
void writePng(const std::string& path, const ImageU8& image);

// 8-bit RGB PNG, same errors as above.
void writePng(const std::string& path, const ImageRgb& image);

// Any PNG (gray, palette, RGB, with or without alpha, 8 or 16 bit) as 8-bit gray. libpng does
// the conversion: colour -> luminance with sRGB weights, alpha composited onto black. An 8-bit
// gray file comes back byte for byte. Throws core::InputError ("<path>: ...") on failure.
ImageU8 readPngGray(const std::string& path);

}  // namespace millsim::vision
