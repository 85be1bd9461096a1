#pragma once
// Binary mask of the charge in one normalised view (mill_view.hpp), without learned weights.
// The paper used Meta's SAM for balls and a direct threshold for dry ore (Doroszek et al. 2024,
// sections 3.7.1-3.7.2); both are replaced here by classical cues that do not depend on how
// brightly a part of the drum is lit:
//
// balls  Local contrast: c = sd / (mean + dark_offset) of the (denoised) gray level over a
//        square window of texture_window_mm, computed from masked box sums so the drum rim does
//        not leak in. A bed of steel balls is all highlights, shading and dark gaps (c ~ 0.3-1);
//        the empty back of the drum is smooth (c ~ noise / level). A ratio, so a multiplicative
//        lighting gradient cancels, and a specular highlight only adds contrast. Threshold: Otsu
//        over the drum unless texture_threshold > 0.
// dry    The paper's direct threshold, made illumination-proof by a two-class model with slowly
//        varying class means: a first Otsu split gives charge and background; each class's gray
//        level is smoothed over illumination_sigma_mm by normalised convolution (sum of
//        class pixels / sum of class weights, so each field is filled in where that class is
//        absent), and a pixel is charge where it is above the mid-point of the two fields
//        (below it with charge_brighter = false). Three rounds. A fixed intensity_threshold > 0
//        (gray level 0-255) skips the model.
//
// Then, for both: closing (close_mm: bridges the gaps between balls, highlights and grains),
// opening (open_mm: removes specks), connected components smaller than min_component_fraction
// of the largest dropped (balls in flight, glare on the window, bolt heads on the back plate:
// the heat map removes what moves, this removes what is still but detached), holes filled.
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

enum class ChargeMode { Balls, Dry };

struct SegmentationOptions {
  ChargeMode mode = ChargeMode::Balls;
  double denoise_sigma_px = 1.0;        // Gaussian pre-smoothing (sensor noise, codec blocks); 0: none
  double texture_window_mm = 8.0;       // balls: side of the local-contrast window
  double texture_threshold = 0.0;       // balls: contrast threshold; 0: Otsu over the drum
  double dark_offset = 10.0;            // balls: gray levels added to the mean, so near-black noise is not contrast
  double illumination_sigma_mm = 40;    // dry: scale of the class-mean fields (the lighting's scale)
  double intensity_threshold = 0.0;     // dry: fixed gray-level threshold; 0: the two-class model
  bool charge_brighter = true;          // dry: ore brighter than the empty drum
  double close_mm = 5.0;                // closing radius; 0: none
  double open_mm = 2.0;                 // opening radius; 0: none
  double min_component_fraction = 0.2;  // keep components at least this fraction of the largest
};

// `view` and `mask` (255 = analysed) of equal size; `pixels_per_mm` converts the mm options.
// Returns 255 for charge, 0 elsewhere (always 0 outside the mask). Throws std::invalid_argument
// for mismatched sizes or bad options.
ImageU8 segmentCharge(const ImageRgb& view, const ImageU8& mask, double pixels_per_mm, const SegmentationOptions& opt);

// Otsu's threshold of `values` (256 bins between the smallest
// value and the 99.5th percentile). Exposed for tests.
double otsuThreshold(const std::vector<float>& values);

}  // namespace millsim::vision
