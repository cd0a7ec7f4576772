// Doors and windows found in the walls by their geometry (objects/wall_openings.h), on hand-built voxel
// maps as a scan leaves them: the room's free space, the surfaces it sees occupied, and unknown behind them.
#include "objects/wall_openings.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace semvox {
namespace {

// A room 6 m along x at 5 cm, its south wall's face in row y = 7 (facing +y, the room at y >= 8, free up to
// the ceiling at z = 54) and unknown behind it (inside the wall, outside). The floor is the occupied layer
// z = 0. Openings are cut into the wall with the helpers.
struct WallScene {
  static constexpr double kRes = 0.05;
  static constexpr int kFace = 7, kTop = 54;
  VoxelGrid grid{kRes, {32768, 32768, 32768}, {120, 60, 58}};
  void Set(int x, int y, int z, VoxelState s) { grid.set_state(grid.Index(x, y, z), s); }
  WallScene() {
    for (int z = 0; z < 58; ++z)
      for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 120; ++x) {
          VoxelState s = VoxelState::kUnknown;
          if (y > kFace && z > 0 && z < kTop) s = VoxelState::kFree;                    // the room
          if ((y == kFace && z <= kTop) || (y > kFace && (z == 0 || z == kTop))) s = VoxelState::kOccupied;  // wall face, floor, ceiling
          grid.set_state(grid.Index(x, y, z), s);
        }
  }
  double FloorZ() const { return grid.CellCenter(0, 0, 0).z(); }
  double TopZ() const { return grid.CellCenter(0, 0, kTop).z() - 0.1; }
  // A pane (or closed leaf) `depth` (< 8) cells behind the face over x0..x1, z0..z1; the reveal in front of it
  // is seen (free), the jambs, sill and lintel are the wall's (occupied).
  void Recess(int x0, int x1, int z0, int z1, int depth) {
    for (int z = z0; z <= z1; ++z)
      for (int x = x0; x <= x1; ++x) {
        for (int k = 0; k < depth; ++k) Set(x, kFace - k, z, VoxelState::kFree);
        Set(x, kFace - depth, z, VoxelState::kOccupied);
      }
    for (int k = 1; k < depth; ++k)
      for (int z = z0; z <= z1; ++z) Set(x0 - 1, kFace - k, z, VoxelState::kOccupied), Set(x1 + 1, kFace - k, z, VoxelState::kOccupied);
  }
  // An open doorway over x0..x1 up to z1: free through the wall to the grid's edge (the next room).
  void Doorway(int x0, int x1, int z1) {
    for (int z = 1; z <= z1; ++z)
      for (int x = x0; x <= x1; ++x)
        for (int y = 0; y <= kFace; ++y) Set(x, y, z, VoxelState::kFree);
  }
  // A door leaf standing open in the room: column x, from the wall out to y = kFace + length, z 1..z1.
  void Leaf(int x, int length, int z1) {
    for (int z = 1; z <= z1; ++z)
      for (int k = 1; k <= length; ++k) Set(x, kFace + k, z, VoxelState::kOccupied);
  }
};

const WallOpening* Find(const std::vector<WallOpening>& openings, int nyu40, int along0) {
  for (const WallOpening& o : openings)
    if (o.nyu40 == nyu40 && std::abs(o.along0 - along0) <= 1) return &o;
  return nullptr;
}

