// Solving, the second part of the semantic stage: the Voxel-CRF (Kim et al., ICCV 2013, Alg. 1) over the
// evidence of pipeline/semantic_evidence.h, giving the labelled voxels and the refined occupancy.
//
//   SemanticLabels labels;
//   Status st = SolveSemantic(map, evidence, models.crf, options.crf, &labels);
#pragma once
#include <array>

#include "core/status.h"
#include "core/voxel_grid.h"
#include "mapping/voxelizer.h"
#include "objects/wall_openings.h"
#include "pipeline/semantic_evidence.h"
#include "voxelcrf/semantic_map.h"
#include "voxelcrf/voxel_crf.h"

namespace semvox {

struct SegmentationResult;

struct SemanticLabels {
  VoxelCrfResult crf;   // Labels and visibility per node, planes, cliques, iterations.
  SemanticMap map;      // The occupied voxels with label, confidence, colour (and room, once assigned).
  VoxelGrid refined;    // The occupancy after the CRF: the grid the later stages use.
  double seconds = 0;
  std::vector<WallOpening> openings;  // ApplyWallOpenings.
  size_t opening_voxels = 0;          // Voxels it relabelled.
  double seconds_openings = 0;
  int other_segments = 0;             // ApplyOtherLabels: segments whose "other" voxels got a fine id,
  size_t other_voxels = 0;            // and those voxels.
  double seconds_other = 0;
  int item_groups = 0;                // ApplyItemLabels: items on top of segments given an NYU40 id of their own,
  size_t item_voxels = 0;             // and the voxels it relabelled.
  double seconds_items = 0;
  size_t floor_surface_voxels = 0;    // ApplyFloorSurface: floor voxels above the floor's surface relabelled.
  size_t furniture_feet_voxels = 0;   // ApplyFurnitureFeet: floor voxels under furniture relabelled.
  int bar_table_segments = 0;             // ApplyBarTables: free-standing counter-height segments whose counter voxels
  size_t bar_table_voxels = 0;            // became table, and those voxels.
};

// Solves the CRF of `evidence` (built on `map`) with `model` and `options`; may be called again with other
// options (the CRF variants of bench/voxelcrf_bench.cc) over the same evidence.
Status SolveSemantic(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfModel& model,
                     const VoxelCrfOptions& options, SemanticLabels* labels);

// The voxels of each object segment of `evidence` that came out "other" (the id `model` writes for it) take
// the NYU40 id `labeller` gives them (objects/other_labels.h). Segments with fewer than `min_voxels` such
// voxels, and "other" voxels outside every segment, keep the model's id. Needs evidence.segmentation.
void ApplyOtherLabels(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfModel& model,
                      const OtherLabeller& labeller, int min_voxels, SemanticLabels* labels);

// The items on top of each object segment of `evidence` (objects/other_labels.h, ItemsOnTop with
// `min_voxels`) that `labeller` calls objects of their own take its NYU40 id, on their voxels that are not
// structure (wall, floor, ceiling, door, window); the rest stay parts of the furniture. Needs
// evidence.segmentation.
void ApplyItemLabels(const VoxelMap& map, const SemanticEvidence& evidence, const ItemLabeller& labeller, int min_voxels,
                     SemanticLabels* labels);

// The floor is a surface: a voxel labelled floor that lies wholly above it (its bottom at least `margin_m`
// above map.floor_z, i.e. beyond the floor's scan noise) holds the bottom of what stands there, a wall's or
// a piece of furniture's. It takes the label of the first of the two voxels above it that is labelled and
// neither floor nor ceiling, else the most frequent such label among its 26 neighbours, else stays floor.
// Voxels are visited from the top down, so a relabelled voxel passes its label on to the one below it.
void ApplyFloorSurface(const VoxelMap& map, double margin_m, SemanticLabels* labels);

// Furniture stands on the floor. The floor's scan noise fills two layers of voxels, the one whose centre lies under
// the floor's surface (map.floor_z) and the one above it; a piece of furniture that reaches the floor fills the
// upper one too, and that voxel holds the furniture's foot as much as the floor. After the other steps: a voxel
// labelled floor whose centre lies above the floor's surface and whose upper neighbour is labelled an object (any
// label but floor, ceiling, wall, door and window) takes its upper neighbour's label. Open floor (nothing on it) and
// the foot of a wall, a door or a window stay floor.
void ApplyFurnitureFeet(const VoxelMap& map, SemanticLabels* labels);

// Doors and windows of the map's walls (objects/wall_openings.h) relabel the labelled voxels of their pane or
// closed leaf that came out wall, door or window, and every voxel of an open leaf but floor and ceiling.
void ApplyWallOpenings(const VoxelMap& map, const WallOpeningOptions& options, SemanticLabels* labels);

// A bar is a table by name and a counter by use. A counter is a work surface along a wall; a top at counter height
// or above (kSegTopSurface at least kBarMinTopM above the floor) whose footprint's centre lies kBarMinWallDistanceM
// or more from every wall column (kSegWallDistance) is a bar or an island, which ScanNet's and NYU's annotators name
// table. The room types read it as the kitchen furniture it is, so this step runs after them (pipeline.cc,
// RoomsStage): the voxels labelled counter of such an object segment, and those joined to them (26-connected),
// take the label table. Without a segmentation nothing changes.
inline constexpr double kBarMinTopM = 1.0, kBarMinWallDistanceM = 0.6;
void ApplyBarTables(const VoxelMap& map, const SegmentationResult* segmentation, SemanticLabels* labels);

}  // namespace semvox
