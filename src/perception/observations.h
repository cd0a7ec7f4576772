// The 15-D local observation of every superpixel of a view: Table 1 of the MST-CRF semantic parsing paper
// (Sec. 3.3), 8 image features then 7 3D features.
//
//   image:  L, a, b means; L, a, b standard deviations; vertical position of the centroid;
//           entropy H_s of the vanishing-direction memberships of its boundary edge pixels (Eq. 5)
//   3D:     centroid height h_s and depth d_s; mean and std of |d_s - d_j| over image neighbours j when
//           the superpixel is in front of them (d_s < mean d_j), else 0; planarity 3 l3 / (l1 + l2 + l3);
//           neighbourhood planarity 1 - mean |n_s . n_j|; orientation |horizontal part of n_s|.
//
// Where a superpixel has no depth (mesh holes, beyond the render's max depth) its 3D features take the
// table's default, 0, and `has_depth` is false: the union-coverage CRF gives it the image-only unary.
//
// Choices where the paper leaves room (docs/perception.md):
// - Vertical position is normalised by the image height (resolution-independent).
// - The vanishing directions are the world axes seen through the view's known rotation (the Manhattan
//   frame of a generated or aligned apartment), instead of estimating them with the gradient mixture
//   model; an edge pixel (Sobel magnitude on L >= edge_gradient_min) belongs to the vanishing point its
//   edge direction points at within vanishing_angle_max_deg, or to the fourth bin "none".
// - Planarity uses the eigenvalues of the points' covariance (the squared singular values of the centred
//   points, up to 1/n); the normal is the smallest eigenvector, turned towards the camera.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "perception/superpixels.h"
#include "render/view_renderer.h"

namespace semvox {

// Indices into SuperpixelObservation::z.
enum ObservationDim : int {
  kObsLabMeanL = 0, kObsLabMeanA, kObsLabMeanB, kObsLabStdL, kObsLabStdA, kObsLabStdB,
  kObsVerticalPosition,   // Centroid row / image height, [0, 1], 0 at the top.
  kObsVanishingEntropy,   // H_s, Eq. 5, natural log, [0, log 4].
  kObsHeight,             // World z of the 3D centroid, metres.
  kObsDepth,              // Mean depth along the optical axis, metres.
  kObsInFrontMean,        // Mean |d_s - d_j|, metres.
  kObsInFrontStd,         // Std |d_s - d_j|, metres.
  kObsPlanarity,          // 3 l3 / (l1 + l2 + l3), [0, 1], 0 for a plane.
  kObsNeighbourPlanarity, // 1 - mean |n_s . n_j|, [0, 1].
  kObsOrientation,        // Length of the horizontal part of the unit normal, 0 floor/ceiling, 1 wall.
};
inline constexpr int kImageObservationDims = 8;  // Image features only: the f1 unary's input.
inline constexpr int kObservationDims = 15;      // Image + 3D: the f2 unary's input.

struct ObservationOptions {
  // A superpixel has depth when at least this fraction of its pixels hit a surface. (0, 1].
  double min_depth_fraction = 0.5;
  // Boundary pixels with a Sobel gradient magnitude of L below this are not edges (not counted in H_s),
  // L units per pixel (Sobel 3x3 normalised by 1/8). >= 0.
  double edge_gradient_min = 2.0;
  // Largest angle between an edge's direction and the direction to a vanishing point for the pixel to
  // belong to that vanishing point, degrees. (0, 90).
  double vanishing_angle_max_deg = 5.0;

  bool Check(std::string* error) const;
};

struct SuperpixelObservation {
  std::array<float, kObservationDims> z{};  // Indexed by ObservationDim.
  bool has_depth = false;
  int pixel_count = 0;
  int hit_count = 0;                                   // Pixels with depth.
  Eigen::Vector3f lab_mean = Eigen::Vector3f::Zero();  // Also z[0..2], kept for the pairwise terms.
  Eigen::Vector3d centroid_world = Eigen::Vector3d::Zero();  // Mean hit point; zero without depth.
  Eigen::Vector3d normal_world = Eigen::Vector3d::Zero();    // Unit; zero without depth or < 3 points.
  Eigen::Vector2d centroid_px = Eigen::Vector2d::Zero();     // Mean pixel centre (x + 0.5, y + 0.5).
};

struct ViewObservations {
  std::vector<SuperpixelObservation> superpixels;  // Indexed by superpixel id.
  // Pairs (i, j), i < j, of superpixels sharing a 4-connected pixel border; sorted, unique.
  std::vector<std::pair<int, int>> image_adjacency;
};

// Computes the observation of every superpixel of `view` (rgb, depth, normal and camera are read).
// `superpixels.label` must have the view's size.
Result<ViewObservations> ComputeObservations(const RenderedView& view, const Superpixels& superpixels,
                                             const ObservationOptions& options);

// Membership of every pixel to the vanishing points of the world axes (Sec. 3.3.1): -1 where the pixel is
// not an edge (Sobel magnitude of L below edge_gradient_min, or on the image border), 0/1/2 for the
// vanishing point of world X/Y/Z its edge direction points at, 3 for none of them. `lab` is
// RgbToLab(view.rgb).
Image<int8_t> VanishingMembership(const RenderedView& view, const ImageF32& lab, const ObservationOptions& options);

// Eq. 5: entropy (natural log) of the normalised 4-bin histogram; 0 for an empty histogram.
double HistogramEntropy(const std::array<int, 4>& counts);

}  // namespace semvox