TEST(WallOpenings, WindowClosedDoorAndOpenDoorWithItsLeafAreFoundWithTheirExtents) {
  WallScene s;
  s.Recess(10, 33, 18, 41, 2);   // window: 1.2 m wide, sill 0.85 m, top 2.05 m above the floor layer
  s.Recess(50, 66, 1, 40, 2);    // closed door, 0.85 m x 2.0 m
  s.Doorway(80, 96, 40);         // open doorway, 0.85 m x 2.0 m ...
  s.Leaf(80, 17, 40);            // ... its leaf open into the room at the left jamb
  const std::vector<WallOpening> openings = FindWallOpenings(s.grid, s.FloorZ(), s.TopZ());
  ASSERT_EQ(openings.size(), 3u);

  const WallOpening* window = Find(openings, 9, 10);
  ASSERT_NE(window, nullptr);
  EXPECT_EQ(window->axis, 0);
  EXPECT_EQ(window->facing, 1);
  EXPECT_EQ(window->line, WallScene::kFace);
  EXPECT_EQ(window->along1, 33);
  EXPECT_EQ(window->z0, 18);
  EXPECT_EQ(window->z1, 41);
  EXPECT_FALSE(window->open_leaf);
  // Its voxels are the pane and nothing else: 24 x 24 cells two behind the face.
  EXPECT_EQ(window->voxels.size(), 24u * 24u);
  for (uint32_t v : window->voxels) EXPECT_EQ(s.grid.Cell(v)[1], WallScene::kFace - 2);

  const WallOpening* closed = Find(openings, 8, 50);
  ASSERT_NE(closed, nullptr);
  EXPECT_EQ(closed->along1, 66);
  EXPECT_EQ(closed->z0, 1);
  EXPECT_EQ(closed->z1, 40);
  EXPECT_FALSE(closed->open_leaf);
  EXPECT_EQ(closed->voxels.size(), 17u * 40u);

  // The leaf hides the doorway's first column, so the opening seen from the room starts one cell later.
  const WallOpening* open = Find(openings, 8, 81);
  ASSERT_NE(open, nullptr);
  EXPECT_EQ(open->along1, 96);
  EXPECT_TRUE(open->open_leaf);
  EXPECT_EQ(open->voxels.size(), 17u * 40u);  // The leaf's voxels; the doorway holds none.
  for (uint32_t v : open->voxels) {
    EXPECT_EQ(s.grid.Cell(v)[0], 80);
    EXPECT_GT(s.grid.Cell(v)[1], WallScene::kFace);
  }
  EXPECT_NEAR(window->width_m(WallScene::kRes), 1.2, 1e-9);
}

TEST(WallOpenings, AWallMeetingTheDoorwayIsNoLeaf) {
  // The same doorway, with a partition wall at its left jamb instead of a leaf: it runs up to the ceiling.
  WallScene s;
  s.Doorway(80, 96, 40);
  for (int z = 1; z < WallScene::kTop; ++z)
    for (int k = 1; k <= 17; ++k) s.Set(80, WallScene::kFace + k, z, VoxelState::kOccupied);
  const std::vector<WallOpening> openings = FindWallOpenings(s.grid, s.FloorZ(), s.TopZ());
  ASSERT_EQ(openings.size(), 1u);
  EXPECT_EQ(openings[0].nyu40, 8);
  EXPECT_FALSE(openings[0].open_leaf);
  EXPECT_TRUE(openings[0].voxels.empty());
}

TEST(WallOpenings, APlainWallAndShapesUnlikeOpeningsGiveNone) {
  {
    WallScene s;
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
  }
  {
    // Recessed 0.3 m (a niche deeper than max_recess_m: the wall under wall cabinets), window-sized.
    WallScene s;
    s.Recess(10, 33, 18, 41, 6);
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
    WallOpeningOptions deeper;  // Allowed that deep, it is a window.
    deeper.max_recess_m = 0.35;
    EXPECT_EQ(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ(), deeper).size(), 1u);
  }
  {
    // Window-sized but not flat: the depth steps every 4 columns (1, 3, 5, 1, 3, 5 cells).
    WallScene s;
    for (int x = 10; x <= 33; x += 4) s.Recess(x, x + 3, 18, 41, 1 + 2 * ((x - 10) / 4 % 3));
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
    WallOpeningOptions any_shape;  // Without the flatness test it would be a window.
    any_shape.min_flat_share = 0;
    EXPECT_EQ(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ(), any_shape).size(), 1u);
  }
  {
    // Too narrow for a window (0.3 m) and for a door.
    WallScene s;
    s.Recess(10, 15, 18, 41, 2);
    s.Recess(40, 45, 1, 40, 2);
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
  }
  {
    // A gap from the floor to the ceiling (no lintel): where two walls do not meet, not a door.
    WallScene s;
    s.Doorway(50, 66, WallScene::kTop);
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
  }
}

