// Gaussian filtering of points with low-dimensional features on a regular grid with cubic interpolation
// (a dense "bilateral grid", Paris and Durand 2006 / Chen et al. 2007, with Keys' cubic convolution kernel
// instead of multilinear weights):
//
//   CubicGrid grid;
//   grid.Build(features, n, d, spacing);   // features already divided by the kernel's standard deviations,
//                                          // spacing: d node spacings in standard deviations
//   grid.Filter(values, m, &filtered);     // filtered_i ~ sum_j exp(-|f_i - f_j|^2 / 2) v_j
//
// Splat: every point adds its value to the 4^d grid nodes around it with the weights of Keys' cubic
// (a = -1/2, interpolating, third-order accurate); blur: the sampled unit Gaussian exp(-(k h)^2 / 2), k in
// [-T, T], T = ceil(4.5 / h), along each axis; slice: the same cubic weights. The effective kernel is the
// cubic interpolant, in both points, of the Gaussian sampled on the grid: its error against the Gaussian is
// O(h^3) per axis (measured in 1-D: at most 7.2e-4 of the peak at h = 1/4, 1.8e-3 at 1/3, 7.8e-3 at 1/2).
// The grid spans the points' bounding box (+2 nodes): cells = prod_k (extent_k / h + 4), so this is for
// d <= 3 and compact features; Build reports the size first (CellsFor) so that callers can choose.
// Float grid (the splat and slice accumulate in float, the blur along the last axis in double); deterministic
// (the splat goes into a fixed number of partial grids summed in a fixed order).
#pragma once

#include <cstdint>
#include <vector>

namespace semvox {

class CubicGrid {
 public:
  // Grid nodes Build would allocate for these features; -1 when d is out of [1, 4] or a feature is not finite.
  static int64_t CellsFor(const float* features, int n, int d, const std::vector<double>& spacing);
  static constexpr double kTruncation = 4.5;  // Blur radius, standard deviations.
  // `features`: n rows of d floats (row-major), already scaled by the kernel's inverse standard deviations.
  // d in [1, 4], `spacing`: d values h_k in (0, 1] (standard deviations). Throws std::invalid_argument otherwise.
  void Build(const float* features, int n, int d, const std::vector<double>& spacing);
  // `in`: n rows of m values; `out` receives n rows of m values (resized).
  void Filter(const float* in, int m, std::vector<float>* out) const;

  int num_points() const { return n_; }
  int64_t num_cells() const { return cells_; }

 private:
  int n_ = 0, d_ = 0;
  int64_t cells_ = 0;
  std::vector<int> size_;            // Nodes per axis.
  std::vector<int64_t> stride_;      // Linear stride per axis.
  std::vector<int64_t> base_;        // n: linear index of the point's first (lowest) node.
  std::vector<float> weight_;        // n x d x 4: cubic weights of the 4 nodes per axis.
  std::vector<std::vector<double>> taps_;  // Per axis: Gaussian taps g[0..T].
};

}  // namespace semvox
