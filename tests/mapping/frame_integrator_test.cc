// IntegrateFrame (rays stepped several at a time, free cells stored by both cores) against a plain
// reference: one ray at a time with the boundary-checked TraverseGrid, keys collected in a std::set. The
// reference traversal is the one bench/voxelize_bench checks against OctoMap's computeRayKeys.
#include "mapping/frame_integrator.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "mapping/ray_traversal.h"

namespace semvox {
namespace {

constexpr double kHalfExtent = 2.5;  // The reference grid spans origin +- this, metres.

// Free and occupied keys of one frame with OctoMap's rules, unlimited range: every key a ray crosses
// (origin's included, end's excluded) is free, every end key is occupied, occupied wins. Keys in grid
// order (z slowest, x fastest), as IntegrateFrame gives them.
void Reference(const Eigen::Vector3f& origin, const std::vector<Eigen::Vector3f>& ends, double res,
               std::vector<VoxelKey>* free, std::vector<VoxelKey>* occupied) {
  // A grid with room to spare around every ray, so that TraverseGrid's boundary never stops one.
  int lo[3], dims[3];
  for (int i = 0; i < 3; ++i) {
    lo[i] = int(CoordToKeyIndex(origin[i] - kHalfExtent, res));
    dims[i] = int(CoordToKeyIndex(origin[i] + kHalfExtent, res)) - lo[i] + 1;
  }
  std::vector<uint8_t> cells(size_t(dims[0]) * dims[1] * dims[2], 0);  // 1 free, 2 occupied.
  for (const Eigen::Vector3f& e : ends)
    TraverseGrid(origin, e, res, lo, dims, [&](size_t idx) {
      cells[idx] = 1;
      return true;
    });
  for (const Eigen::Vector3f& e : ends) {
    const int64_t k[3] = {CoordToKeyIndex(e.x(), res), CoordToKeyIndex(e.y(), res), CoordToKeyIndex(e.z(), res)};
    cells[(size_t(k[2] - lo[2]) * dims[1] + size_t(k[1] - lo[1])) * dims[0] + size_t(k[0] - lo[0])] = 2;
  }
  size_t i = 0;
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x, ++i)
        if (cells[i])
          (cells[i] == 2 ? occupied : free)->push_back(VoxelKey{uint16_t(lo[0] + x), uint16_t(lo[1] + y), uint16_t(lo[2] + z)});
}

// End points of a scanner frame: rays in all directions to distances up to 2 m (some inside the origin's
// own voxel, some repeated, some on voxel boundaries), deterministic from `seed`.
std::vector<Eigen::Vector3f> FrameEnds(const Eigen::Vector3f& origin, double res, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), dist(0.0f, 2.0f);
  std::vector<Eigen::Vector3f> ends;
  for (int i = 0; i < 5000; ++i) {
    Eigen::Vector3f d(unit(rng), unit(rng), unit(rng));
    if (d.squaredNorm() < 1e-6f) continue;
    ends.push_back(origin + d.normalized() * dist(rng));
    if (i % 97 == 0) ends.push_back(ends.back());                          // The same end twice.
    if (i % 89 == 0) ends.push_back(origin + 0.2f * float(res) * d);     // In or next to the origin's voxel.
    if (i % 83 == 0) ends.push_back(Eigen::Vector3f(float(res) * std::round(ends.back().x() / float(res)),
                                                    ends.back().y(), ends.back().z()));  // On a boundary.
  }
  return ends;
}

TEST(FrameIntegrator, EqualsRayByRayTraversal) {
  for (double res : {0.05, 0.02}) {
    for (unsigned seed : {1u, 2u}) {
      const Eigen::Vector3f origin(1.23f, -0.71f, 1.5f);
      const std::vector<Eigen::Vector3f> ends = FrameEnds(origin, res, seed);
      std::vector<VoxelKey> free, occupied;
      Reference(origin, ends, res, &free, &occupied);
      EXPECT_GT(free.size(), 5000u);
      const FrameUpdate update = IntegrateFrame(origin, ends, res);
      EXPECT_TRUE(update.free == free) << "res " << res << " seed " << seed << ": " << update.free.size()
                                       << " free keys, " << free.size() << " expected";
      EXPECT_TRUE(update.occupied == occupied) << "res " << res << " seed " << seed << ": " << update.occupied.size()
                                               << " occupied keys, " << occupied.size() << " expected";
    }
  }
}

TEST(FrameIntegrator, MaxRangeCutsRaysAndMarksNoEnd) {
  // A ray 3 m long with max range 1 m: free up to 1 m along it, nothing occupied.
  const Eigen::Vector3f origin(0.01f, 0.02f, 0.03f);
  const FrameUpdate update = IntegrateFrame(origin, {Eigen::Vector3f(3.01f, 0.02f, 0.03f)}, 0.1, 1.0);
  EXPECT_TRUE(update.occupied.empty());
  ASSERT_EQ(update.free.size(), 10u);  // Keys x = 0.0 .. 0.9 m; the cut point's voxel (1.0 m) is the end.
  for (const VoxelKey& k : update.free) {
    EXPECT_LE(KeyToCoord(k, 0.1).x(), 1.1);
    EXPECT_EQ(k.y, CoordToKeyIndex(0.02, 0.1));
  }
  EXPECT_EQ(update.free.front().x, CoordToKeyIndex(0.01, 0.1));
}

}  // namespace
}  // namespace semvox
