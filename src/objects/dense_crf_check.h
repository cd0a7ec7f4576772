// The small image on which the permutohedral mean-field is checked against brute force, shared
// by DenseCrf.PermutohedralMeanFieldMatchesBruteForce (tests/objects/permutohedral_test.cc) and
// bench/support_bench.cc, so that both measure the same case with the same settings.
//
// 40 x 30 pixels: a raised "table top" (x in [9, 31], y in [13, 29]: height 0.75 m, normal up, light RGB)
// beside a wall (height 1.5 - 0.02 y m, normal +x, dark RGB), RGB noise 0..9, noisy unaries (seed 7).
// All four kernels of the pipeline (appearance, smoothness, height, normal) at their configured scales
// except theta_beta = 8 px (40 px at 640 x 480, scaled with the image); weights 1, which keep the marginals
// away from 0 and 1, where any two solvers agree trivially. The filters are the pipeline's defaults
// (DenseCrfOptions{}: exact separable smoothness, height on the cubic grid, 5-D kernels on the lattice).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/image.h"
#include "objects/dense_crf.h"

namespace semvox {

struct SyntheticCrfImage {
  ImageRgb8 rgb;
  ImageF32 height, normal;
  std::vector<float> p;  // n x 3 unary probabilities; the true class is 0 on the top, 2 elsewhere.
};

inline SyntheticCrfImage MakeSyntheticCrfImage() {
  const int w = 40, h = 30, m = 3;
  SyntheticCrfImage im{ImageRgb8(w, h, 3), ImageF32(w, h, 1), ImageF32(w, h, 3), std::vector<float>(size_t(w * h * m))};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool top = y > 12 && x > 8 && x < 32;
      for (int c = 0; c < 3; ++c) im.rgb.at(x, y, c) = uint8_t(uint8_t(top ? 150 + 10 * c : 60 + 20 * c) + uint8_t(u(rng) * 10));
      im.height.at(x, y) = top ? 0.75f : 1.5f - y * 0.02f;
      im.normal.at(x, y, top ? 2 : 0) = 1.f;
      const int truth = top ? 0 : 2;
      float s = 0;
      for (int l = 0; l < m; ++l) s += (im.p[size_t((y * w + x) * m + l)] = (l == truth ? 1.2f : 0.5f) * u(rng) + 0.05f);
      for (int l = 0; l < m; ++l) im.p[size_t((y * w + x) * m + l)] /= s;
    }
  return im;
}

inline DenseCrfOptions SyntheticCrfOptions() {
  DenseCrfOptions options;
  options.position_scale_px = 8;
  options.appearance_weight = options.smoothness_weight = options.height_weight = options.normal_weight = 1.0;
  return options;
}

}  // namespace semvox
