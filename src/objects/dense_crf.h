// The fully connected pixel CRF of the support/clutter paper (Sec. 5, Eq. 2-4), solved by mean-field
// (Sec. 5.3, after Kraehenbuehl and Koltun 2011).
//
//   DenseCrfInput input{&view.rgb, &height, &normal};             // per-pixel features
//   Result<DenseCrf> crf = DenseCrf::Create(input, DenseCrfOptions{});
//   std::vector<float> q = crf->MeanField(unary_probabilities, 3);  // n x 3 marginals
//
// Energy: unary psi_u(x_i = l) = -log p_i(l) (Eq. 3 turns the SVM's probabilities into the unary; we take
// their negative log, as Kraehenbuehl and Koltun do, so that exp(-psi_u) = p), Potts compatibility
// mu(l, l') = [l != l'], and the four Gaussian kernels of Sec. 5.2:
//   appearance  w1 exp(-|p_i - p_j|^2 / 2 theta_beta^2 - |I_i - I_j|^2 / 2 theta_v^2)
//   smoothness  w2 exp(-|p_i - p_j|^2 / 2 theta_p^2)
//   height      w3 exp(-|p_i - p_j|^2 / 2 theta_beta^2 - |h_i - h_j|^2 / 2 theta_q^2)
//   normal      w4 exp(-|p_i - p_j|^2 / 2 theta_beta^2 - |n_i - n_j|^2 / 2 theta_n^2)
// Each kernel is normalised per pixel, k~_m(i, j) = k_m(f_i, f_j) / Z_m,i with Z_m,i = sum_j k_m(f_i, f_j)
// (the row normalisation of Kraehenbuehl and Koltun 2013, "Parameter learning and convergent inference for
// dense random fields"): a message is then a weighted average of Q over the kernel's support, the weights
// do not depend on the image size, and the lattice's errors in the kernel's mass cancel between numerator
// and normaliser. The sums include j = i (as the lattice does).
// Mean-field update (parallel over pixels, K&K 2011 Algorithm 1):
//   Q_i(l) ∝ exp(-psi_u(l) + sum_m w_m sum_j k~_m(i, j) Q_j(l)).
// The message passing is a Gaussian filter. The smoothness kernel depends on pixel position only and the
// points are the view's full pixel grid (every pixel is a point), so it is summed exactly by a separable
// convolution on the grid (two 1-D passes, radius ceil(5 theta_p); the truncated tail moves a normalised
// message by at most 2 * 2 Phi(-5) ~ 2.3e-6). The height kernel (3-D) is filtered on a regular grid with
// cubic interpolation (cubic_grid.h), the 5-D appearance and normal kernels on the permutohedral lattice
// (O(n), permutohedral.h). `brute_force` takes the exact O(n^2) sums of all four (tests and benchmarks).
// Pixels without depth take height 0 and normal 0 in the height and normal kernels.
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "objects/cubic_grid.h"
#include "objects/permutohedral.h"

namespace semvox {

struct DenseCrfOptions {
  int iterations = 5;
  double appearance_weight = 3.0;       // w1 (on the normalised kernel, as all weights). >= 0.
  double position_scale_px = 40.0;      // theta_beta, pixels (appearance, height and normal kernels). > 0.
  double colour_scale = 13.0;           // theta_v, RGB units (0..255). > 0.
  double smoothness_weight = 1.0;       // w2. >= 0.
  double smoothness_scale_px = 3.0;     // theta_p, pixels. > 0.
  double height_weight = 2.0;           // w3. >= 0.
  double height_scale_m = 0.1;          // theta_q, metres. > 0.
  double normal_weight = 2.0;           // w4. >= 0.
  double normal_scale = 0.3;            // theta_n, on unit normals. > 0.
  double probability_floor = 1e-4;      // Unary probabilities are clamped below by this. (0, 0.5).
  // Smoothness kernel by the exact separable convolution on the pixel grid (default) or, false, by a 2-D
  // permutohedral lattice at lattice_refinement (kept to measure the lattice against it).
  bool exact_smoothness = true;
  // Height kernel (3-D: x, y / theta_beta, h / theta_q) on a regular grid with cubic interpolation
  // (cubic_grid.h), node spacing in standard deviations along the height and the two position axes, (0, 1];
  // height_grid_spacing 0: on the permutohedral lattice at lattice_refinement. A grid above kMaxGridCells
  // nodes (a height range above ~50 m at 640 x 480) takes the lattice.
  double height_grid_spacing = 0.25;
  double height_grid_position_spacing = 0.5;
  static constexpr int64_t kMaxGridCells = int64_t(1) << 21;  // ~300 MB of splat and blur buffers at m = 3.
  // PermutohedralLattice::Build's refinement r (lattice s = sqrt((3r + 1) / 4) times finer, r blur passes):
  // for the height (3-D) kernel (and the smoothness kernel without exact_smoothness), and for the
  // appearance and normal (5-D) kernels, whose refined lattices cost far more vertices (the image's 2-D
  // manifold thickened in 3 dimensions). [1, 64]. With the default filters above, refinement 1 / 1 keeps
  // the mean-field within 1e-3 of brute force (7.1e-4) on the check image (objects/dense_crf_check.h;
  // docs/objects.md has the table by setting).
  int lattice_refinement = 1;
  int lattice_refinement_5d = 1;

