#pragma once
// Frames of a mill recording: a video file (whatever OpenCV's FFmpeg backend decodes: mp4, avi,
// mov, mkv ...) or a folder of still images, sampled at N evenly spaced indices (Doroszek et al.
// 2024, section 3.7: "a set of 100 frames with equal time step between them is used").
// Every failure a user can cause (missing path, not a video, no decoder for the codec, empty
// folder, unreadable image) throws core::InputError with the path and the reason in one line.
#include <string>
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

struct FrameSequence {
  std::vector<ImageRgb> frames;  // the sampled frames, in time order
  std::vector<int> indices;      // their indices in the source (0-based)
  int total = 0;                 // frames (or images) in the source
  std::string source;            // the path read
};

// Indices of `count` evenly spaced frames of `total`: floor(i * total / count), i = 0..count-1,
// or all of them when count >= total. count <= 0 means all.
std::vector<int> evenlySpacedIndices(int total, int count);

// Decodes the video sequentially and keeps the sampled frames (seeking is unreliable in many
// codecs; grab() without retrieve() skips the colour conversion of the frames not kept).
FrameSequence readVideoFrames(const std::string& path, int count);

// Images (.png .jpg .jpeg .bmp .tif .tiff, any case) of a folder in natural name order
// (frame2 before frame10), sampled like a video. All must have the same size.
FrameSequence readImageFolder(const std::string& dir, int count);

}  // namespace millsim::vision
