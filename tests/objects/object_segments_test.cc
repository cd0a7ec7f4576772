// Object segments by shape (objects/object_segments.h) on a hand-built voxel room.
#include "objects/object_segments.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace semvox {
namespace {

// A 6 x 5 m room at 5 cm (floor at z = 0, walls 2.5 m high, one cell thick), with a bed (2.0 x 1.5 m,
// 0.5 m high, a solid box), a table (1.2 x 0.8 m top at 0.75 m on four legs) and a fridge (0.7 x 0.7 m,
// 1.8 m high, its surface only, as a scan sees it) 0.3 m in front of the north wall.
struct Room {
  static constexpr double kRes = 0.05;
  VoxelGrid grid{kRes, {32768 - 10, 32768 - 10, 32768}, {140, 120, 56}};
  // Cell of a metric position (x, y from the room's corner at cell 10, z from the floor cell 0).
  int C(double m) const { return int(std::floor(m / kRes + 1e-9)); }
  void Fill(double x0, double y0, double z0, double x1, double y1, double z1, bool shell = false) {
    for (int z = C(z0); z < C(z1); ++z)
      for (int y = 10 + C(y0); y < 10 + C(y1); ++y)
        for (int x = 10 + C(x0); x < 10 + C(x1); ++x) {
          const bool inside = z + 1 < C(z1) && y > 10 + C(y0) && y + 1 < 10 + C(y1) && x > 10 + C(x0) && x + 1 < 10 + C(x1);
          if (!shell || !inside) grid.set_state(grid.Index(x, y, z), VoxelState::kOccupied);
        }
  }
  void Clear(double x0, double y0, double z0, double x1, double y1, double z1) {
    for (int z = C(z0); z < C(z1); ++z)
      for (int y = 10 + C(y0); y < 10 + C(y1); ++y)
        for (int x = 10 + C(x0); x < 10 + C(x1); ++x) grid.set_state(grid.Index(x, y, z), VoxelState::kFree);
  }
  Room() {
    Fill(0, 0, 0, 6, 5, 0.05);            // floor layer
    Fill(-0.05, -0.05, 0, 0, 5.05, 2.5);  // west wall
    Fill(6, -0.05, 0, 6.05, 5.05, 2.5);   // east wall
    Fill(0, -0.05, 0, 6, 0, 2.5);         // south wall
    Fill(0, 5, 0, 6, 5.05, 2.5);          // north wall
    Fill(1.0, 1.0, 0.05, 3.0, 2.5, 0.5);  // bed
    Fill(4.0, 1.0, 0.70, 5.2, 1.8, 0.75); // table top
    for (double lx : {4.0, 5.15})
      for (double ly : {1.0, 1.75}) Fill(lx, ly, 0.05, lx + 0.05, ly + 0.05, 0.70);
    Fill(4.5, 4.0, 0.05, 5.2, 4.7, 1.8, /*shell=*/true);  // fridge
  }
  // The floor surface inside the floor layer (cell 0): its centre.
  double FloorZ() const { return grid.CellCenter(0, 0, 0).z(); }
};

const ObjectSegment* SegmentAt(const SegmentationResult& r, const VoxelGrid& g, int x, int y, int z) {
  const uint32_t v = uint32_t(g.Index(x, y, z));
  for (const ObjectSegment& s : r.segments)
    if (std::binary_search(s.voxels.begin(), s.voxels.end(), v)) return &s;
  return nullptr;
}

// The room at 2.5 cm: every 5 cm cell split into eight voxels of its state.
VoxelGrid Halved(const VoxelGrid& g) {
  const auto& o = g.origin_key();
  const auto& d = g.dims();
  VoxelGrid fine(g.resolution() / 2, {2 * o[0] - 32768, 2 * o[1] - 32768, 2 * o[2] - 32768}, {2 * d[0], 2 * d[1], 2 * d[2]});
  for (size_t i = 0; i < fine.size(); ++i) {
    const auto c = fine.Cell(i);
    fine.set_state(i, g.state(g.Index(c[0] / 2, c[1] / 2, c[2] / 2)));
  }
  return fine;
}

// Segments do not depend on the voxel size: at 2.5 cm they are found and described on the 5 cm lattice, so the
// room gives the same segments with the same features, each holding the eight voxels of each of its cells, and
// every voxel the structure of its cell; DescribeVoxels measures a segment's voxels on the lattice too.
TEST(ObjectSegments, AFinerGridGivesTheSameSegmentsAndFeatures) {
  Room room;
  const double floor_z = room.FloorZ();
  const SegmentationResult coarse = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  const VoxelGrid fine_grid = Halved(room.grid);
  const SegmentationResult fine = SegmentObjects(fine_grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  ASSERT_TRUE(fine.feature_grid);
  EXPECT_EQ(fine.feature_grid->dims(), room.grid.dims());
  ASSERT_EQ(fine.segments.size(), coarse.segments.size());
  for (size_t s = 0; s < coarse.segments.size(); ++s) {
    EXPECT_EQ(fine.segments[s].features, coarse.segments[s].features) << s;
    EXPECT_EQ(fine.segments[s].voxels.size(), 8 * coarse.segments[s].voxels.size()) << s;
    EXPECT_TRUE(std::is_sorted(fine.segments[s].voxels.begin(), fine.segments[s].voxels.end()));
    std::array<float, kNumSegmentFeatures> described = DescribeVoxels(fine_grid, fine.segments[s].voxels, fine);
    std::array<float, kNumSegmentFeatures> want = coarse.segments[s].features;
    want[kSegNeighbourRise] = 0;  // DescribeVoxels leaves it 0.
    EXPECT_EQ(described, want) << s;
  }
  for (size_t i = 0; i < fine_grid.size(); i += 7) {
    const auto c = fine_grid.Cell(i);
    EXPECT_EQ(fine.structure[i], coarse.structure[room.grid.Index(c[0] / 2, c[1] / 2, c[2] / 2)]) << i;
  }
  EXPECT_EQ(fine.wall_distance[size_t(100) * size_t(fine_grid.dims()[0]) + 20],
            coarse.wall_distance[size_t(50) * size_t(room.grid.dims()[0]) + 10]);
}

TEST(ObjectSegments, WallsAndFloorAreStructureAndFurnitureSegmentsHaveTheirShape) {
  Room room;
  const double floor_z = room.FloorZ();
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  // Walls and the floor layer are structure, none of the furniture is.
  EXPECT_EQ(r.structure[room.grid.Index(9, 50, 30)], 3);    // west wall
  EXPECT_EQ(r.structure[room.grid.Index(50, 110, 30)], 3);  // north wall
  EXPECT_EQ(r.structure[room.grid.Index(50, 50, 0)], 1);    // floor
  // The wall columns are grown by a cell (wall_dilation_cells): the room's first column beside the west wall is
  // wall (distance 0), the room's middle is not.
  const int columns_x = room.grid.dims()[0];
  ASSERT_EQ(r.wall_distance.size(), size_t(columns_x) * size_t(room.grid.dims()[1]));
  EXPECT_EQ(r.wall_distance[50 * size_t(columns_x) + 10], 0.f);
  EXPECT_EQ(r.wall_distance[50 * size_t(columns_x) + 9], 0.f);
  EXPECT_GT(r.wall_distance[50 * size_t(columns_x) + 50], 1.f);
  EXPECT_FALSE(r.feature_grid) << "a 5 cm grid is segmented as it is";
  ASSERT_EQ(r.segments.size(), 3u);
  const ObjectSegment* bed = SegmentAt(r, room.grid, 40, 40, 5);
  const ObjectSegment* table = SegmentAt(r, room.grid, 100, 40, 14);
  const ObjectSegment* fridge = SegmentAt(r, room.grid, 105, 90, 20);  // its front face
  ASSERT_TRUE(bed && table && fridge);
  EXPECT_NE(bed, table);
  EXPECT_NE(table, fridge);
  // Shape features within a voxel (5 cm) of the built sizes.
  const double tol = 0.051;
  EXPECT_NEAR(bed->features[kSegLength], 2.0, tol);
  EXPECT_NEAR(bed->features[kSegWidth], 1.5, tol);
  // Heights above the floor (0.025 m): the bed's highest voxel centre is at 0.475 m, the table top's at
  // 0.725 m, the fridge's at 1.775 m; the floor band (0.08 m) takes the furniture's lowest layer.
  EXPECT_NEAR(bed->features[kSegTop], 0.45, tol);
  EXPECT_NEAR(bed->features[kSegBottom], 0.10, tol);
  EXPECT_NEAR(bed->features[kSegFill], 1.0, 0.05);
  EXPECT_NEAR(table->features[kSegTopSurface], 0.70, tol);
  EXPECT_NEAR(table->features[kSegLength], 1.2, tol);
  EXPECT_LT(table->features[kSegFill], 0.3);           // a top on legs
  EXPECT_GT(table->features[kSegUnderShare], 0.8);     // most of its footprint is above 0.15 m
  EXPECT_NEAR(fridge->features[kSegTop], 1.75, tol);
  EXPECT_LT(fridge->features[kSegWallDistance], 0.8);  // near the north wall
  EXPECT_GT(bed->features[kSegWallDistance], 0.9);
  // Deterministic.
  const SegmentationResult again = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  ASSERT_EQ(again.segments.size(), r.segments.size());
  for (size_t i = 0; i < r.segments.size(); ++i) EXPECT_EQ(again.segments[i].voxels, r.segments[i].voxels);
}

// A real scan leaves walls full of holes and not always along the axes; furniture that touches has
// different tops; clutter on the floor touches everything.
TEST(ObjectSegments, HoledAndDiagonalWallsAreWallsAndTouchingFurnitureComesApart) {
  Room room;
  // Knock every third cell out of the west wall's columns at staggered heights (coverage about 2/3), and a
  // window (1 m wide, 0.9-2.0 m) out of the south wall.
  for (int y = 9; y <= 111; ++y)
    for (int z = 0; z < 50; ++z)
      if ((z + y) % 3 == 0) room.grid.set_state(room.grid.Index(9, y, z), VoxelState::kFree);
  room.Clear(2.0, -0.05, 0.9, 3.0, 0.0, 2.0);
  // A diagonal wall, 1.4 m long, 2.5 m high, across the south-west corner (45 degrees).
  for (int t = 0; t < 20; ++t)
    for (int z = 0; z < 50; ++z) room.grid.set_state(room.grid.Index(10 + 2 + t, 10 + 22 - t, z), VoxelState::kOccupied);
  // A desk (0.75 m top, 1.0 x 0.6 m, solid) touching the bed's east side, and a rug-like layer of clutter
  // 0.1-0.15 m above the floor joining the bed to the table.
  room.Fill(3.0, 1.0, 0.05, 4.0, 1.6, 0.75);
  room.Fill(3.0, 1.7, 0.05, 4.05, 1.8, 0.15);
  const double floor_z = room.FloorZ();
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  EXPECT_EQ(r.structure[room.grid.Index(9, 60, 31)], 3);   // west wall, holed
  EXPECT_EQ(r.structure[room.grid.Index(14, 50, 35)], 0);  // nothing there
  EXPECT_EQ(r.structure[room.grid.Index(10 + 2 + 10, 10 + 22 - 10, 30)], 3);  // the diagonal wall
  const ObjectSegment* bed = SegmentAt(r, room.grid, 40, 40, 5);
  const ObjectSegment* desk = SegmentAt(r, room.grid, 75, 35, 12);
  const ObjectSegment* table = SegmentAt(r, room.grid, 100, 40, 14);
  ASSERT_TRUE(bed && desk && table);
  EXPECT_NE(bed, desk);
  EXPECT_NE(bed, table);
  EXPECT_NEAR(bed->features[kSegTop], 0.45, 0.051);
  EXPECT_NEAR(desk->features[kSegTop], 0.70, 0.051);
  // Without the cuts the bed, desk and table are one segment.
  SegmentOptions whole;
  whole.split_height_m = 0;
  whole.split_top_step_m = 0;
  const SegmentationResult w = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, whole);
  EXPECT_EQ(SegmentAt(w, room.grid, 40, 40, 5), SegmentAt(w, room.grid, 100, 40, 14));
}

// A scan sees the room's free space, the front and sides of a fridge and a wardrobe standing against the
// wall (their insides unknown) and, above them, the wall behind. Their fronts cover the wall band as a wall
// does; they are furniture, and the walls beside and behind them, an interior wall with free space on both
// sides and an exterior wall with nothing behind it stay walls.
TEST(ObjectSegments, FurnitureFrontsAgainstAWallAreNotWall) {
  Room room;
  room.Clear(0, 0, 0.05, 6, 5, 2.5);                         // the room's free space
  room.Fill(4.4, 4.3, 0.05, 5.1, 5.0, 1.8, /*shell=*/true);  // fridge, 0.7 m deep, flush with the north wall
  room.Clear(4.45, 4.35, 0.10, 5.05, 4.95, 1.75);            // its inside: never seen
  for (int z = 2; z < 35; ++z)
    for (int y = 10 + 87; y < 10 + 99; ++y)
      for (int x = 10 + 89; x < 10 + 101; ++x) room.grid.set_state(room.grid.Index(x, y, z), VoxelState::kUnknown);
  room.Fill(0.5, 4.4, 0.05, 2.0, 5.0, 2.1, /*shell=*/true);  // wardrobe, 0.6 m deep, 1.5 m wide
  for (int z = 2; z < 41; ++z)
    for (int y = 10 + 89; y < 10 + 99; ++y)
      for (int x = 10 + 11; x < 10 + 39; ++x) room.grid.set_state(room.grid.Index(x, y, z), VoxelState::kUnknown);
  // An interior wall, 0.15 m thick, 2 m long, from the south wall, free on both sides.
  room.Fill(3.0, 0, 0.05, 3.15, 2.0, 2.5);
  const double floor_z = room.FloorZ();
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  EXPECT_EQ(r.structure[room.grid.Index(10 + 95, 10 + 86, 20)], 0);  // fridge front
  EXPECT_EQ(r.structure[room.grid.Index(10 + 88, 10 + 92, 20)], 0);  // fridge side
  EXPECT_EQ(r.structure[room.grid.Index(10 + 25, 10 + 88, 20)], 0);  // wardrobe front
  EXPECT_EQ(r.structure[room.grid.Index(10 + 80, 10 + 100, 20)], 3); // north wall beside the fridge
  EXPECT_EQ(r.structure[room.grid.Index(10 + 95, 10 + 100, 45)], 3); // north wall behind the fridge
  EXPECT_EQ(r.structure[room.grid.Index(10 + 60, 10 + 20, 20)], 3);  // interior wall
  EXPECT_EQ(r.structure[room.grid.Index(9, 50, 30)], 3);            // west wall (exterior)
  const ObjectSegment* fridge = SegmentAt(r, room.grid, 10 + 95, 10 + 86, 20);
  const ObjectSegment* wardrobe = SegmentAt(r, room.grid, 10 + 25, 10 + 88, 20);
  ASSERT_TRUE(fridge && wardrobe);
  EXPECT_NE(fridge, wardrobe);
  EXPECT_NEAR(fridge->features[kSegTop], 1.75, 0.051);
  // Without the test both fronts are wall.
  SegmentOptions no_front;
  no_front.front_max_depth_m = 0;
  const SegmentationResult w = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, no_front);
  EXPECT_EQ(w.structure[room.grid.Index(10 + 95, 10 + 86, 20)], 3);
  EXPECT_EQ(w.structure[room.grid.Index(10 + 25, 10 + 88, 20)], 3);
}

