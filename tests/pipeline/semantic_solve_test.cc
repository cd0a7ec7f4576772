// pipeline/semantic_solve.h: ApplyFloorSurface, the floor as a surface: floor voxels wholly above it take the
// label of what stands on them or beside them; voxels at the surface, and floor voxels with nothing else
// around them, stay floor.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/labels.h"
#include "pipeline/semantic_solve.h"

namespace semvox {
namespace {

// A 10 x 10 x 10 grid of 5 cm voxels whose floor surface is the bottom of layer 2: layers 1 and 2 hold the
// floor's scan points, layer 3 starts 5 cm above it.
struct FloorScene {
  VoxelMap map;
  SemanticLabels labels;
  void Add(int x, int y, int z, int label) {
    SemanticVoxelRecord r;
    r.voxel = uint32_t(map.grid.Index(x, y, z));
    r.centre = map.grid.CellCenter(x, y, z).cast<float>();
    r.label = uint16_t(label);
    labels.map.occupied.push_back(r);
  }
  int At(int x, int y, int z) { return labels.map.Find(uint32_t(map.grid.Index(x, y, z)))->label; }
  void Sort() {
    std::sort(labels.map.occupied.begin(), labels.map.occupied.end(),
              [](const SemanticVoxelRecord& a, const SemanticVoxelRecord& b) { return a.voxel < b.voxel; });
  }
};

FloorScene MakeFloorScene() {
  FloorScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {10, 10, 10});
  s.map.floor_z = s.map.grid.CellCenter(0, 0, 2).z() - 0.025;
  s.map.floor_found = true;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) s.Add(x, y, 1, nyu40::kFloor), s.Add(x, y, 2, nyu40::kFloor);
  // A sofa's column: its bottom two layers came out floor, the sofa from layer 5 up.
  s.Add(3, 3, 3, nyu40::kFloor);
  s.Add(3, 3, 4, nyu40::kFloor);
  for (int z = 5; z < 9; ++z) s.Add(3, 3, z, nyu40::kSofa);
  // A floor voxel above the surface with nothing above it, beside the bottom of a wall.
  s.Add(6, 6, 3, nyu40::kFloor);
  s.Add(7, 6, 3, nyu40::kWall);
  s.Add(7, 6, 4, nyu40::kWall);
  s.Add(7, 7, 3, nyu40::kWall);
  s.Add(5, 6, 3, nyu40::kCeiling);  // Ceiling and floor neighbours never give their label.
  // A floor voxel above the surface with only floor around it.
  s.Add(0, 9, 3, nyu40::kFloor);
  s.Sort();
  return s;
}

TEST(FloorSurface, FloorVoxelsAboveTheSurfaceTakeTheLabelOfWhatStandsThere) {
  FloorScene s = MakeFloorScene();
  ApplyFloorSurface(s.map, 0.03, &s.labels);
  EXPECT_EQ(s.At(3, 3, 4), nyu40::kSofa) << "the voxel above gives its label";
  EXPECT_EQ(s.At(3, 3, 3), nyu40::kSofa) << "visited top down, the label passes to the voxel below";
  EXPECT_EQ(s.At(6, 6, 3), nyu40::kWall) << "nothing above: most of the neighbours";
  EXPECT_EQ(s.At(0, 9, 3), nyu40::kFloor) << "only floor around: it stays floor";
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      EXPECT_EQ(s.At(x, y, 1), nyu40::kFloor);
      EXPECT_EQ(s.At(x, y, 2), nyu40::kFloor) << "the layer the surface passes through stays floor";
    }
  EXPECT_EQ(s.labels.floor_surface_voxels, 3u);
}

TEST(FloorSurface, AMarginAsDeepAsTheScanNoiseKeepsTheFloor) {
  // With a margin of 6 cm, layer 3's bottom (5 cm above the floor) lies within the floor's noise: only layer 4
  // (10 cm up) is above the surface.
  FloorScene s = MakeFloorScene();
  ApplyFloorSurface(s.map, 0.06, &s.labels);
  EXPECT_EQ(s.At(3, 3, 4), nyu40::kSofa);
  EXPECT_EQ(s.At(3, 3, 3), nyu40::kFloor);
  EXPECT_EQ(s.At(6, 6, 3), nyu40::kFloor);
  EXPECT_EQ(s.labels.floor_surface_voxels, 1u);
}

}  // namespace
}  // namespace semvox
