// 3D object segments classified by their shape (library semvox_objects).
//
//   std::vector<ObjectSegment> segments = SegmentObjects(map.grid, floor_z, ceiling_z, SegmentOptions{});
//   ObjectSegmentClassifier clf = ...Load("models/object_segments.knn");
//   std::vector<double> p = clf.Probabilities(segments[i]);     // per second-level class
//
// A per-view classifier sees colour first; on a real scan (textured, lit, sparse) colour says little, but
// a bed is still a waist-high flat box two metres long, a table a flat top on legs, a fridge a tall box.
// This module cuts the occupied voxels that are not structure into connected segments and describes each
// one by its shape in the scan's canonical frame (+z up, heights above the floor), so that a k-NN model
// trained on randomised generated apartments can classify them. The class probabilities enter the
// Voxel-CRF as a unary on the segment's voxels with a learned weight (voxel_crf.h, kWSegment), next to
// the per-view evidence.
//
// Structure, removed first: the floor layer (within `floor_band_m` of the floor), the ceiling layer (within
// `ceiling_band_m` of a found ceiling), and walls: in the canonical frame walls lie along the grid axes, so
// a column (x, y) is wall-like when its longest vertical run of occupied voxels (gaps up to 2 cells
// bridged) is at least `wall_min_run_m` tall, and wall-like columns that line up along x or along y over at
// least `wall_min_length_m` (gaps up to `wall_max_gap_m`) are walls. Tall furniture narrower than that
// (a fridge, a shelf) and furniture under wall cabinets (two shorter runs) stay objects. What remains is
// cut into 26-connected components of at least `min_voxels`.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/voxel_grid.h"

namespace semvox {

struct SegmentOptions {
  double floor_band_m = 0.08;       // Voxels with centre below floor + this are floor. >= 0.
  double ceiling_band_m = 0.15;     // ... above ceiling - this are ceiling (when the ceiling was found). >= 0.
  double wall_min_run_m = 0.8;      // Vertical occupied run of a wall-like column, metres. > 0.
  double wall_min_length_m = 1.0;   // Wall-like columns in a line along x or y over at least this, metres. > 0.
  double wall_max_gap_m = 0.2;      // ... bridging gaps up to this, metres. >= 0.
  int wall_dilation_cells = 1;      // Wall columns grow by this many cells (thick, noisy walls). >= 0.
  int min_voxels = 12;              // Smaller components are not segments. >= 1.
  int max_voxels = 200000;          // Larger components (a whole scan that is one blob) are not segments. >= min_voxels.
  bool Check(std::string* error) const;
};

// Shape features of a segment, canonical frame: heights above the floor, metres, shares in [0, 1].
enum SegmentFeature : int {
  kSegBottom = 0,       // Lowest voxel centre above the floor.
  kSegTop,              // Highest.
  kSegLength,           // Horizontal extent along the segment's principal horizontal axis.
  kSegWidth,            // Across it.
  kSegFootprint,        // Area of the occupied (x, y) cells, m².
  kSegVolume,           // Voxel count x voxel volume, m³.
  kSegFill,             // Voxels / voxels of the bounding box (principal axes).
  kSegTopSurface,       // Height of the largest upward-facing layer (voxels with no occupied voxel above).
  kSegTopShare,         // Its area / footprint.
  kSegUpShare,          // Upward-facing voxels / all voxels.
  kSegSideShare,        // Voxels with a non-occupied horizontal neighbour / all voxels.
  kSegWallDistance,     // Distance from the footprint's centre to the nearest wall column, metres (capped at 3).
  kSegWallContact,      // Share of footprint cells within 2 cells of a wall column.
  kSegLayers,           // Upward-facing layers holding >= 10 % of the footprint (shelves, seats + backs).
  kSegUnderShare,       // Footprint cells whose lowest voxel is above floor + 0.15 m (legs, overhangs, hung).
  kSegCeilingGap,       // Ceiling (or scan top) minus top, metres.
  kNumSegmentFeatures
};

struct ObjectSegment {
  std::vector<uint32_t> voxels;  // VoxelGrid indices, ascending.
  std::array<float, kNumSegmentFeatures> features{};
};

struct SegmentationResult {
  std::vector<ObjectSegment> segments;
  std::vector<uint8_t> structure;  // Per VoxelGrid index: 1 floor, 2 ceiling, 3 wall, 0 otherwise.
};

// Structure, segments and their features. Deterministic (segments in ascending order of first voxel).
SegmentationResult SegmentObjects(const VoxelGrid& grid, double floor_z, double ceiling_z, bool ceiling_found,
                                  const SegmentOptions& options);

// Names of the features, for reports.
const char* SegmentFeatureName(int f);

}  // namespace semvox