TEST(WallOpenings, FurnitureInFrontHidesPartOfAWindowWithoutHidingIt) {
  WallScene s;
  s.Recess(10, 33, 18, 41, 2);
  // A cabinet 0.1 m in front of the wall covers the window's lower left quarter.
  for (int z = 1; z <= 29; ++z)
    for (int x = 5; x <= 21; ++x) s.Set(x, WallScene::kFace + 2, z, VoxelState::kOccupied);
  const std::vector<WallOpening> openings = FindWallOpenings(s.grid, s.FloorZ(), s.TopZ());
  ASSERT_EQ(openings.size(), 1u);
  EXPECT_EQ(openings[0].nyu40, 9);
  EXPECT_EQ(openings[0].along0, 10);
  EXPECT_EQ(openings[0].along1, 33);
  EXPECT_EQ(openings[0].voxels.size(), 24u * 24u - 12u * 12u);
}

TEST(WallOpenings, AWallTheScanSawOnlyInPartAboveAWindowStillFramesIt) {
  // The wall above the window (rows 42 and 43, its lintel) unseen over the first `unseen` of its 24 columns.
  auto with_unseen_lintel = [](int unseen) {
    WallScene s;
    s.Recess(10, 33, 18, 41, 2);
    for (int z = 42; z <= 43; ++z)
      for (int x = 10; x < 10 + unseen; ++x) s.Set(x, WallScene::kFace, z, VoxelState::kUnknown);
    return FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).size();
  };
  EXPECT_EQ(with_unseen_lintel(15), 1u);  // 9 of 24 seen (>= min_frame_seen_share 0.25), all of them face.
  EXPECT_EQ(with_unseen_lintel(21), 0u);  // 3 of 24 seen: too little to call it framed.
}

TEST(WallOpenings, APaneWhoseUnseenWallAboveJoinsUnrecordedGlassIsAWindow) {
  // The ScanNet studio's bathroom window: the wall above the pane never seen, and a strip of unrecorded glass
  // (the view through the wall's plane, nothing behind) beside the right jamb rising to the top of the scan.
  // The pane and the strip make one region with no lintel; the pane alone, cut from it, is the window.
  auto openings = [](int glass_columns) {
    WallScene s;
    s.Recess(10, 33, 18, 41, 2);
    for (int z = 42; z < WallScene::kTop; ++z)
      for (int x = 10; x <= 33; ++x) s.Set(x, WallScene::kFace, z, VoxelState::kUnknown);
    for (int z = 42; z < WallScene::kTop; ++z)
      for (int x = 34 - glass_columns; x <= 33; ++x)
        for (int y = WallScene::kFace - 1; y <= WallScene::kFace; ++y) s.Set(x, y, z, VoxelState::kFree);
    return FindWallOpenings(s.grid, s.FloorZ(), s.TopZ());
  };
  const std::vector<WallOpening> found = openings(8);  // 96 glass cells beside the pane's 576: 14 %.
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].nyu40, 9);
  EXPECT_EQ(found[0].along0, 10);
  EXPECT_EQ(found[0].along1, 33);
  EXPECT_EQ(found[0].z0, 18);
  EXPECT_EQ(found[0].z1, 41);
  EXPECT_EQ(found[0].voxels.size(), 24u * 24u);
  // Without the glass the wall above is only unseen: too little seen to call the pane framed (as a lintel seen
  // over 3 of its 24 cells above). With a few holes (2 columns, 24 cells: 4 %, under a tenth) the region is a
  // recessed surface seen past something, not a pane beside glass, and is not cut either.
  EXPECT_TRUE(openings(0).empty());
  EXPECT_TRUE(openings(2).empty());
}

