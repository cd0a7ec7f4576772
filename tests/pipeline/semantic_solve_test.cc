// pipeline/semantic_solve.h: ApplyFloorSurface, the floor as a surface: floor voxels wholly above it take the
// label of what stands on them or beside them; voxels at the surface, and floor voxels with nothing else
// around them, stay floor. ApplyWallMargin: wall voxels in the cell the segmentation adds around the walls take
// the label of the object beside them; a bare wall's margin and the wall itself stay wall. ApplyWallColour: wall
// voxels off the walls' colour take the label of the object beside them whose colour is closer.
// ApplyRefrigeratorColour: "refrigerator" voxels in wood's colour are a cabinet; a white or a blue one stays.
// ApplyDoorsInDoorways: door voxels far from every door found are a curtain (thin) or a cabinet (thick).
// ApplyTallObjectWalls: the wall voxels of a tall object segment clear of the ceiling take its class by shape;
// a low segment's, one reaching the ceiling, one its shape calls wall or calls an object unsurely, stay wall.
// ApplyWoodenWallUnits: a hung wood-coloured part of the wall labels, of another colour than the wall around it, is
// a cabinet; one down to the floor, one on a window's span, one of the wall's own colour, stay wall.
// ApplyHungWallCabinets: a part of the wall labels hung over seen free space is a cabinet; the wall, a pillar, a
// lintel over a door found, a small part, a shallow one and one over space never seen stay wall.
// ApplyFurnitureFeet: a floor voxel above the floor's surface under an object takes its label; one under the
// surface, one under a wall or nothing, stays floor. ApplyBarTables: the counter voxels of a free-standing
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

// A wall along y at x = 0 (its columns) whose margin is the column row x = 1, as the segmentation grows it; a
// sofa stands against it at x = 2..3, y = 3..5, z = 2..5, and the margin cells beside it came out wall.
struct WallScene : FloorScene {
  SegmentationResult seg;
};

WallScene MakeWallScene() {
  WallScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {10, 10, 10});
  s.seg.wall_margin.assign(100, 0);
  for (int y = 0; y < 10; ++y) {
    s.seg.wall_margin[size_t(y) * 10 + 1] = 1;
    for (int z = 2; z < 8; ++z) s.Add(0, y, z, nyu40::kWall), s.Add(1, y, z, nyu40::kWall);
  }
  for (int y = 3; y <= 5; ++y)
    for (int z = 2; z <= 5; ++z)
      for (int x = 2; x <= 3; ++x) s.Add(x, y, z, nyu40::kSofa);
  s.Add(2, 8, 7, nyu40::kPicture);  // One neighbour of margin voxels (1, 7..9, 6..7).
  s.Add(2, 9, 2, nyu40::kFloor);    // Floor and ceiling never give their label.
  s.Add(2, 9, 3, nyu40::kCeiling);
  s.Sort();
  return s;
}

TEST(WallMargin, AMarginVoxelBesideAnObjectTakesItsLabel) {
  WallScene s = MakeWallScene();
  ApplyWallMargin(s.map, s.seg, 2, &s.labels);
  for (int y = 2; y <= 6; ++y)
    for (int z = 2; z <= 6; ++z) {
      const bool two = (y >= 3 && y <= 5) || z <= 5;  // Sofa neighbours: (rows y-1..y+1 in 3..5) x (layers z-1..z+1 in 2..5).
      EXPECT_EQ(s.At(1, y, z), two ? nyu40::kSofa : nyu40::kWall) << "margin voxel (1, " << y << ", " << z << ")";
    }
  EXPECT_EQ(s.At(1, 2, 6), nyu40::kWall) << "one sofa neighbour only";
  EXPECT_EQ(s.At(1, 7, 3), nyu40::kWall) << "its sofa-labelled neighbours became sofa in this step: labels are read from before it";
  EXPECT_EQ(s.At(1, 8, 7), nyu40::kWall) << "one picture neighbour only";
  EXPECT_EQ(s.At(1, 9, 2), nyu40::kWall) << "floor and ceiling neighbours give nothing";
  for (int y = 0; y < 10; ++y)
    for (int z = 2; z < 8; ++z) EXPECT_EQ(s.At(0, y, z), nyu40::kWall) << "the wall's own columns stay wall";
  EXPECT_EQ(s.labels.wall_margin_voxels, 23u);
}

