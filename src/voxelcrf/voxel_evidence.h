// Evidence per voxel for the Voxel-CRF (Kim et al., "3D Scene Understanding by Voxel-CRF", ICCV 2013,
// Sec. 4.1), gathered from rendered views through their per-pixel voxel keys.
//
//   VoxelCrfNodes nodes = SelectVoxelCrfNodes(map.grid, floor_z, ceiling_z, options);   // the CRF's voxels
//   EvidenceAccumulator acc(map.grid, nodes, options);
//   acc.AddDepthView(view);                    // every kept view: depth, density, colour, normal
//   acc.AddClassifiedView(view, sp, probs);    // classified views: rays + per-pixel class probabilities
//   VoxelEvidence ev = std::move(acc).Finish();
//
// Nodes. The CRF does not label every voxel of the grid: far free space is certain. Its nodes are the
// occupied voxels, the free voxels next to them (so noisy geometry can move by a voxel), and the unknown
// voxels within `completion_band_m` of an occupied voxel inside the apartment (so occluded walls and floors
// can be completed). Columns count as inside when a free voxel lies within `interior_margin_cells` of them.
//
// Depth and density (Eq. 3-4). Each node is projected into every depth view. With d_i its depth and d^m the
// depth the view observed at its pixel, Delta = d_i - d^m; a node with Delta > 1.5 sigma lies behind the
// observed surface (occluded in that view: no evidence). Otherwise f_s(Delta) = exp(-Delta^2 / 2 sigma^2)
// (the normal density N(0, sigma^2) scaled to 1 at 0) and the node's F_i is the mean of f_s over the views
// that observe it. The point-density ratio rho_i = |P_i| / |P_i^max| is the number of pixels whose hit lies
// in the voxel over the number of pixel rays that reach it (its projected footprint, (f s / d)^2 pixels,
// summed over the views whose observed surface is not nearer than the voxel's half diagonal), clipped to
// [0, 1]; voxels no ray reaches have rho = 0 and no density evidence.
//
// Appearance (Eq. 3, P(s_i | O)). Classified views contribute rays (every `ray_stride`-th pixel with a hit)
// that carry the class distribution of their pixel. Which voxel a ray's observation belongs to is the
// visibility question of Eq. 9: the first voxel along the ray labelled occupied. VoxelCrf recomputes it after
// every inference iteration (Alg. 1); P(s_i | O) is the mean over the rays for which i is visible.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>
#include "core/option_table.h"
#include "core/image.h"
#include "core/voxel_grid.h"
#include "render/view_renderer.h"

namespace semvox {

struct VoxelEvidenceOptions {
  double depth_sigma_voxels = 1.0;
  double completion_band_m = 0.25;  // Those unknown voxels become nodes.
  int interior_margin_cells = 2;
  int ray_stride = 2;
  double ray_extension_m = 0.5;

