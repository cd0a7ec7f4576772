#include "core/voxel_grid.h"

#include <cmath>

namespace semvox {

VoxelGrid::VoxelGrid(double resolution, const std::array<int, 3>& origin_key, const std::array<int, 3>& dims)
    : resolution_(resolution), origin_key_(origin_key), dims_(dims),
      state_(size_t(dims[0]) * dims[1] * dims[2], uint8_t(VoxelState::kUnknown)) {}

std::array<int, 3> VoxelGrid::CellOf(const Eigen::Vector3d& p) const {
  return {int(CoordToKeyIndex(p.x(), resolution_) - origin_key_[0]),
          int(CoordToKeyIndex(p.y(), resolution_) - origin_key_[1]),
          int(CoordToKeyIndex(p.z(), resolution_) - origin_key_[2])};
}

Eigen::Vector3d VoxelGrid::CellCenter(int ix, int iy, int iz) const {
  return {KeyIndexToCoord(origin_key_[0] + ix, resolution_), KeyIndexToCoord(origin_key_[1] + iy, resolution_),
          KeyIndexToCoord(origin_key_[2] + iz, resolution_)};
}

Eigen::Vector3d VoxelGrid::MinCorner() const {
  return {double(origin_key_[0] - kKeyOffset) * resolution_, double(origin_key_[1] - kKeyOffset) * resolution_,
          double(origin_key_[2] - kKeyOffset) * resolution_};
}

int VoxelGrid::TopOccupiedLayer() const {
  // Indices grow with z fastest-last, so the last occupied index lies in the highest occupied layer.
  for (size_t i = state_.size(); i-- > 0;)
    if (VoxelState(state_[i]) == VoxelState::kOccupied) return Cell(i)[2];
  return -1;
}

std::array<size_t, 3> VoxelGrid::CountStates() const {
  std::array<size_t, 3> c{0, 0, 0};
  for (uint8_t s : state_) c[s < 3 ? s : 0]++;
  return c;
}

}  // namespace semvox