TEST(WallOpenings, AFusedCloudsNoisyFaceHidesNoPane) {
  // A fused cloud's wall: its face read one cell back at scattered cells (45 % of them, a fixed hash), its pane two
  // cells back with a fifth of it read one cell back. The one-cell recesses join the pane to the wall around it, so
  // the plain regions are no rectangle; the smoothed elevation (median over 3 x 3) finds it.
  auto noisy_wall = [](bool pane) {
    WallScene s;
    auto hash = [](int x, int z) {
      uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ULL ^ uint64_t(z) * 0xC2B2AE3D27D4EB4FULL;
      h ^= h >> 29, h *= 0xBF58476D1CE4E5B9ULL, h ^= h >> 32;
      return double(h >> 11) * 0x1.0p-53;
    };
    for (int z = 1; z < WallScene::kTop; ++z)
      for (int x = 0; x < 120; ++x) {
        const bool in_pane = pane && x >= 10 && x <= 33 && z >= 18 && z <= 41;
        const int depth = in_pane ? (hash(x, z) < 0.2 ? 1 : 2) : (hash(x, z) < 0.45 ? 1 : 0);
        for (int k = 0; k < depth; ++k) s.Set(x, WallScene::kFace - k, z, VoxelState::kFree);
        s.Set(x, WallScene::kFace - depth, z, VoxelState::kOccupied);
      }
    return s;
  };
  {
    WallScene s = noisy_wall(true);
    const std::vector<WallOpening> openings = FindWallOpenings(s.grid, s.FloorZ(), s.TopZ());
    ASSERT_EQ(openings.size(), 1u);
    EXPECT_EQ(openings[0].nyu40, 9);
    EXPECT_NEAR(openings[0].along0, 10, 1);
    EXPECT_NEAR(openings[0].along1, 33, 1);
    EXPECT_NEAR(openings[0].z0, 18, 1);
    EXPECT_NEAR(openings[0].z1, 41, 1);
    // Its voxels: the pane's first surfaces (one or two cells back; behind them is unknown), inside the window:
    // most of its 24 x 24 cells (the median can erode the rim by a cell, and the rows it trims off).
    EXPECT_GE(openings[0].voxels.size(), 24u * 24u * 8 / 10);
    EXPECT_LE(openings[0].voxels.size(), 24u * 24u);
    for (uint32_t v : openings[0].voxels) {
      const auto c = s.grid.Cell(v);
      EXPECT_LE(c[1], WallScene::kFace - 1);
      EXPECT_GE(c[0], 9);
      EXPECT_LE(c[0], 34);
    }
  }
  {
    WallScene s = noisy_wall(false);  // The noise alone is no opening.
    EXPECT_TRUE(FindWallOpenings(s.grid, s.FloorZ(), s.TopZ()).empty());
  }
}

TEST(WallOpenings, WallsAlongYAndFacingEitherWayAreLookedAtToo) {
  // The same window in a wall along y facing -x: transpose the scene and mirror x.
  WallScene s;
  s.Recess(10, 33, 18, 41, 2);
  VoxelGrid t(WallScene::kRes, {32768, 32768, 32768}, {60, 120, 58});
  for (int z = 0; z < 58; ++z)
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 120; ++x) t.set_state(t.Index(59 - y, x, z), s.grid.state(s.grid.Index(x, y, z)));
  const std::vector<WallOpening> openings = FindWallOpenings(t, s.FloorZ(), s.TopZ());
  ASSERT_EQ(openings.size(), 1u);
  EXPECT_EQ(openings[0].axis, 1);
  EXPECT_EQ(openings[0].facing, -1);
  EXPECT_EQ(openings[0].line, 59 - WallScene::kFace);
  EXPECT_EQ(openings[0].along0, 10);
  EXPECT_EQ(openings[0].along1, 33);
  EXPECT_EQ(openings[0].voxels.size(), 24u * 24u);
}

TEST(WallOpenings, OptionsAreChecked) {
  std::string error;
  EXPECT_TRUE(WallOpeningOptions{}.Check(&error)) << error;
  WallOpeningOptions o;
  o.hole_depth_m = o.max_recess_m;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("hole_depth_m"), std::string::npos);
  o = WallOpeningOptions{};
  o.door_max_width_m = 0.1;
  EXPECT_FALSE(o.Check(&error));
  o = WallOpeningOptions{};
  o.min_fill = 0;
  EXPECT_FALSE(o.Check(&error));
}

}  // namespace
}  // namespace semvox
