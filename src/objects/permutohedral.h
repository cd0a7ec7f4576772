// Gaussian filtering in a high-dimensional feature space with the permutohedral lattice (Adams, Baek and
// Davis 2010), the O(N) message passing step of dense CRF mean-field (Kraehenbuehl and Koltun 2011, Sec. 4).
//
//   PermutohedralLattice lattice;
//   lattice.Build(features, n, d);          // features already divided by the kernel's standard deviations
//   lattice.Filter(values, m, &filtered);   // filtered_i = sum_j exp(-|f_i - f_j|^2 / 2) v_j (approximately)
//
// Build embeds every point in the d-dimensional hyperplane of Z^{d+1} (the lattice A*_d), finds the
// enclosing simplex and its barycentric weights and records the d+1 lattice vertices of every point.
// Filter is then splat (points -> vertices, barycentric weights), blur (a [1 2 1]/4 filter, r times along
// each of the d+1 lattice directions) and slice (vertices -> points). Both are linear in n: Build O(n d^2 +
// L d r), Filter O(n d m + L d r m) for L lattice vertices (L <= n (d+1) at r = 1; a refined lattice, r > 1,
// also holds the vertices its blur passes through, up to a factor (2r+1)^(d-2) more around the 2-D image
// manifold). The lattice is built once per kernel and reused for every mean-field iteration.
//
// The filter approximates the Gaussian; the self term (j = i) is included. Error against the exact sum: see
// tests/objects/permutohedral_test.cc and docs/objects.md.
#pragma once

#include <cstdint>
#include <vector>

namespace semvox {

class PermutohedralLattice {
 public:
  // `features`: n rows of d floats (row-major), each already scaled by the inverse standard deviation of the
  // kernel. d in [1, 16].
  // `refinement` r >= 1: the features are scaled by s = sqrt((3 r + 1) / 4) before the embedding and the
  // blur is r passes of [1 2 1] / 4 along each direction, so that the filter keeps unit standard deviation
  // (blur variance 3 r / 4 and splat + slice 1 / 4, in units of the scaled features) while the lattice is
  // s times finer relative to it. r = 1 is the lattice of Adams et al.; larger r is more accurate and
  // costs more vertices (up to s^d times) and r times the blur.
  void Build(const float* features, int n, int d, int refinement = 1);
  // `in`: n rows of m values; `out` receives n rows of m values (resized).
  void Filter(const float* in, int m, std::vector<float>* out) const;

  int num_points() const { return n_; }
  int dims() const { return d_; }
  int num_vertices() const { return num_vertices_; }
  int refinement() const { return refinement_; }
  static double RefinementScale(int refinement);
  static constexpr int kMaxRefinement = 64;

 private:
  int n_ = 0, d_ = 0, num_vertices_ = 0, refinement_ = 1;
  std::vector<int32_t> offset_;     // n (d+1): vertex index of each of the point's simplex corners.
  std::vector<double> barycentric_;  // n (d+1).
  // The splat as a gather: for vertex v, splat_entry_[splat_start_[v] .. splat_start_[v + 1]) are the
  // entries k = p (d+1) + r with offset_[k] = v, ascending (the order of a sequential splat over the points),
  // so that the vertices can be filled in parallel with the sums of a sequential splat.
  std::vector<int32_t> splat_start_, splat_entry_;
  // Blur neighbours: for each direction j in [0, d] and vertex v, the vertex at -1 and +1 along j (or -1).
  std::vector<int32_t> neighbour_minus_, neighbour_plus_;  // (d+1) L each.
};

}  // namespace semvox
