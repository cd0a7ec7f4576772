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
// `ceiling_band_m` of a found ceiling), and walls: walls run from floor to ceiling, so a column (x, y) is a
// wall column when at least `wall_min_coverage` of its cells between floor + `wall_band_bottom_m` and the
// ceiling (or the scan's top) - `wall_band_top_m` are occupied, in any order: a sparse real scan leaves
// holes in walls, and windows and doors cut them. A wall column with the room in front of it and, behind
// it, unseen space up to something higher (0.3-1.6 m back) is the front of a fridge, wardrobe or cabinet
// standing against the wall, and not wall (`front_*`). 8-connected groups of wall columns shorter than
// `wall_min_length_m` are dropped (a lone tall column is furniture); walls need not lie along the axes.
// Counters, tables, beds and sofas, and wall cabinets above a counter, cover too little of the band and
// stay objects. What remains is cut into 26-connected components of at least `min_voxels`, found above
// floor + `split_height_m` first so that clutter and noise on the floor do not join the furniture of a room,
// and each component is cut into parts of similar top height (`split_top_step_m`, parts of at least
// `min_part_area_m2`): furniture that touches (a desk beside a bed) has different tops.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/voxel_grid.h"

namespace semvox {

struct SegmentOptions {
  double floor_band_m = 0.08;       // Voxels with centre below floor + this are floor. >= 0.
  double ceiling_band_m = 0.15;     // ... above ceiling - this are ceiling (when the ceiling was found). >= 0.
  double wall_min_coverage = 0.4;   // Share of a column's wall band that is occupied for a wall column. (0, 1].
  double wall_band_bottom_m = 0.25; // Wall band: from floor + this ... >= 0.
  double wall_band_top_m = 0.35;    // ... to the ceiling (or the scan's top) - this. >= 0.
  double wall_min_length_m = 1.0;   // 8-connected wall columns whose extent (bounding-box diagonal) is under this are not walls. > 0.
  int wall_dilation_cells = 1;      // Wall columns grow by this many cells (thick, noisy walls). >= 0.
  // Furniture fronts: a wall column with free space on one side (the room) and, behind it on the other,
  // columns that are not free (the inside of a cabinet or fridge, never seen) up to an occupied column that
  // rises higher (the wall behind, or what stands on top) between front_min_depth_m and front_max_depth_m
  // is the front of furniture standing against the wall, not wall. A wall's own thickness is under
  // front_min_depth_m; behind an exterior wall nothing is occupied. front_max_depth_m = 0: no test.
  double front_min_depth_m = 0.3;   // >= 0.
  double front_max_depth_m = 1.6;   // 0 or > front_min_depth_m.
  double front_free_share = 0.3;    // A column is free (room) when at least this share of its wall band is free. (0, 1].
  double split_height_m = 0.25;     // Segments are cut above floor + this; lower voxels join what they touch. >= 0.
  double split_top_step_m = 0.1;    // Parts of a segment: footprint columns whose tops differ by at most this grow
                                    // into one part (0: no cut). >= 0.
  double min_part_area_m2 = 0.12;   // Parts with a smaller footprint join the neighbouring part. >= 0.
  double rise_min_thickness_m = 0.2;  // Adjacent parts thinner than this (door leaves, curtains) give no neighbour rise. >= 0.
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
  kSegThickness,        // Twice the largest distance from a footprint cell to the footprint's edge, metres: an
                        // L-shaped sofa seat is long and wide in its box but 0.6-0.9 m thick, a bed 1.4-2 m.
  kSegNeighbourRise,    // How far the highest adjacent part of the same component rises above this part's top,
                        // metres, 0 when none does (a seat beside its back, a counter under wall cabinets).
  kNumSegmentFeatures
};

struct ObjectSegment {
  std::vector<uint32_t> voxels;  // VoxelGrid indices, ascending.
  std::array<float, kNumSegmentFeatures> features{};
};

struct SegmentationResult {
  std::vector<ObjectSegment> segments;
  std::vector<uint8_t> structure;  // Per VoxelGrid index: 1 floor, 2 ceiling, 3 wall, 0 otherwise.
  // What the features are measured against: per (x, y) column (x fastest), the distance to the nearest wall
  // column in metres; the floor height and the ceiling (or the scan's top).
  std::vector<float> wall_distance;
  // When the grid is finer than kSegmentCellM: the lattice the segments were found and described on (a cell
  // occupied where any voxel of the grid is; SegmentObjects) and its columns' wall distance; null otherwise.
  std::shared_ptr<const VoxelGrid> feature_grid;
  std::vector<float> feature_wall_distance;
  double floor_z = 0, top_z = 0;
};

// The size of the cells segments are found and described on (metres): the object-segment models are trained on
// 5 cm voxels, and the features (shares and counts of cells, layers, thicknesses) follow the cell size.
inline constexpr double kSegmentCellM = 0.05;

// Structure, segments and their features. Deterministic (segments in ascending order of first voxel). On a grid
// finer than kSegmentCellM the segmentation runs on the lattice of kSegmentCellM cells holding the grid's voxels
// (OctoMap keys at that size; a cell is occupied when any of its voxels is, else free when any is) and every
// voxel takes the structure and segment of its cell: the same segments and features as a map at kSegmentCellM
// would give, whatever the voxel size. Coarser grids are segmented as they are.
SegmentationResult SegmentObjects(const VoxelGrid& grid, double floor_z, double ceiling_z, bool ceiling_found,
                                  const SegmentOptions& options);

// The features of any set of occupied voxels of `grid` (grid indices), measured as SegmentObjects measures
// its segments against `seg` (SegmentObjects(grid, ...)'s result); kSegNeighbourRise is left 0.
std::array<float, kNumSegmentFeatures> DescribeVoxels(const VoxelGrid& grid, const std::vector<uint32_t>& voxels,
                                                      const SegmentationResult& seg);

// Names of the features, for reports.
const char* SegmentFeatureName(int f);

}  // namespace semvox