// A cabinet 1.5 m high and 0.6 m deep against the north wall, its inside never seen. The scan sees over its
// top: the space above it is free over 36 % of the wall band, more than the 30 % that makes a column "room".
// Only the band below the front's top says whether a column behind the front is the room or the cabinet's
// inside, so the front is still found; the wall above and beside the cabinet stays wall.
TEST(ObjectSegments, FurnitureFrontsAreFoundWhenTheScanSeesOverTheTop) {
  Room room;
  room.Clear(0, 0, 0.05, 6, 5, 2.5);                         // the room's free space, above the cabinet too
  room.Fill(0.5, 4.4, 0.05, 1.7, 5.0, 1.5, /*shell=*/true);  // the cabinet, flush with the north wall
  room.Clear(0.55, 4.45, 0.10, 1.65, 4.95, 1.45);            // its inside: never seen
  for (int z = 2; z < 29; ++z)
    for (int y = 10 + 89; y < 10 + 99; ++y)
      for (int x = 10 + 11; x < 10 + 33; ++x) room.grid.set_state(room.grid.Index(x, y, z), VoxelState::kUnknown);
  const double floor_z = room.FloorZ();
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  EXPECT_EQ(r.structure[room.grid.Index(10 + 20, 10 + 88, 20)], 0);  // cabinet front
  EXPECT_NE(SegmentAt(r, room.grid, 10 + 20, 10 + 88, 20), nullptr);
  EXPECT_EQ(r.structure[room.grid.Index(10 + 20, 10 + 100, 40)], 3); // north wall above the cabinet
  EXPECT_EQ(r.structure[room.grid.Index(10 + 60, 10 + 100, 20)], 3); // north wall beside it
  // The column over the cabinet is free over 36 % of the band: with the share counted over the whole band it
  // would read as room, and the front as wall.
  int free = 0, band = 0;
  for (int z = 5; z <= 43; ++z, ++band) free += room.grid.state(room.grid.Index(10 + 20, 10 + 94, z)) == VoxelState::kFree;
  EXPECT_GE(free, 0.3 * band);
}

