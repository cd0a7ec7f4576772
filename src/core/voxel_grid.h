// A dense voxel grid aligned with OctoMap keys: the working representation of the map.
//
// The grid covers keys [origin, origin + dims) per axis. Each voxel holds its occupancy state; later
// stages keep labels and probabilities in parallel arrays indexed by VoxelGrid::Index. OctoMap files are
// produced from it at export (mapping/octomap_io.h), and its keys are OctoMap keys.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/voxel_key.h"

namespace semvox {

enum class VoxelState : uint8_t { kUnknown = 0, kFree = 1, kOccupied = 2 };

class VoxelGrid {
 public:
  VoxelGrid() = default;
  // A grid of dims voxels whose first voxel has OctoMap key `origin`.
  VoxelGrid(double resolution, const std::array<int, 3>& origin_key, const std::array<int, 3>& dims);

  double resolution() const { return resolution_; }
  const std::array<int, 3>& origin_key() const { return origin_key_; }
  const std::array<int, 3>& dims() const { return dims_; }
  size_t size() const { return state_.size(); }

  bool Contains(int ix, int iy, int iz) const {
    return ix >= 0 && iy >= 0 && iz >= 0 && ix < dims_[0] && iy < dims_[1] && iz < dims_[2];
  }
  size_t Index(int ix, int iy, int iz) const {
    return (size_t(iz) * dims_[1] + iy) * dims_[0] + ix;
  }
  std::array<int, 3> Cell(size_t index) const {
    int ix = int(index % dims_[0]);
    size_t r = index / dims_[0];
    return {ix, int(r % dims_[1]), int(r / dims_[1])};
  }
  // Grid cell of a world point (may be outside the grid).
  std::array<int, 3> CellOf(const Eigen::Vector3d& p) const;
  Eigen::Vector3d CellCenter(int ix, int iy, int iz) const;
  VoxelKey KeyOf(int ix, int iy, int iz) const {
    return VoxelKey{uint16_t(origin_key_[0] + ix), uint16_t(origin_key_[1] + iy), uint16_t(origin_key_[2] + iz)};
  }
  bool CellOfKey(const VoxelKey& k, std::array<int, 3>* cell) const {  // Inline: called per pixel of every view.
    *cell = {int(k.x) - origin_key_[0], int(k.y) - origin_key_[1], int(k.z) - origin_key_[2]};
    return Contains((*cell)[0], (*cell)[1], (*cell)[2]);
  }
  // World coordinates of the grid's lower corner (min x, min y, min z of voxel (0,0,0)).
  Eigen::Vector3d MinCorner() const;

  VoxelState state(size_t i) const { return VoxelState(state_[i]); }
  void set_state(size_t i, VoxelState s) { state_[i] = uint8_t(s); }
  uint8_t* state_data() { return state_.data(); }
  const uint8_t* state_data() const { return state_.data(); }

  std::array<size_t, 3> CountStates() const;  // unknown, free, occupied
  int TopOccupiedLayer() const;  // z index of the highest occupied voxel, -1 when none is.

 private:
  double resolution_ = 0.05;
  std::array<int, 3> origin_key_{0, 0, 0};
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<uint8_t> state_;
};

}  // namespace semvox