TEST(WallMargin, TheNeighboursAskedForDecide) {
  WallScene s = MakeWallScene();
  ApplyWallMargin(s.map, s.seg, 1, &s.labels);
  EXPECT_EQ(s.At(1, 8, 7), nyu40::kPicture);
  EXPECT_EQ(s.At(1, 2, 6), nyu40::kSofa);
  WallScene strict = MakeWallScene();
  ApplyWallMargin(strict.map, strict.seg, 9, &strict.labels);
  EXPECT_EQ(strict.At(1, 4, 3), nyu40::kSofa) << "nine sofa neighbours (3 x 3 at x = 2)";
  EXPECT_EQ(strict.At(1, 3, 3), nyu40::kWall) << "six";
}

TEST(WallMargin, WithoutTheSegmentationNothingChanges) {
  WallScene s = MakeWallScene();
  s.seg.wall_margin.clear();
  ApplyWallMargin(s.map, s.seg, 2, &s.labels);
  EXPECT_EQ(s.labels.wall_margin_voxels, 0u);
  EXPECT_EQ(s.At(1, 4, 3), nyu40::kWall);
}

// A beige wall three voxels thick (x = 0..2, all y, z = 2..7) with a wooden wardrobe against it (x = 3..4, y =
// 3..5): the wardrobe's front inside the wall band (x = 1..2, y = 3..5) came out wall in the wardrobe's colour.
struct ColourScene : FloorScene {
  void Put(int x, int y, int z, int label, std::array<uint8_t, 3> rgb) {
    Add(x, y, z, label);
    labels.map.occupied.back().rgb = rgb;
  }
};
constexpr std::array<uint8_t, 3> kBeige{140, 130, 110}, kWood{120, 90, 60}, kShadow{120, 112, 95};  // Shadow: 30.8 from beige.

ColourScene MakeColourScene() {
  ColourScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {10, 10, 10});
  for (int y = 0; y < 10; ++y)
    for (int z = 2; z < 8; ++z)
      for (int x = 0; x < 3; ++x) {
        const bool front = x >= 1 && y >= 3 && y <= 5;
        const bool shadow = x == 2 && y == 6 && z == 4;
        const bool stray = x == 2 && y == 8 && z == 4;  // Wood-coloured, nothing labelled an object beside it.
        const bool unseen = x == 2 && y == 2 && z == 3;  // Completed, its colour borrowed.
        s.Put(x, y, z, nyu40::kWall, front || stray || unseen ? kWood : shadow ? kShadow : kBeige);
        if (unseen) s.labels.map.occupied.back().completed = 1;
      }
  for (int y = 3; y <= 5; ++y)
    for (int z = 2; z < 8; ++z)
      for (int x = 3; x <= 4; ++x) s.Put(x, y, z, nyu40::kCabinet, kWood);
  s.Put(3, 8, 4, nyu40::kFloor, kWood);  // Floor and ceiling never give their label.
  s.Put(3, 9, 4, nyu40::kCeiling, kWood);
  s.Put(3, 2, 3, nyu40::kChair, kWood);  // Beside the unseen voxel.
  s.Sort();
  return s;
}