// A closed door in an interior wall, the room behind it never seen (unknown), a ceiling slab over both rooms.
// The ceiling over the unseen room is no furniture's back: with the ceiling found, the door, its lintel and
// the wall stay wall. Without a found ceiling the slab counts as what stands behind, and the same geometry
// makes the door (and the wall) a furniture front: the case that flipped a door between wall and object when
// an apartment was turned (FrameCli.TurnedTiltedShiftedApartmentGivesTheSameRoomsAndLabels).
TEST(ObjectSegments, ClosedDoorBeforeAnUnseenRoomStaysWallUnderAFoundCeiling) {
  Room room;
  room.Clear(0, 0, 0.05, 3.0, 5, 2.5);                 // the seen room, west of the interior wall
  room.Fill(0, 0, 2.5, 3.0, 5, 2.75);                  // the ceiling slab over each room (not over the wall)
  room.Fill(3.05, 0, 2.5, 6, 5, 2.75);
  room.Fill(3.0, 0, 0.05, 3.05, 2.0, 2.5);             // interior wall, south of the door
  room.Fill(3.0, 2.9, 0.05, 3.05, 5.0, 2.5);           // and north of it
  room.Fill(3.0, 2.0, 0.05, 3.05, 2.9, 2.0);           // the closed door leaf
  room.Fill(3.0, 2.0, 2.0, 3.05, 2.9, 2.3);            // its lintel
  const double floor_z = room.FloorZ();
  const int door_x = 10 + 60, door_y = 10 + 48, z = 20;
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, true, SegmentOptions{});
  EXPECT_EQ(r.structure[room.grid.Index(door_x, door_y, z)], 3);       // door leaf
  EXPECT_EQ(r.structure[room.grid.Index(door_x, door_y, 42)], 3);      // lintel
  EXPECT_EQ(r.structure[room.grid.Index(door_x, 10 + 20, z)], 3);      // interior wall
  const SegmentationResult no_ceiling = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  EXPECT_EQ(no_ceiling.structure[room.grid.Index(door_x, door_y, z)], 0);
  EXPECT_NE(SegmentAt(no_ceiling, room.grid, door_x, door_y, z), nullptr);
}

