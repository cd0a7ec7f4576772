// The Voxel-CRF's result as a semantic map and its exports.
//
//   SemanticMap map = MakeSemanticMap(grid, nodes, evidence, result, model);
//   WriteVoxelsPly(map, "voxels.ply");                 // one vertex per occupied voxel
//   VoxelGrid refined = map.RefinedGrid(grid);         // occupancy after the CRF (occupancy map, map.bt)
//   ImageU16 top = SemanticTopView(map, grid, floor_z, band);   // on the occupancy grid
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>
#include "core/image.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {

struct SemanticVoxelRecord {
  uint32_t voxel = 0;                 // VoxelGrid::Index.
  Eigen::Vector3f centre;
  std::array<uint8_t, 3> rgb{0, 0, 0};
  uint16_t label = 0;                 // NYU40 id.
  float confidence = 0;
  int32_t room = -1;                  // Room id (rooms.png), -1 until rooms exist or outside every room.
  uint8_t completed = 0;              // 1: never seen (unknown in the map) and inferred occupied.
};

struct SemanticMap {
  std::vector<SemanticVoxelRecord> occupied;  // In grid-index order.
  // Every CRF node's final state (for the refined grid): node -> occupied?
  std::vector<uint8_t> node_occupied;
  // Occupancy of the grid after the CRF: nodes labelled occupied become occupied, nodes labelled empty that
  // the map held occupied become free (the CRF removed them), everything else keeps its state.
  VoxelGrid RefinedGrid(const VoxelGrid& grid, const VoxelCrfNodes& nodes) const;
  // The record of grid voxel `voxel`, or null when it is not occupied (a binary search).
  SemanticVoxelRecord* Find(uint32_t voxel);
  const SemanticVoxelRecord* Find(uint32_t voxel) const;
  // NYU40 id -> number of occupied voxels.
  std::vector<std::pair<int, size_t>> LabelCounts() const;
  size_t completed_count() const;
};

// Occupied nodes with their NYU40 label, confidence and colour. Completed voxels (no colour observed) take
// the colour of the nearest observed voxel of the same label (breadth-first over 26-neighbours, up to 20
// steps), else the label's display colour.
SemanticMap MakeSemanticMap(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& evidence,
                            const VoxelCrfResult& result, const VoxelCrfModel& model);

// Fills SemanticVoxelRecord::room from a room-id image on the occupancy grid of `grid` (row 0 = largest y).
void AssignRooms(const ImageU16& room_ids, const VoxelGrid& grid, SemanticMap* map);

// voxels.ply: binary little-endian; vertex x, y, z (float, voxel centre, metres, input frame), red, green,
// blue (uchar), label (ushort, NYU40), confidence (float), room (int), completed (uchar). Atomic.
Status WriteVoxelsPly(const SemanticMap& map, const std::string& path,
                      const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());

// NYU40 label of the highest occupied voxel per column whose centre lies in [floor + band_min, floor +
// band_max) metres, on the occupancy grid (width dims[0], height dims[1], row 0 = largest y); 0 = none.
// Voxels whose label confidence is under min_confidence are passed over (the column shows the next one down).
ImageU16 SemanticTopView(const SemanticMap& map, const VoxelGrid& grid, double floor_z, double band_min_m, double band_max_m,
                         double min_confidence = 0);

// The top view in colour: labels in their NYU40 display colours, free cells white, unknown grey (from the
// refined occupancy image), with a legend of the labels present. `show_unlabelled`: occupied cells without a
// label (under the confidence floor) dark grey, with their own legend entry.
ImageRgb8 ColourSemanticTopView(const ImageU16& labels, const ImageRgb8& occupancy_pgm, bool show_unlabelled = false);

}  // namespace semvox
