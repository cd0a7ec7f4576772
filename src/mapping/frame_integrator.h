// Integration of one range frame (sensor origin + end points) into free and occupied voxel keys, with
// OctoMap's semantics and both cores.
//
// For each end point within max range, the voxels the ray crosses are free and the end point's voxel is
// occupied; beyond max range the ray is cut at max range and only marks free voxels; a voxel that is both
// is occupied. This is exactly what octomap::OccupancyOcTreeBase::computeUpdate (OctoMap 1.9, without
// discretisation) produces, so applying the result to an OcTree gives the same tree as insertPointCloud;
// bench/voxelize_bench checks that on every run.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/voxel_key.h"

namespace semvox {

struct FrameUpdate {
  // Unique keys in grid order (z slowest, x fastest); free and occupied are disjoint.
  std::vector<VoxelKey> free;
  std::vector<VoxelKey> occupied;
};

// max_range_m < 0: unlimited.
FrameUpdate IntegrateFrame(const Eigen::Vector3f& origin, const std::vector<Eigen::Vector3f>& end_points,
                           double resolution, double max_range_m = -1.0);

}  // namespace semvox