TEST(WallColour, WallVoxelsInAnObjectsColourTakeItsLabel) {
  ColourScene s = MakeColourScene();
  ApplyWallColour(s.map, 40, 3, &s.labels);
  EXPECT_EQ(s.labels.wall_colour, kBeige) << "the walls' median colour";
  for (int y = 3; y <= 5; ++y)
    for (int z = 2; z < 8; ++z) {
      EXPECT_EQ(s.At(2, y, z), nyu40::kCabinet) << "the front beside the wardrobe (ring 1), y " << y << " z " << z;
      EXPECT_EQ(s.At(1, y, z), nyu40::kCabinet) << "the front one deeper (ring 2), y " << y << " z " << z;
      EXPECT_EQ(s.At(0, y, z), nyu40::kWall) << "the wall's own colour stays wall";
    }
  EXPECT_EQ(s.At(2, 6, 4), nyu40::kWall) << "a shadow on the wall, under the distance, stays wall";
  EXPECT_EQ(s.At(2, 8, 4), nyu40::kWall) << "off the walls' colour but beside no object (floor and ceiling give nothing)";
  EXPECT_EQ(s.At(2, 2, 3), nyu40::kWall) << "a completed voxel is left alone, whatever its borrowed colour";
  EXPECT_EQ(s.labels.wall_colour_voxels, 36u);
}

TEST(WallColour, RingsAndDistanceDecide) {
  ColourScene one = MakeColourScene();
  ApplyWallColour(one.map, 40, 1, &one.labels);
  EXPECT_EQ(one.At(2, 4, 4), nyu40::kCabinet);
  EXPECT_EQ(one.At(1, 4, 4), nyu40::kWall) << "one ring: the deeper front stays wall";
  EXPECT_EQ(one.labels.wall_colour_voxels, 18u);
  ColourScene near = MakeColourScene();
  ApplyWallColour(near.map, 30, 3, &near.labels);
  EXPECT_EQ(near.At(2, 6, 4), nyu40::kWall) << "the shadow lies 30.8 from beige, 41.3 from wood: the wall is nearer";
  ColourScene far = MakeColourScene();
  ApplyWallColour(far.map, 100, 3, &far.labels);
  EXPECT_EQ(far.labels.wall_colour_voxels, 0u) << "wood lies 67.1 from beige";
  ColourScene none = MakeColourScene();
  ApplyWallColour(none.map, 40, 0, &none.labels);
  EXPECT_EQ(none.labels.wall_colour_voxels, 0u);
}

// A white refrigerator (x = 1..3, y = 1..3) under a warm light, with one wood-coloured speck, a wooden tall
// cabinet (x = 6..8) the classifier also took for a refrigerator, and a blue refrigerator (x = 6..8, y = 5..7),
// each 3 x 3 x 6 voxels.
constexpr std::array<uint8_t, 3> kWarmWhite{192, 181, 158}, kOak{201, 135, 66};  // Hue 41 and 31, chroma 34 and 135.
constexpr std::array<uint8_t, 3> kBlue{90, 130, 210};

ColourScene MakeFridgeScene() {
  ColourScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {10, 10, 10});
  for (int x = 1; x <= 8; ++x) {
    if (x == 4 || x == 5) continue;
    for (int y = 1; y <= 3; ++y)
      for (int z = 2; z < 8; ++z) {
        const bool speck = x == 2 && y == 2 && z == 4;
        const bool unseen = x == 7 && y == 2 && z == 7;  // Completed, never seen.
        s.Put(x, y, z, nyu40::kRefrigerator, x >= 6 || speck ? kOak : kWarmWhite);
        if (unseen) s.labels.map.occupied.back().completed = 1;
      }
  }
  for (int x = 6; x <= 8; ++x)
    for (int y = 5; y <= 7; ++y)
      for (int z = 2; z < 8; ++z) s.Put(x, y, z, nyu40::kRefrigerator, kBlue);
  s.Put(2, 5, 4, nyu40::kTable, kOak);  // Other labels are left alone.
  s.Sort();
  return s;
}

