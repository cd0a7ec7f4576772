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
