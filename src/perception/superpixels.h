// SLIC superpixels on a rendered view, and the CIE LAB image the observations are computed on.
//
//   ImageF32 lab = RgbToLab(view.rgb);
//   Result<Superpixels> sp = ComputeSuperpixels(view.rgb, SuperpixelOptions{});
//   int id = sp->label.at(x, y);   // in [0, sp->count)
//
// OpenCV (ximgproc's SLIC) stays inside superpixels.cc.
#pragma once

#include <cstdint>
#include <string>

#include "core/image.h"
#include "core/status.h"

namespace semvox {

struct SuperpixelOptions {
  // Average superpixel side, pixels (SLIC's region size). [4, 256]. At 640x480, 20 px gives ~770 superpixels.
  int region_size_px = 20;
  // SLIC compactness: weight of the spatial term against LAB colour distance. > 0.
  double compactness = 10.0;
  // SLIC k-means iterations. [1, 100]. 4 keeps a 640x480 view under 150 ms from superpixels to tree BP
  // (perception_bench: SLIC 79 ms at 4 iterations, 184 ms at 10, NYU-4 accuracy unchanged).
  int iterations = 4;
  // Segments smaller than this percentage of the average superpixel area are merged into a neighbour
  // (connectivity enforcement). [0, 100].
  int min_element_size_percent = 25;

  bool Check(std::string* error) const;
};

struct Superpixels {
  Image<int32_t> label;  // Superpixel id of every pixel, in [0, count); every id in that range is used.
  int count = 0;
};

// Over-segments `rgb` (3 channels) with SLIC on its LAB values. Fails on an empty image or bad options.
Result<Superpixels> ComputeSuperpixels(const ImageRgb8& rgb, const SuperpixelOptions& options);

// CIE L*a*b* (D65) of every pixel of `rgb` (sRGB): 3 float channels, L in [0, 100], a and b about
// [-128, 127].
ImageF32 RgbToLab(const ImageRgb8& rgb);

}  // namespace semvox