TEST(RefrigeratorColour, AWoodColouredRefrigeratorIsACabinet) {
  ColourScene s = MakeFridgeScene();
  ApplyRefrigeratorColour(s.map, 60, &s.labels);
  for (int y = 1; y <= 3; ++y)
    for (int z = 2; z < 8; ++z) {
      EXPECT_EQ(s.At(2, y, z), nyu40::kRefrigerator) << "the white refrigerator stays, its speck too, y " << y << " z " << z;
      if (!(y == 2 && z == 7)) {
        EXPECT_EQ(s.At(7, y, z), nyu40::kCabinet) << "the wooden one is a cabinet, y " << y << " z " << z;
      }
    }
  EXPECT_EQ(s.At(7, 2, 7), nyu40::kRefrigerator) << "a completed voxel is left alone";
  EXPECT_EQ(s.At(7, 6, 4), nyu40::kRefrigerator) << "a blue refrigerator is a refrigerator";
  EXPECT_EQ(s.At(2, 5, 4), nyu40::kTable);
  EXPECT_EQ(s.labels.refrigerator_colour_voxels, 53u);
}

TEST(RefrigeratorColour, TheChromaAskedForDecides) {
  ColourScene strict = MakeFridgeScene();
  ApplyRefrigeratorColour(strict.map, 136, &strict.labels);
  EXPECT_EQ(strict.labels.refrigerator_colour_voxels, 0u) << "oak's chroma is 135";
  ColourScene loose = MakeFridgeScene();
  ApplyRefrigeratorColour(loose.map, 34, &loose.labels);
  EXPECT_EQ(loose.labels.refrigerator_colour_voxels, 107u) << "warm white's chroma is 34: both are cabinets, blue is no wood";
  EXPECT_TRUE(WoodColour({201, 135, 66}, 60));
  EXPECT_FALSE(WoodColour({90, 130, 210}, 60)) << "blue";
  EXPECT_FALSE(WoodColour({255, 178, 228}, 60)) << "pink: blue above green";
  EXPECT_FALSE(WoodColour({220, 60, 50}, 60)) << "red: hue 3.5 degrees";
  EXPECT_FALSE(WoodColour({200, 200, 80}, 60)) << "yellow: hue 60 degrees";
}

// A 2 x 2 m room (40 x 40 cells of 5 cm) with a door found in the wall y = 0, x = 0..15 (0.8 m wide), and four
// object segments labelled door: a leaf open beside the doorway (A), a thin panel 1.8 m away (B, one of its
// voxels labelled wall), a thick box 1.9 m away (C), and a small thing far away (D, 10 voxels).
struct DoorScene : FloorScene {
  SegmentationResult seg;
  void Segment(int x0, int x1, int y0, int y1, int z0, int z1, double thickness_m) {
    ObjectSegment o;
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          Add(x, y, z, nyu40::kDoor);
          o.voxels.push_back(uint32_t(map.grid.Index(x, y, z)));
        }
    std::sort(o.voxels.begin(), o.voxels.end());
    o.features[kSegThickness] = float(thickness_m);
    seg.segments.push_back(o);
  }
};

DoorScene MakeDoorScene() {
  DoorScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {40, 40, 10});
  WallOpening door;
  door.nyu40 = nyu40::kDoor, door.axis = 0, door.facing = 1, door.line = 0, door.along0 = 0, door.along1 = 15;
  door.z0 = 1, door.z1 = 9;
  s.labels.openings.push_back(door);
  s.Segment(16, 16, 1, 15, 2, 3, 0.05);  // A: 30 voxels up to 0.75 m from the doorway's end.
  s.Segment(35, 35, 30, 37, 2, 6, 0.1);  // B: 40 voxels.
  s.Segment(30, 33, 35, 38, 2, 4, 0.4);  // C: 48 voxels.
  s.Segment(5, 6, 38, 38, 2, 6, 0.1);    // D: 10 voxels.
  s.Sort();
  s.labels.map.Find(uint32_t(s.map.grid.Index(35, 33, 4)))->label = nyu40::kWall;
  return s;
}

