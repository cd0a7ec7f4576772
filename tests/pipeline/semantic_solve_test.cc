// pipeline/semantic_solve.h: ApplyFloorSurface, the floor as a surface: floor voxels wholly above it take the
// label of what stands on them or beside them; voxels at the surface, and floor voxels with nothing else
// around them, stay floor. ApplyFurnitureFeet: a floor voxel above the floor's surface under an object takes its
// label; one under the surface, one under a wall or nothing, stays floor. ApplyBarTables: the counter voxels of a free-standing
// counter-height segment, and those joined to them, are table; a counter along a wall, a low one, stay counter.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>

#include "core/labels.h"
#include "objects/object_segments.h"
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

TEST(FurnitureFeet, TheFloorVoxelUnderAnObjectIsItsFoot) {
  FloorScene s = MakeFloorScene();
  for (int z = 3; z < 7; ++z) s.Add(5, 2, z, nyu40::kBed);
  for (int z = 3; z < 7; ++z) s.Add(8, 2, z, nyu40::kWall);
  s.Add(1, 1, 15 - 6, nyu40::kTable);  // A top far above the floor: nothing in between.
  s.Sort();
  ApplyFurnitureFeet(s.map, &s.labels);
  EXPECT_EQ(s.At(5, 2, 2), nyu40::kBed) << "layer 2's centre lies above the surface; the bed stands on it";
  EXPECT_EQ(s.At(5, 2, 1), nyu40::kFloor) << "layer 1's centre lies under the surface";
  EXPECT_EQ(s.At(8, 2, 2), nyu40::kFloor) << "a wall's foot stays floor";
  EXPECT_EQ(s.At(1, 1, 2), nyu40::kFloor) << "nothing right above";
  EXPECT_EQ(s.At(3, 3, 4), nyu40::kSofa) << "the sofa's column: the floor voxel under its bottom";
  EXPECT_EQ(s.At(3, 3, 3), nyu40::kFloor) << "floor above: the step reads the labels as they were";
  EXPECT_EQ(s.labels.furniture_feet_voxels, 2u);
}

// Object segments on a 40 x 40 x 30 grid of 5 cm cells, floor at z = 0, labelled counter: a bar standing free
// (top 1.1 m, 1.0 m from every wall), a counter along a wall (0.2 m) and a low free-standing one (0.9 m).
struct BarScene : FloorScene {
  std::shared_ptr<SegmentationResult> seg = std::make_shared<SegmentationResult>();
  void Segment(int x, double top_m, double wall_distance_m) {
    ObjectSegment o;
    for (int z = 1; z <= int(top_m / 0.05); ++z)
      for (int dx = 0; dx < 3; ++dx) {
        Add(x + dx, 5, z, nyu40::kCounter);
        o.voxels.push_back(uint32_t(map.grid.Index(x + dx, 5, z)));
      }
    std::sort(o.voxels.begin(), o.voxels.end());
    o.features[kSegTopSurface] = float(top_m);
    o.features[kSegWallDistance] = float(wall_distance_m);
    seg->segments.push_back(o);
  }
};

BarScene MakeBarScene() {
  BarScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {40, 40, 30});
  s.Segment(2, 1.1, 1.0);
  s.Segment(12, 1.1, 0.2);
  s.Segment(22, 0.9, 1.0);
  s.Add(5, 5, 22, nyu40::kCounter);   // Joined to the bar (outside its segment).
  s.Add(6, 5, 22, nyu40::kCounter);   // Joined to that one.
  s.Add(3, 6, 23, nyu40::kSofa);      // Another label beside it stays.
  s.Add(8, 5, 22, nyu40::kCounter);   // Apart from it.
  s.Sort();
  return s;
}

TEST(BarTables, AFreeStandingCounterHeightTopIsATable) {
  BarScene s = MakeBarScene();
  ApplyBarTables(s.map, s.seg.get(), &s.labels);
  EXPECT_EQ(s.At(3, 5, 10), nyu40::kTable) << "the bar";
  EXPECT_EQ(s.At(5, 5, 22), nyu40::kTable) << "joined to the bar";
  EXPECT_EQ(s.At(6, 5, 22), nyu40::kTable) << "joined through another";
  EXPECT_EQ(s.At(8, 5, 22), nyu40::kCounter) << "apart";
  EXPECT_EQ(s.At(3, 6, 23), nyu40::kSofa);
  EXPECT_EQ(s.At(13, 5, 10), nyu40::kCounter) << "a counter along a wall";
  EXPECT_EQ(s.At(23, 5, 10), nyu40::kCounter) << "a low counter";
  EXPECT_EQ(s.labels.bar_table_segments, 1);
  EXPECT_EQ(s.labels.bar_table_voxels, 3u * 22u + 2u);
  BarScene none = MakeBarScene();
  ApplyBarTables(none.map, nullptr, &none.labels);
  EXPECT_EQ(none.At(3, 5, 10), nyu40::kCounter) << "without a segmentation nothing changes";
  EXPECT_EQ(none.labels.bar_table_voxels, 0u);
}

}  // namespace
}  // namespace semvox
