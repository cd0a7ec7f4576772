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
  size_t wall_margin_voxels = 0;      // ApplyWallMargin: wall voxels of the walls' margin relabelled.
  size_t wall_colour_voxels = 0;      // ApplyWallColour: wall voxels off the walls' colour relabelled.
  std::array<uint8_t, 3> wall_colour{0, 0, 0};  // ApplyWallColour: the walls' colour (per-channel median).
  size_t refrigerator_colour_voxels = 0;  // ApplyRefrigeratorColour: wood-coloured refrigerator voxels relabelled.
  int doorless_segments = 0;              // ApplyDoorsInDoorways: segments whose door voxels were relabelled,
  size_t doorless_voxels = 0;             // and those voxels.
  int tall_object_wall_segments = 0;      // ApplyTallObjectWalls: tall object segments whose wall voxels were relabelled,
  size_t tall_object_wall_voxels = 0;     // and those voxels.
  int wall_unit_components = 0;          // ApplyWoodenWallUnits: hung wood-coloured parts of the wall relabelled cabinet,
  size_t wall_unit_voxels = 0;            // and their voxels.
  int hung_wall_components = 0;          // ApplyHungWallCabinets: parts of the wall labels hung over free space
  size_t hung_wall_voxels = 0;            // relabelled cabinet, and their voxels.
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

// The wall's margin: the object segmentation grows the wall columns by a cell (SegmentOptions::
// wall_dilation_cells) so that a noisy wall's surface stays wall, and with it takes the back of whatever stands
// against the wall, a sofa's, a toilet's, a door's frame. A voxel labelled wall in such a margin column takes the
// most frequent label among its 26 neighbours that is neither wall, floor nor ceiling when at least
// `min_neighbours` of them carry it (the smallest id on a tie), read from the labels before this step; a
// bare wall's margin has no such neighbours and stays wall.
void ApplyWallMargin(const VoxelMap& map, const SegmentationResult& segmentation, int min_neighbours, SemanticLabels* labels);

// A wall is painted one colour; what stands against it or is set in it, a wooden wardrobe's front, a window's
// frame, a toilet's back, is another. The walls' colour is the per-channel median of the voxels labelled wall.
// A voxel labelled wall whose colour lies at least `min_distance` (RGB, 0-441) from the walls' colour and closer
// to that of one of its 26 neighbours labelled neither wall, floor nor ceiling takes the label of the closest
// such neighbour (the smallest id on a tie). This repeats for `rings` rings, each read from the labels before it,
// so that an object's colour spreads into the wall band at most `rings` voxels. Completed voxels (never seen, their
// colour borrowed) neither change nor give their label, and do not count in the walls' colour.
void ApplyWallColour(const VoxelMap& map, double min_distance, int rings, SemanticLabels* labels);

// Wood's colour: red >= green >= blue, hue (degrees, red 0, yellow 60) within [kWoodHueMinDeg, kWoodHueMaxDeg]
// (cherry and walnut to pine and oak, and their laminates), chroma (red - blue, 0-255) at least `min_chroma`.
inline constexpr double kWoodHueMinDeg = 10, kWoodHueMaxDeg = 50;
bool WoodColour(const std::array<int, 3>& rgb, int min_chroma);

// A refrigerator is no wooden box; one of its shape in wood's colour, a kitchen's pantry unit, a hall's tall
// cabinet, the cabinet over the refrigerator, is a cabinet. A voxel labelled refrigerator whose colour, the
// per-channel median over itself and its 26 neighbours labelled refrigerator, is wood's (WoodColour with
// `min_chroma`) takes the label cabinet. Decided on the labels before this step; completed voxels (never seen,
// their colour borrowed) neither change nor count.
void ApplyRefrigeratorColour(const VoxelMap& map, int min_chroma, SemanticLabels* labels);

// A door's leaf stands in its doorway, or open beside it within its own width. After ApplyWallOpenings, when
// it found at least one door: the voxels labelled door of an object segment (at least kDoorlessMinVoxels of
// them) that all lie farther from every door found than that door's width + kDoorwayReachMarginM (horizontally,
// from the doorway's span on the wall's face) are no leaf: a segment no thicker than kDoorlessThinMaxM (a panel
// hung along a wall) takes the label curtain, a thicker one (a tall box) cabinet. Without doors found, or
// without the segmentation, nothing changes: a doorway the search missed would lose its leaf.
inline constexpr int kDoorlessMinVoxels = 20;
inline constexpr double kDoorwayReachMarginM = 0.3, kDoorlessThinMaxM = 0.35;
void ApplyDoorsInDoorways(const VoxelMap& map, const SegmentationResult* segmentation, SemanticLabels* labels);

// Doors and windows of the map's walls (objects/wall_openings.h) relabel the labelled voxels of their pane or
// closed leaf that came out wall, door or window, and every voxel of an open leaf but floor and ceiling.
void ApplyWallOpenings(const VoxelMap& map, const WallOpeningOptions& options, SemanticLabels* labels);