TEST(DoorsInDoorways, DoorVoxelsAwayFromEveryDoorwayAreCurtainOrCabinet) {
  DoorScene s = MakeDoorScene();
  ApplyDoorsInDoorways(s.map, &s.seg, &s.labels);
  EXPECT_EQ(s.At(16, 15, 3), nyu40::kDoor) << "a leaf open beside its doorway stays door";
  EXPECT_EQ(s.At(35, 30, 2), nyu40::kCurtain) << "a thin panel far from the doorway";
  EXPECT_EQ(s.At(35, 33, 4), nyu40::kWall) << "only the door voxels change";
  EXPECT_EQ(s.At(31, 36, 3), nyu40::kCabinet) << "a thick box far from the doorway";
  EXPECT_EQ(s.At(5, 38, 4), nyu40::kDoor) << "fewer than kDoorlessMinVoxels door voxels";
  EXPECT_EQ(s.labels.doorless_segments, 2);
  EXPECT_EQ(s.labels.doorless_voxels, 39u + 48u);
}

TEST(DoorsInDoorways, WithoutADoorFoundOrTheSegmentationNothingChanges) {
  DoorScene none = MakeDoorScene();
  none.labels.openings.clear();
  ApplyDoorsInDoorways(none.map, &none.seg, &none.labels);
  EXPECT_EQ(none.labels.doorless_voxels, 0u);
  EXPECT_EQ(none.At(35, 30, 2), nyu40::kDoor);
  DoorScene window = MakeDoorScene();
  window.labels.openings[0].nyu40 = nyu40::kWindow;
  ApplyDoorsInDoorways(window.map, &window.seg, &window.labels);
  EXPECT_EQ(window.labels.doorless_voxels, 0u) << "a window is no doorway";
  DoorScene unsegmented = MakeDoorScene();
  ApplyDoorsInDoorways(unsegmented.map, nullptr, &unsegmented.labels);
  EXPECT_EQ(unsegmented.labels.doorless_voxels, 0u);
  DoorScene wide = MakeDoorScene();
  wide.labels.openings[0].along1 = 39;  // A doorway along the whole wall: B and C lie within its width + 0.3 m.
  ApplyDoorsInDoorways(wide.map, &wide.seg, &wide.labels);
  EXPECT_EQ(wide.labels.doorless_voxels, 0u);
}

// A 2 x 2 x 2.5 m room (40 x 40 x 50 cells of 5 cm, floor at z = 0, no ceiling found: the scan's top is 2.5 m)
// with five object segments, each a front of 2 x 1 columns whose voxels came out wall and a top voxel its own
// class: a wardrobe (top 2.0 m, cabinet 0.7), a low cabinet under a window (top 0.9 m, cabinet 0.7), a
// cupboard up to the scan's top (2.35 m, cabinet 0.7), a segment shaped like a wall (top 2.0 m, wall 0.7) and a
// tall shelf the shape classifier is unsure of (top 2.0 m, bookshelf 0.4).
struct TallScene : FloorScene {
  std::shared_ptr<SegmentationResult> seg = std::make_shared<SegmentationResult>();
  SemanticEvidence evidence;
  VoxelCrfModel model = VoxelCrfModel::Default({nyu40::kWall, nyu40::kCabinet, nyu40::kBookshelf, nyu40::kFloor},
                                               {"wall", "cabinet", "bookshelf", "floor"});
  std::vector<std::array<float, 4>> probabilities;
  void Segment(int x, int y, int top_cell, double top_m, double ceiling_gap_m, std::array<float, 4> p, int top_label) {
    ObjectSegment o;
    for (int z = 2; z <= top_cell; ++z)
      for (int dx = 0; dx < 2; ++dx) {
        Add(x + dx, y, z, z == top_cell ? top_label : nyu40::kWall);
        o.voxels.push_back(uint32_t(map.grid.Index(x + dx, y, z)));
      }
    std::sort(o.voxels.begin(), o.voxels.end());
    o.features[kSegTopSurface] = float(top_m);
    o.features[kSegCeilingGap] = float(ceiling_gap_m);
    seg->segments.push_back(o);
    probabilities.push_back(p);
  }
  // The evidence as SemanticEvidenceBuilder::Finish leaves it: one CRF node per segment voxel, each carrying
  // its segment's probabilities.
  void Finish() {
    Sort();
    evidence.nodes.node_of_voxel.assign(map.grid.size(), -1);
    for (size_t i = 0; i < seg->segments.size(); ++i)
      for (uint32_t v : seg->segments[i].voxels) {
        evidence.nodes.node_of_voxel[v] = int32_t(evidence.nodes.voxel.size());
        evidence.nodes.voxel.push_back(v);
        evidence.voxels.segment.insert(evidence.voxels.segment.end(), probabilities[i].begin(), probabilities[i].end());
      }
    evidence.segmentation = seg;
  }
};