  // The fields users set (section `objects`): meaning, unit and range.
  static const OptionTable<DenseCrfOptions>& Options() {
    using O = DenseCrfOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::iterations, "iterations", 0, 100, "", "dense CRF mean-field iterations"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct DenseCrfInput {
  const ImageRgb8* rgb = nullptr;     // 3 channels.
  const ImageF32* height = nullptr;   // 1 channel: world z of the pixel's hit, metres (0 without depth).
  const ImageF32* normal = nullptr;   // 3 channels: unit world normal (0 without depth).
};

class DenseCrf {
 public:
  static Result<DenseCrf> Create(const DenseCrfInput& input, const DenseCrfOptions& options);

  // `probabilities`: n x m unary probabilities (row-major, n = width * height). Returns n x m marginals
  // after options.iterations mean-field updates. `brute_force` sums the kernels exactly (O(n^2)).
  std::vector<float> MeanField(const std::vector<float>& probabilities, int m, bool brute_force = false) const;
  // One message-passing step: out_i(l) = sum_m w_m sum_j k~_m(i, j) q_j(l).
  void Messages(const std::vector<float>& q, int m, bool brute_force, std::vector<float>* out) const;
  // Exact message for pixel i only (the benchmark extrapolates brute force from a sample of pixels).
  void BruteForceMessage(int i, const std::vector<float>& q, int m, float* out) const;

  int num_pixels() const { return n_; }

 private:
  struct Kernel {
    double weight = 0;
    int dims = 0;
    std::vector<float> features;  // n x dims, divided by the standard deviations.
    PermutohedralLattice lattice;
    std::vector<float> grid_taps;  // Non-empty: exact separable convolution on the pixel grid, taps g[0..R].
    bool on_cubic_grid = false;    // Filtered by `cubic` instead of `lattice`.
    std::vector<float> normaliser;  // n: Z_i = sum_j k(f_i, f_j), filtered once by Create.
    CubicGrid cubic;
  };
  // Messages; with rows_sum_to_one (q holds marginals) the last label's message comes from the normaliser.
  void Messages(const std::vector<float>& q, int m, bool brute_force, bool rows_sum_to_one, std::vector<float>* out) const;
  // Filters `in` (n x m1) with kernel k (separable grid convolution, cubic grid or lattice) into `out`.
  void Filter(const Kernel& k, const std::vector<float>& in, int m1, std::vector<float>* out) const;
  int n_ = 0, width_ = 0, height_ = 0;
  DenseCrfOptions options_;
  std::vector<Kernel> kernels_;
};

// The mean-field on a grid `factor` times coarser than the input, for views where the pixel CRF is most of
// the cost: each factor x factor block of pixels becomes one point with the block's mean colour, mean height
// and normalised mean normal over its pixels with depth (a non-zero normal; 0 where none has depth) and the
// mean of its pixels' unary probabilities; the pixel scales (theta_beta, theta_p) are divided by the factor,
// so the kernels keep their extent in the view. options.iterations - 1 updates run on the coarse grid; the
// last update is each pixel's own: its unary plus the message its block receives from the coarse marginals.
// So a pixel keeps its own unary's detail (the superpixel borders) while the messages, Gaussian sums over
// tens of pixels, are taken on a quarter of the points (factor 2). factor 1 is DenseCrf::MeanField.
Result<std::vector<float>> CoarseGridMeanField(const DenseCrfInput& input, const DenseCrfOptions& options,
                                               const std::vector<float>& probabilities, int m, int factor);

}  // namespace semvox
