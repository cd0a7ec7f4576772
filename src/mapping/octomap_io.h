// OctoMap files from the voxel grid. OctoMap headers stay in octomap_io.cc.
#pragma once

#include <string>

#include "core/status.h"
#include "core/voxel_grid.h"

namespace semvox {

// Writes the free and occupied voxels as an OctoMap binary tree (.bt, readable by octovis), atomically.
Status WriteOctomapBinary(const VoxelGrid& grid, const std::string& path);

// Reads a .bt and returns its leaves at full depth as (key, occupied) pairs, in key order (tests).
Result<std::vector<std::pair<VoxelKey, bool>>> ReadOctomapLeaves(const std::string& path, double* resolution);

}  // namespace semvox