TallScene MakeTallScene() {
  TallScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {40, 40, 50});
  s.Segment(2, 5, 40, 2.0, 0.5, {0.1f, 0.7f, 0.1f, 0.1f}, nyu40::kCabinet);   // Wardrobe.
  s.Segment(10, 5, 18, 0.9, 1.6, {0.1f, 0.7f, 0.1f, 0.1f}, nyu40::kCabinet);  // Low cabinet.
  s.Segment(18, 5, 47, 2.35, 0.15, {0.1f, 0.7f, 0.1f, 0.1f}, nyu40::kCabinet); // Up to the scan's top.
  s.Segment(26, 5, 40, 2.0, 0.5, {0.7f, 0.1f, 0.1f, 0.1f}, nyu40::kWall);     // Shaped like a wall.
  s.Segment(34, 5, 40, 2.0, 0.5, {0.2f, 0.3f, 0.4f, 0.1f}, nyu40::kBookshelf); // Unsure.
  s.Finish();
  return s;
}

TEST(TallObjectWalls, AWardrobesFrontIsNoWall) {
  TallScene s = MakeTallScene();
  ApplyTallObjectWalls(s.evidence, s.model, &s.labels);
  EXPECT_EQ(s.At(2, 5, 20), nyu40::kCabinet) << "the wardrobe's front";
  EXPECT_EQ(s.At(3, 5, 2), nyu40::kCabinet);
  EXPECT_EQ(s.At(11, 5, 10), nyu40::kWall) << "a low segment: the wall under a window";
  EXPECT_EQ(s.At(18, 5, 20), nyu40::kWall) << "a segment up to the scan's top may be a wall";
  EXPECT_EQ(s.At(26, 5, 20), nyu40::kWall) << "a segment shaped like a wall";
  EXPECT_EQ(s.At(34, 5, 20), nyu40::kWall) << "a class under kTallObjectMinProbability";
  EXPECT_EQ(s.At(34, 5, 40), nyu40::kBookshelf) << "labels other than wall never change";
  EXPECT_EQ(s.labels.tall_object_wall_segments, 1);
  EXPECT_EQ(s.labels.tall_object_wall_voxels, 2u * 38u);
}

TEST(TallObjectWalls, WithoutASegmentTermNothingChanges) {
  TallScene none = MakeTallScene();
  none.evidence.voxels.segment.clear();
  ApplyTallObjectWalls(none.evidence, none.model, &none.labels);
  EXPECT_EQ(none.labels.tall_object_wall_voxels, 0u);
  EXPECT_EQ(none.At(2, 5, 20), nyu40::kWall);
  TallScene unsegmented = MakeTallScene();
  unsegmented.evidence.segmentation.reset();
  ApplyTallObjectWalls(unsegmented.evidence, unsegmented.model, &unsegmented.labels);
  EXPECT_EQ(unsegmented.labels.tall_object_wall_voxels, 0u);
}

// A wall face along x at y = 0 (40 x 1 x 50 cells of 5 cm, floor at z = 0), beige, 3 cells thick, with a wooden
// wall unit on it from 1.4 to 2.2 m (x 5-14), a wooden panel down to the floor (x 20-25), and a wooden window frame
// (x 30-35, 1.4-2.2 m) around a window found at x 31-34.
struct WallUnitScene : FloorScene {
  void Wall(std::array<uint8_t, 3> beige) {
    for (int z = 0; z < 50; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 40; ++x) {
          Add(x, y, z, nyu40::kWall);
          labels.map.occupied.back().rgb = beige;
        }
    Sort();
  }
  void Paint(int x0, int x1, int z0, int z1, std::array<uint8_t, 3> rgb) {
    for (int z = z0; z <= z1; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = x0; x <= x1; ++x) labels.map.Find(uint32_t(map.grid.Index(x, y, z)))->rgb = rgb;
  }
};