  // The fields users set (section `semantic`): meaning, unit and range.
  static const OptionTable<VoxelEvidenceOptions>& Options() {
    using O = VoxelEvidenceOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::depth_sigma_voxels, "depth_sigma_voxels", 0.01, 100, "voxel sizes", "sigma of the depth term f_s"),
        OptionNumber(&O::completion_band_m, "completion_band_m", 0, 5, "metres",
                     "unknown voxels this close to an occupied voxel can be completed"),
        OptionNumber(&O::interior_margin_cells, "interior_margin_cells", 0, 100, "cells",
                     "columns this close to a free column count as inside"),
        OptionNumber(&O::ray_stride, "ray_stride", 1, 64, "", "one classification ray per ray_stride x ray_stride pixels"),
        OptionNumber(&O::ray_extension_m, "ray_extension_m", 0, 10, "metres",
                     "a ray's visible voxel may lie this far behind its observed hit"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

// The voxels the CRF labels, in block order (8x8x8 blocks of the grid; nodes of one block are contiguous).
struct VoxelCrfNodes {
  std::vector<int32_t> node_of_voxel;  // Per VoxelGrid::Index: node id or -1.
  std::vector<uint32_t> voxel;         // Per node: VoxelGrid::Index.
  std::vector<uint8_t> initial_state;  // Per node: the map's VoxelState.
  std::vector<uint8_t> holds_point;    // Per node: 1 where the voxel holds a point of the input cloud
                                       // (MarkPointNodes) or the input mesh's surface (MarkSurfaceNodes);
                                       // empty when none are known.
  // Blocks: nodes [block_begin[b], block_begin[b + 1]) with bounding sphere (centre, radius).
  std::vector<uint32_t> block_begin;
  std::vector<Eigen::Vector3f> block_centre;
  std::vector<float> block_radius;
  size_t size() const { return voxel.size(); }
  size_t count_state(VoxelState s) const;
};

VoxelCrfNodes SelectVoxelCrfNodes(const VoxelGrid& grid, double floor_z, double ceiling_z, const VoxelEvidenceOptions& options);
// Sets `holds_point` from the grid indices of the voxels that hold input points (VoxelMap::point_voxels).
void MarkPointNodes(const std::vector<uint32_t>& point_voxels, VoxelCrfNodes* nodes);
// A mesh's surface is exact: sets `holds_point` on every node whose voxel the map holds occupied.
void MarkSurfaceNodes(VoxelCrfNodes* nodes);

// One classified-view ray: from `origin` (index into VoxelEvidence::origins) along `direction` up to
// `max_t` metres; its observation is row `observation` of VoxelEvidence::observations.
struct EvidenceRay {
  Eigen::Vector3f direction;
  float max_t = 0;
  int32_t origin = 0;
  int32_t observation = 0;
  int32_t view = 0;
  int16_t px = 0, py = 0;  // Pixel, in ray_stride units (neighbouring rays of a view differ by 1).
};

struct VoxelEvidence {
  int num_classes = 0;                   // K of the per-view classifier.
  double sigma_m = 0;                    // sigma of f_s.
  // Per node.
  std::vector<float> depth_agreement;    // F_i, mean f_s over observing views; 0 when unobserved.
  std::vector<float> density;            // rho_i in [0, 1].
  std::vector<float> reaching_rays;      // |P_i^max|: pixel rays that reach the voxel (0: no density evidence).
  std::vector<uint16_t> observing_views; // Depth views that observe the node (Delta <= 1.5 sigma).
  std::vector<uint32_t> hits;            // Depth-view pixels whose hit lies in the voxel.
  std::vector<std::array<uint8_t, 3>> colour;  // Mean colour of those pixels (0 when none).
  std::vector<Eigen::Vector3f> normal;   // Mean unit normal of those pixels (0 when none).
  // Classified-view rays and their observations (K probabilities per row).
  std::vector<Eigen::Vector3f> origins;
  std::vector<EvidenceRay> rays;
  std::vector<float> observations;       // rows x K.
  // Per node x K: class probabilities of the object segment holding the node (objects/object_segments.h),
  // all zero for nodes outside segments; empty when no segment classifier ran.
  std::vector<float> segment;
  int num_classified_views = 0;
  int num_depth_views = 0;
  bool observed(size_t node) const { return observing_views[node] > 0; }
};

class EvidenceAccumulator {
 public:
  EvidenceAccumulator(const VoxelGrid& grid, const VoxelCrfNodes& nodes, int num_classes, const VoxelEvidenceOptions& options);
  // Depth, density, colour and normal evidence from one rendered view (keys at the grid's resolution).
  void AddDepthView(const RenderedView& view);
  // Rays of one classified view; `pixel_probabilities` holds K floats per pixel (row-major, like the view)
  // or, with `segment` non-null, K floats per segment id of `segment` (superpixels).
  void AddClassifiedView(const RenderedView& view, const Image<int32_t>* segment, std::span<const float> probabilities);
  VoxelEvidence Finish() &&;

 private:
  const VoxelGrid& grid_;
  const VoxelCrfNodes& nodes_;
  VoxelEvidenceOptions options_;
  VoxelEvidence ev_;
  std::vector<float> sum_f_, footprint_;
  std::vector<std::array<float, 3>> colour_sum_;
  std::vector<Eigen::Vector3f> normal_sum_;
  std::vector<Eigen::Vector3f> centre_;  // Each node's voxel centre (world frame, float), for AddDepthView.
  std::vector<int32_t> pixel_node_;  // AddDepthView scratch: the node each pixel hits (-1: none).
  std::vector<float> tile_max_depth_;  // AddDepthView scratch: the deepest depth of each pixel tile.
};

}  // namespace semvox
