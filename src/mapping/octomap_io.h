// OctoMap files from the voxel grid. OctoMap headers stay in octomap_io.cc.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/status.h"
#include "mapping/frame_integrator.h"
#include "core/voxel_grid.h"

namespace semvox {

// Writes the free and occupied voxels as an OctoMap binary tree (.bt, readable by octovis), atomically.
Status WriteOctomapBinary(const VoxelGrid& grid, const std::string& path);

// Reads a .bt and returns its leaves at full depth as (key, occupied) pairs, in key order (tests).
Result<std::vector<std::pair<VoxelKey, bool>>> ReadOctomapLeaves(const std::string& path, double* resolution);

// One voxel of the semantic OctoMap (map.ot): occupancy, NYU40 label (0 for free voxels) and confidence.
struct SemanticVoxel {
  VoxelKey key;
  bool occupied = false;
  uint16_t label = 0;
  float confidence = 0;
};

// Writes a semantic OctoMap `.ot`: an OctoMap tree of tree type "SemanticOcTree" whose nodes hold the
// occupancy log-odds (as OcTree's), a uint16 label and a float confidence; identical free leaves are pruned.
// Atomic. Readable by ReadSemanticOctree (and any OctoMap program that registers the same node type).
Status WriteSemanticOctree(const std::vector<SemanticVoxel>& voxels, double resolution, const std::string& path);
// Reads it back: every leaf expanded to full depth (free regions pruned on writing come back voxel by voxel),
// in key order.
Result<std::vector<SemanticVoxel>> ReadSemanticOctree(const std::string& path, double* resolution);

// An OctoMap occupancy tree fed with frame updates (OctoMap types stay in octomap_io.cc).
class OccupancyOctree {
 public:
  explicit OccupancyOctree(double resolution);
  ~OccupancyOctree();
  OccupancyOctree(OccupancyOctree&&) noexcept;
  // One observation per key: a miss for update.free, a hit for update.occupied, as insertPointCloud does;
  // inner nodes are refreshed once at the end.
  void Apply(const FrameUpdate& update);
  size_t num_nodes() const;
  // Writes the tree as .bt, atomically.
  Status WriteBinary(const std::string& path) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semvox