WallUnitScene MakeWallUnitScene(std::array<uint8_t, 3> beige = {150, 140, 120}) {
  WallUnitScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {40, 10, 50});
  s.map.floor_z = s.map.grid.CellCenter(0, 0, 0).z() - 0.025;
  s.Wall(beige);
  const std::array<uint8_t, 3> oak{170, 130, 85};
  s.Paint(5, 14, 28, 43, oak);   // Wall unit: bottom 1.4 m, 0.8 m tall, 480 voxels.
  s.Paint(20, 25, 0, 30, oak);   // Down to the floor.
  s.Paint(30, 35, 28, 43, oak);  // A window's frame.
  WallOpening window;
  window.nyu40 = nyu40::kWindow, window.axis = 0, window.facing = 1, window.line = 2, window.along0 = 31, window.along1 = 34;
  window.z0 = 29, window.z1 = 42;
  s.labels.openings.push_back(window);
  return s;
}

TEST(WoodenWallUnits, AHungWoodenPartOfTheWallIsACabinet) {
  WallUnitScene s = MakeWallUnitScene();
  ApplyWoodenWallUnits(s.map, &s.labels);
  EXPECT_EQ(s.At(9, 1, 35), nyu40::kCabinet) << "the wall unit";
  EXPECT_EQ(s.At(22, 1, 20), nyu40::kWall) << "a wooden panel down to the floor";
  EXPECT_EQ(s.At(32, 1, 35), nyu40::kWall) << "a window's frame";
  EXPECT_EQ(s.At(2, 1, 35), nyu40::kWall) << "the beige wall";
  EXPECT_EQ(s.labels.wall_unit_components, 1);
  EXPECT_GE(s.labels.wall_unit_voxels, 300u);
  EXPECT_LE(s.labels.wall_unit_voxels, 480u);
}

TEST(WoodenWallUnits, APartOfTheWallsOwnColourStays) {
  // A tan wall (chroma 40, no wood) whose lit upper part just reaches wood's chroma (150, 125, 88: 62): it hangs and
  // is wood's colour, but lies 16 from the wall around it, under kWallUnitMinContrast.
  WallUnitScene s = MakeWallUnitScene({140, 125, 100});
  s.labels.openings.clear();
  s.Paint(0, 39, 0, 49, {140, 125, 100});
  s.Paint(5, 14, 28, 43, {150, 125, 88});
  ApplyWoodenWallUnits(s.map, &s.labels);
  EXPECT_EQ(s.At(9, 1, 35), nyu40::kWall);
  EXPECT_EQ(s.labels.wall_unit_voxels, 0u);
  // The same part in oak is a cabinet.
  WallUnitScene oak = MakeWallUnitScene({140, 125, 100});
  oak.labels.openings.clear();
  oak.Paint(20, 39, 0, 49, {140, 125, 100});
  ApplyWoodenWallUnits(oak.map, &oak.labels);
  EXPECT_EQ(oak.At(9, 1, 35), nyu40::kCabinet);
  EXPECT_EQ(oak.labels.wall_unit_components, 1);
}

// A 60 x 10 x 60 grid of 5 cm cells, floor at z = 0, the space in front of a wall (y 0-1, full height) seen free. A
// cabinet labelled wall hangs in front of it (x 5-14, y 2-7, z 28-43: bottom 1.4 m); a pillar stands on the floor
// (x 20-23); a small part hangs (x 26-27, y 2, z 30-35); a part hangs over a door found (x 30-39, z 34-40: a lintel
// 1.7 m up); a shelf one cell deep hangs (x 42-50, y 2, z 28-35: footprint 0.02 m²); a part hangs over space never
// seen (x 52-59).
struct HungScene : FloorScene {
  void Box(int x0, int x1, int y0, int y1, int z0, int z1) {
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) Add(x, y, z, nyu40::kWall);
  }
};