// Tall furniture is no wall. Walls are what the object segmentation removed first (wall columns: occupied over
// most of the band from the floor to the ceiling); an object segment is what remains, and the Voxel-CRF still
// calls wall the flat front of a wardrobe or tall cabinet standing in it, which the per-view evidence and the
// planes' cliques read as a wall. After the doors and windows: the voxels labelled wall of an object segment
// whose top surface (kSegTopSurface) lies at least kTallObjectMinTopM above the floor and at least
// kTallObjectMinCeilingGapM under the ceiling (or the scan's top; a wall runs up to it), and whose most probable
// class by shape (the segment term's probabilities, `evidence.voxels.segment`) is an object with a probability of
// at least kTallObjectMinProbability, take that class's NYU40 id. Objects are any class but wall, floor, ceiling,
// window, door and "other" (whose NYU40 id is not known yet). Low segments are left alone: the wall under a
// window joins the furniture in front of it. Without a segment term nothing changes.
inline constexpr double kTallObjectMinTopM = 1.5, kTallObjectMinCeilingGapM = 0.3, kTallObjectMinProbability = 0.5;
void ApplyTallObjectWalls(const SemanticEvidence& evidence, const VoxelCrfModel& model, SemanticLabels* labels);

// Wooden wall units are cabinets. A kitchen's or bedroom's wall units hang on the wall 1.3-2.4 m up, 0.3-0.4 m deep,
// and their fronts cover the upper half of the wall band, so the object segmentation keeps their columns as wall and
// the Voxel-CRF labels them wall. After the tall objects: the voxels labelled wall whose colour (the per-channel
// median over the voxel and its 26 neighbours labelled wall) is wood's (WoodColour with kWallUnitWoodChroma) form
// 26-connected parts; a part of at least kWallUnitMinVoxels voxels that hangs on the wall (its bottom at least
// kWallUnitMinBottomM above the floor, at most kWallUnitMaxHeightM tall), lies on no door's or window's span (within
// kWallUnitOpeningMarginCells: a frame), and whose median colour lies at least kWallUnitMinContrast (RGB) from that
// of the wall voxels around it (not in wood's colour, within two cells; at least kWallUnitMinAroundVoxels of them)
// takes the label cabinet. A wall painted in a wood tone, its brighter parts split from its shaded ones, is its own
// colour around them. Completed voxels (never seen, their colour borrowed) neither change nor count.
inline constexpr int kWallUnitWoodChroma = 60, kWallUnitMinVoxels = 50, kWallUnitOpeningMarginCells = 3, kWallUnitMinAroundVoxels = 20;
inline constexpr double kWallUnitMinBottomM = 1.0, kWallUnitMaxHeightM = 1.3, kWallUnitMinContrast = 30;
void ApplyWoodenWallUnits(const VoxelMap& map, SemanticLabels* labels);

// A wall stands on the floor; a wall cabinet hangs. A wall unit's front covers the upper half of the wall band, so
// the object segmentation keeps its columns as wall and the Voxel-CRF labels it wall, whatever its colour. After the
// wooden wall units: a voxel labelled wall (not completed) whose column holds, under the bottom of its run of wall
// voxels, kHungMinGapM of cells that are not occupied, at least half of them seen free, hangs. The hanging voxels
// form 26-connected parts; a part of at least kHungMinVoxels voxels whose bottom lies kHungMinBottomM to
// kHungMaxBottomM above the floor (under a door's lintel), at most kHungMaxHeightM tall, whose footprint covers at
// least kHungMinFootprintM2 (a cabinet is deep, a strip of wall over an opening is not), on no door's or window's span
// found in the walls (within kWallUnitOpeningMarginCells), takes the label cabinet. The wall itself, and a picture
// or a panel flat on it, share their columns with the wall under them; the wall behind furniture was never seen.
inline constexpr double kHungMinGapM = 0.4, kHungMinBottomM = 1.0, kHungMaxBottomM = 1.8, kHungMaxHeightM = 1.3,
                        kHungMinFootprintM2 = 0.1;
inline constexpr int kHungMinVoxels = 50;
void ApplyHungWallCabinets(const VoxelMap& map, SemanticLabels* labels);

// A bar is a table by name and a counter by use. A counter is a work surface along a wall; a top at counter height
// or above (kSegTopSurface at least kBarMinTopM above the floor) whose footprint's centre lies kBarMinWallDistanceM
// or more from every wall column (kSegWallDistance) is a bar or an island, which ScanNet's and NYU's annotators name
// table. The room types read it as the kitchen furniture it is, so this step runs after them (pipeline.cc,
// RoomsStage): the voxels labelled counter of such an object segment, and those joined to them (26-connected),
// take the label table. Without a segmentation nothing changes.
inline constexpr double kBarMinTopM = 1.0, kBarMinWallDistanceM = 0.6;
void ApplyBarTables(const VoxelMap& map, const SegmentationResult* segmentation, SemanticLabels* labels);

}  // namespace semvox
