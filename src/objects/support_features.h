// Per-superpixel features of the support/clutter paper (Sec. 4.1, Table 2), the SVM's input:
//
//   F1  height of the 3D centroid (world z, metres; the map's floor is at z = 0 for generated apartments)
//   F2  the unit normal's components: along the camera's horizontal right and forward directions and up
//   F3  mean local entropy (Eq. 1, bits) of R, G and B in a 9 x 9 window
//   F4  mean local entropy of the depth in a 9 x 9 window
//
// Choices where the paper leaves room (docs/objects.md):
// - The normal is the mean of the rendered per-pixel world normals of the superpixel (normalised), not a
//   plane fit at the centroid; its horizontal components are taken in the camera's yaw frame (right,
//   forward), so that the feature does not change when the whole room is rotated about z.
// - Depth is quantised in `depth_bin_m` steps (256 bins, wrapping) for its entropy histogram; pixels
//   without depth fall in their own bin.
// - Superpixels with fewer than `min_depth_fraction` pixels with depth have height 0 and normal 0 and are
//   flagged (`has_depth` false).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "perception/superpixels.h"
#include "render/view_renderer.h"

namespace semvox {

enum SupportFeatureDim : int {
  kSupportHeight = 0,
  kSupportNormalRight, kSupportNormalForward, kSupportNormalUp,
  kSupportEntropyR, kSupportEntropyG, kSupportEntropyB,
  kSupportEntropyDepth,
};
inline constexpr int kSupportFeatureDims = 8;

struct SupportFeatureOptions {
  int entropy_window_px = 9;        // Side of the entropy window, pixels (the paper's 9 x 9). Odd, [3, 31].
  double depth_bin_m = 0.01;        // Depth quantisation for its entropy histogram, metres. > 0.
  double min_depth_fraction = 0.5;  // Superpixels with fewer pixels with depth have no 3D features. (0, 1].

  bool Check(std::string* error) const;
};

struct SupportFeatures {
  int count = 0;                 // Superpixels.
  std::vector<float> rows;       // count x kSupportFeatureDims, indexed by SupportFeatureDim.
  std::vector<uint8_t> has_depth;
  std::vector<int> pixel_count;
};

// Eq. 1 at every pixel: entropy (bits) of the 256-bin histogram of `channel` in the window x window
// neighbourhood (clipped at the image border). O(1) per pixel and window column (sliding histogram).
ImageF32 LocalEntropy(const Image<uint8_t>& channel, int window);

// Table 2 features of every superpixel of `view` (rgb, depth, normal, camera pose).
Result<SupportFeatures> ComputeSupportFeatures(const RenderedView& view, const Superpixels& superpixels,
                                               const SupportFeatureOptions& options);

}  // namespace semvox