HungScene MakeHungScene() {
  HungScene s;
  s.map.grid = VoxelGrid(0.05, {32763, 32763, 32766}, {60, 10, 60});
  s.map.floor_z = s.map.grid.CellCenter(0, 0, 0).z() - 0.025;
  for (size_t i = 0; i < s.map.grid.size(); ++i) s.map.grid.set_state(i, VoxelState::kFree);
  s.Box(0, 59, 0, 1, 0, 55);
  s.Box(5, 14, 2, 7, 28, 43);
  s.Box(20, 23, 2, 7, 0, 55);
  s.Box(26, 27, 2, 2, 30, 35);
  s.Box(30, 39, 2, 7, 34, 40);
  s.Box(42, 50, 2, 2, 28, 35);
  s.Box(52, 59, 2, 7, 28, 43);
  for (int z = 0; z < 28; ++z)
    for (int y = 2; y <= 7; ++y)
      for (int x = 52; x <= 59; ++x) s.map.grid.set_state(s.map.grid.Index(x, y, z), VoxelState::kUnknown);
  for (const SemanticVoxelRecord& r : s.labels.map.occupied) s.map.grid.set_state(r.voxel, VoxelState::kOccupied);
  WallOpening door;
  door.nyu40 = nyu40::kDoor, door.axis = 0, door.facing = 1, door.line = 2, door.along0 = 31, door.along1 = 38;
  door.z0 = 0, door.z1 = 33;
  s.labels.openings.push_back(door);
  s.Sort();
  return s;
}

TEST(HungWallCabinets, APartOfTheWallHungOverFreeSpaceIsACabinet) {
  HungScene s = MakeHungScene();
  ApplyHungWallCabinets(s.map, &s.labels);
  EXPECT_EQ(s.At(9, 4, 35), nyu40::kCabinet) << "the hung cabinet";
  EXPECT_EQ(s.At(9, 7, 28), nyu40::kCabinet) << "its bottom front";
  EXPECT_EQ(s.At(9, 1, 35), nyu40::kWall) << "the wall behind it stands on the floor";
  EXPECT_EQ(s.At(21, 4, 35), nyu40::kWall) << "a pillar";
  EXPECT_EQ(s.At(26, 2, 32), nyu40::kWall) << "a small part";
  EXPECT_EQ(s.At(35, 4, 37), nyu40::kWall) << "a lintel over a door";
  EXPECT_EQ(s.At(46, 2, 30), nyu40::kWall) << "a shelf one cell deep";
  EXPECT_EQ(s.At(55, 4, 35), nyu40::kWall) << "over space never seen";
  EXPECT_EQ(s.labels.hung_wall_components, 1);
  EXPECT_EQ(s.labels.hung_wall_voxels, 10u * 6u * 16u);
}

TEST(HungWallCabinets, ALowPartOrATallOneStaysWall) {
  // The same cabinet from 0.6 m (a sideboard's top left as wall, say) and one 1.6 m tall stay wall.
  HungScene low = MakeHungScene();
  for (int z = 12; z < 28; ++z)
    for (int y = 2; y <= 7; ++y)
      for (int x = 5; x <= 14; ++x) low.Add(x, y, z, nyu40::kWall);
  for (int z = 0; z < 12; ++z)
    for (int y = 2; y <= 7; ++y)
      for (int x = 5; x <= 14; ++x) low.map.grid.set_state(low.map.grid.Index(x, y, z), VoxelState::kFree);
  low.Sort();
  ApplyHungWallCabinets(low.map, &low.labels);
  EXPECT_EQ(low.At(9, 4, 35), nyu40::kWall) << "bottom 0.6 m, 1.6 m tall";
  EXPECT_EQ(low.labels.hung_wall_components, 0);
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