// A part's neighbour rise is meant for a seat's back or a counter's wall cabinets. An open door leaf standing
// beside a toilet (a thin panel, 0.15 m) gives none; a tall cabinet beside a stool (0.6 m thick) does.
TEST(ObjectSegments, ThinPanelsGiveNoNeighbourRise) {
  Room room;
  room.Fill(1.0, 3.5, 0.05, 1.4, 4.05, 0.42);   // toilet-like seat
  room.Fill(1.4, 3.3, 0.05, 1.55, 4.2, 2.0);    // door leaf touching it, 0.15 x 0.9 m, 2 m high
  room.Fill(3.45, 2.5, 0.05, 4.0, 3.05, 0.42);  // stool-like seat
  room.Fill(4.0, 2.5, 0.05, 4.6, 3.1, 1.8);     // tall cabinet touching it
  const double floor_z = room.FloorZ();
  const int z = 4;  // 0.2-0.25 m above the floor
  const SegmentationResult r = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, SegmentOptions{});
  const ObjectSegment* toilet = SegmentAt(r, room.grid, 10 + 24, 10 + 75, z);
  const ObjectSegment* leaf = SegmentAt(r, room.grid, 10 + 29, 10 + 75, 30);
  const ObjectSegment* stool = SegmentAt(r, room.grid, 10 + 74, 10 + 55, z);
  const ObjectSegment* cabinet = SegmentAt(r, room.grid, 10 + 86, 10 + 55, 30);
  ASSERT_TRUE(toilet && leaf && stool && cabinet);
  ASSERT_NE(toilet, leaf);
  ASSERT_NE(stool, cabinet);
  EXPECT_LT(leaf->features[kSegThickness], 0.2);
  EXPECT_GT(cabinet->features[kSegThickness], 0.5);
  EXPECT_EQ(toilet->features[kSegNeighbourRise], 0.f);
  EXPECT_NEAR(stool->features[kSegNeighbourRise], 1.4, 0.051);  // 1.775 - 0.375 m
  // Every adjacent part counts when thin ones are not left out.
  SegmentOptions all;
  all.rise_min_thickness_m = 0;
  const SegmentationResult a = SegmentObjects(room.grid, floor_z, floor_z + 2.5, false, all);
  EXPECT_NEAR(SegmentAt(a, room.grid, 10 + 24, 10 + 75, z)->features[kSegNeighbourRise], 1.6, 0.051);  // 1.975 - 0.375 m
  EXPECT_NEAR(SegmentAt(a, room.grid, 10 + 74, 10 + 55, z)->features[kSegNeighbourRise], 1.4, 0.051);
}

TEST(ObjectSegments, RejectsBadOptions) {
  SegmentOptions o;
  o.wall_min_coverage = 0;
  std::string error;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("wall_min_coverage"), std::string::npos);
  SegmentOptions f;
  f.front_max_depth_m = 0.2;  // not beyond front_min_depth_m
  EXPECT_FALSE(f.Check(&error));
  EXPECT_NE(error.find("front_"), std::string::npos);
}

}  // namespace
}  // namespace semvox
