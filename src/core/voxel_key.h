// Voxel keys identical to OctoMap's OcTreeKey, so that voxel keys recorded anywhere in semvox (render
// buffers, label maps) address the same voxels as the exported OctoMap files.
//
// OctoMap (16-level tree): key = floor(coord / resolution) + 2^15 per axis, as in
// octomap::OcTreeBaseImpl::coordToKey; the voxel centre is (key - 2^15 + 0.5) * resolution.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>

namespace semvox {

inline constexpr int kKeyOffset = 32768;  // OctoMap's tree_max_val for tree depth 16.

struct VoxelKey {
  uint16_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator!=(const VoxelKey& o) const { return !(*this == o); }
  bool operator<(const VoxelKey& o) const {
    return x != o.x ? x < o.x : (y != o.y ? y < o.y : z < o.z);
  }
  uint64_t Pack() const { return (uint64_t(x) << 32) | (uint64_t(y) << 16) | uint64_t(z); }
};

struct VoxelKeyHash {
  size_t operator()(const VoxelKey& k) const { return std::hash<uint64_t>()(k.Pack()); }
};

// Integer key index along one axis (may be outside [0, 65535] for absurd coordinates; callers check).
// Multiplies by 1/resolution exactly as OctoMap does, so boundary cases round the same way.
inline int64_t CoordToKeyIndex(double coord, double resolution) {
  const double resolution_factor = 1.0 / resolution;
  return static_cast<int64_t>(std::floor(resolution_factor * coord)) + kKeyOffset;
}
inline double KeyIndexToCoord(int64_t key, double resolution) {
  return (double(key - kKeyOffset) + 0.5) * resolution;
}
inline bool KeyIndexInRange(int64_t k) { return k >= 0 && k < 65536; }

inline Eigen::Vector3d KeyToCoord(const VoxelKey& k, double resolution) {
  return {KeyIndexToCoord(k.x, resolution), KeyIndexToCoord(k.y, resolution), KeyIndexToCoord(k.z, resolution)};
}

}  // namespace semvox
