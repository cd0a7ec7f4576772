// The voxeliser against exact geometry: a closed box room with a table, built here from boxes.
#include "mapping/voxelizer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "mapping/ray_traversal.h"
#include "scenegen/mesh_builder.h"

namespace semvox {
namespace {

struct Box {
  Eigen::Vector3d lo, hi;
};

// Interior [0, 4] x [0, 3] x [0, 2.5]; 0.25 m walls, floor slab and ceiling slab; a table
// (top 1.0 x 0.8 m at 0.75 m, four 5 cm legs).
std::vector<Box> RoomWithTable() {
  const double T = 0.25, W = 4.0, D = 3.0, H = 2.5;
  std::vector<Box> b = {
      {{-T, -T, -T}, {W + T, D + T, 0}},   // floor slab
      {{-T, -T, H}, {W + T, D + T, H + T}},  // ceiling slab
      {{-T, -T, 0}, {0, D + T, H}},        // west wall
      {{W, -T, 0}, {W + T, D + T, H}},     // east wall
      {{0, -T, 0}, {W, 0, H}},             // south wall
      {{0, D, 0}, {W, D + T, H}},          // north wall
      {{1.5, 1.0, 0.71}, {2.5, 1.8, 0.75}},  // table top
  };
  for (double x : {1.5, 2.45})
    for (double y : {1.0, 1.75}) b.push_back({{x, y, 0.0}, {x + 0.05, y + 0.05, 0.71}});
  return b;
}

Mesh ToMesh(const std::vector<Box>& boxes) {
  MeshBuilder mb;
  for (const Box& b : boxes) mb.AddBox(b.lo, b.hi, Rgb8{128, 128, 128}, FaceTags{1, -1, -1});
  return mb.Take();
}

bool SegmentHitsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Box& box) {
  double t0 = 0, t1 = 1;
  const Eigen::Vector3d d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(d[i]) < 1e-12) {
      if (a[i] < box.lo[i] || a[i] > box.hi[i]) return false;
      continue;
    }
    double u = (box.lo[i] - a[i]) / d[i], v = (box.hi[i] - a[i]) / d[i];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
    if (t0 > t1) return false;
  }
  return true;
}

// Exact state of each voxel: occupied where the (half-open) cell meets a box surface; free where the
// centre is in the air and visible from a scan position; unknown otherwise.
VoxelState ExactState(const VoxelGrid& g, int ix, int iy, int iz, const std::vector<Box>& boxes,
                      const std::vector<Eigen::Vector3d>& positions) {
  const double r = g.resolution(), eps = 1e-4 * r;
  const Eigen::Vector3d c = g.CellCenter(ix, iy, iz);
  const Eigen::Vector3d lo = c.array() - 0.5 * r - eps, hi = c.array() + 0.5 * r - eps;
  bool inside_solid = false;
  for (const Box& b : boxes) {
    const bool meets = (lo.array() <= b.hi.array()).all() && (hi.array() >= b.lo.array()).all();
    const bool interior = (lo.array() > b.lo.array()).all() && (hi.array() < b.hi.array()).all();
    if (meets && !interior) return VoxelState::kOccupied;
    inside_solid |= interior;
  }
  if (inside_solid) return VoxelState::kUnknown;
  if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() > 4 || c.y() > 3 || c.z() > 2.5) return VoxelState::kUnknown;
  for (const auto& p : positions) {
    bool blocked = false;
    for (const Box& b : boxes)
      if (SegmentHitsBox(p, c, b)) { blocked = true; break; }
    if (!blocked) return VoxelState::kFree;
  }
  return VoxelState::kUnknown;
}

struct Agreement {
  double fraction = 0;
  std::array<std::array<size_t, 3>, 3> confusion{};  // [exact][computed]
};

Agreement Compare(const VoxelMap& map, const std::vector<Box>& boxes) {
  Agreement a;
  const auto& d = map.grid.dims();
  size_t agree = 0, total = 0;
  for (int iz = 0; iz < d[2]; ++iz)
    for (int iy = 0; iy < d[1]; ++iy)
      for (int ix = 0; ix < d[0]; ++ix) {
        const VoxelState e = ExactState(map.grid, ix, iy, iz, boxes, map.scan_positions);
        const VoxelState s = map.grid.state(map.grid.Index(ix, iy, iz));
        a.confusion[int(e)][int(s)]++;
        agree += e == s;
        ++total;
      }
  a.fraction = double(agree) / double(total);
  return a;
}

std::string Describe(const Agreement& a) {
  std::string s = "exact\\computed unknown free occupied\n";
  const char* names[] = {"unknown", "free", "occupied"};
  for (int i = 0; i < 3; ++i)
    s += std::string(names[i]) + " " + std::to_string(a.confusion[i][0]) + " " + std::to_string(a.confusion[i][1]) +
         " " + std::to_string(a.confusion[i][2]) + "\n";
  return s;
}

TEST(Voxelize, BoxRoomWithTableMatchesExactGeometry) {
  const std::vector<Box> boxes = RoomWithTable();
  Scene scene;
  scene.mesh = ToMesh(boxes);
  VoxelizeOptions opt;  // 5 cm voxels.
  Result<VoxelMap> map = Voxelize(scene, opt);
  ASSERT_TRUE(map.ok()) << map.status().message();
  ASSERT_FALSE(map->scan_positions.empty());
  EXPECT_TRUE(map->enclosed);
  EXPECT_NEAR(map->floor_z, 0.0, 0.01);
  EXPECT_NEAR(map->ceiling_z, 2.5, 0.01);
  const Agreement a = Compare(map.value(), boxes);
  std::printf("voxel agreement with exact geometry: %.4f\n%s", a.fraction, Describe(a).c_str());
  EXPECT_GE(a.fraction, 0.98) << Describe(a);
  // Surfaces are exact: every exactly-occupied voxel is occupied and vice versa.
  EXPECT_EQ(a.confusion[2][0] + a.confusion[2][1], 0u) << Describe(a);
  EXPECT_EQ(a.confusion[0][2] + a.confusion[1][2], 0u) << Describe(a);
}

TEST(Voxelize, UnknownUnderTheTableAndInsideWalls) {
  const std::vector<Box> boxes = RoomWithTable();
  Scene scene;
  scene.mesh = ToMesh(boxes);
  Result<VoxelMap> map = Voxelize(scene, VoxelizeOptions());
  ASSERT_TRUE(map.ok());
  const VoxelGrid& g = map->grid;
  auto state_at = [&](double x, double y, double z) {
    const auto c = g.CellOf({x, y, z});
    return g.state(g.Index(c[0], c[1], c[2]));
  };
  EXPECT_EQ(state_at(-0.12, 1.5, 1.2), VoxelState::kUnknown);  // Inside the west wall.
  EXPECT_EQ(state_at(2.0, 1.4, 0.3), VoxelState::kUnknown);   // Under the middle of the table.
  EXPECT_EQ(state_at(3.5, 2.5, 1.5), VoxelState::kFree);      // Open air.
  EXPECT_EQ(state_at(2.0, 1.4, 0.73), VoxelState::kOccupied); // Table top.
}

// Points sampled on the visible box faces at `spacing`.
PointCloud SampleVisibleSurfaces(const std::vector<Box>& boxes, double spacing) {
  PointCloud cloud;
  auto inside_other = [&](const Eigen::Vector3d& p, size_t self) {
    for (size_t j = 0; j < boxes.size(); ++j)
      if (j != self && (p.array() > boxes[j].lo.array() - 1e-9).all() && (p.array() < boxes[j].hi.array() + 1e-9).all())
        return true;
    return false;
  };
  for (size_t k = 0; k < boxes.size(); ++k) {
    const Box& b = boxes[k];
    for (int axis = 0; axis < 3; ++axis)
      for (double side : {b.lo[axis], b.hi[axis]}) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (double s = b.lo[u]; s <= b.hi[u] + 1e-9; s += spacing)
          for (double t = b.lo[v]; t <= b.hi[v] + 1e-9; t += spacing) {
            Eigen::Vector3d p;
            p[axis] = side, p[u] = s, p[v] = t;
            const bool in_room = p.x() >= 0 && p.x() <= 4 && p.y() >= 0 && p.y() <= 3 && p.z() >= 0 && p.z() <= 2.5;
            if (in_room && !inside_other(p, k)) cloud.points.push_back(p.cast<float>());
          }
      }
  }
  return cloud;
}

TEST(Voxelize, DenseCloudAgreesWithTheMeshAndDoesNotLeak) {
  const std::vector<Box> boxes = RoomWithTable();
  Scene mesh_scene;
  mesh_scene.mesh = ToMesh(boxes);
  Result<VoxelMap> mesh_map = Voxelize(mesh_scene, VoxelizeOptions());
  ASSERT_TRUE(mesh_map.ok());
  for (double spacing : {0.02, 0.09}) {  // Dense, and sparser than a voxel (points become discs).
    Scene scene;
    scene.cloud = SampleVisibleSurfaces(boxes, spacing);
    Result<VoxelMap> map = Voxelize(scene, VoxelizeOptions());
    ASSERT_TRUE(map.ok()) << map.status().message();
    EXPECT_NEAR(map->floor_z, 0.0, 0.03) << spacing;
    EXPECT_NEAR(map->ceiling_z, 2.5, 0.03) << spacing;
    // Free space agrees with the mesh's inside the room; nothing outside the room is free.
    const VoxelGrid& g = map->grid;
    size_t room = 0, agree = 0, leaks = 0;
    for (size_t i = 0; i < g.size(); ++i) {
      const auto c = g.Cell(i);
      const Eigen::Vector3d p = g.CellCenter(c[0], c[1], c[2]);
      const bool in_room = p.x() > 0 && p.y() > 0 && p.z() > 0 && p.x() < 4 && p.y() < 3 && p.z() < 2.5;
      const bool free = g.state(i) == VoxelState::kFree;
      if (!in_room) { leaks += free; continue; }
      ++room;
      // The cloud's grid can be shifted by the bounds; compare through world coordinates.
      const auto mc = mesh_map->grid.CellOf(p);
      const bool mesh_free = mesh_map->grid.state(mesh_map->grid.Index(mc[0], mc[1], mc[2])) == VoxelState::kFree;
      agree += free == mesh_free;
    }
    std::printf("cloud spacing %.2f m: free-space agreement with the mesh %.4f, leaks %zu\n", spacing,
                double(agree) / room, leaks);
    EXPECT_EQ(leaks, 0u) << "spacing " << spacing;
    EXPECT_GE(double(agree) / room, 0.95) << "spacing " << spacing;
  }
}

// Share of free voxels at points 5 cm apart from `lo` up to (not including) `hi`.
double FreeShare(const VoxelMap& map, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const VoxelGrid& g = map.grid;
  int free = 0, total = 0;
  for (double x = lo.x(); x < hi.x(); x += 0.05)
    for (double y = lo.y(); y < hi.y(); y += 0.05)
      for (double z = lo.z(); z < hi.z(); z += 0.05) {
        const auto c = g.CellOf({x, y, z});
        free += g.state(g.Index(c[0], c[1], c[2])) == VoxelState::kFree;
        ++total;
      }
  return double(free) / total;
}

// Pocket positions on real layouts: a closet 0.9 m x 1.2 m behind a door (0.6 m wide, lintel at 2.0 m) in
// the east wall of the 4 m x 3 m room: the 1 m grid has no position in it (the nearest grid point is 7.5 cm
// from its wall), so without pocket positions most of it stays unknown; with them it gets a position and is
// seen through. The sealed inside of a closed wardrobe mesh (1.2 x 0.9 x 2.1 m) is clear too but borders no
// seen free space.
TEST(Voxelize, ClosetBehindADoorGetsAPocketPositionAndIsSeenThrough) {
  const double T = 0.25, H = 2.5;
  std::vector<Box> boxes = RoomWithTable();
  boxes[0] = {{-T, -T, -T}, {5.4, 3.0 + T, 0}};  // Floor and ceiling slabs under the closet too.
  boxes[1] = {{-T, -T, H}, {5.4, 3.0 + T, H + T}};
  boxes[3] = {{4.0, -T, 0}, {4.0 + T, 0.3, H}};   // East wall: below the door ...
  boxes.push_back({{4.0, 0.9, 0}, {4.0 + T, 3.0 + T, H}});  // ... above it ...
  boxes.push_back({{4.0, 0.3, 2.0}, {4.0 + T, 0.9, H}});    // ... and the lintel.
  boxes.push_back({{5.15, -T, 0}, {5.4, 1.45, H}});         // Closet: east wall,
  boxes.push_back({{4.25, -T, 0}, {5.15, 0, H}});           // south wall,
  boxes.push_back({{4.25, 1.2, 0}, {5.15, 1.45, H}});       // north wall.
  boxes.push_back({{0.1, 2.0, 0}, {1.3, 2.9, 2.1}});         // A closed wardrobe: its sealed inside is no pocket.
  Scene scene;
  scene.mesh = ToMesh(boxes);
  auto closet_free = [](const VoxelMap& map) { return FreeShare(map, {4.3, 0.05, 0.8}, {5.1, 1.15, 1.8}); };
  auto in_closet = [](const Eigen::Vector3d& p) { return p.x() > 4.25 && p.x() < 5.15 && p.y() > 0 && p.y() < 1.2; };
  VoxelizeOptions without;
  without.pocket_rounds = 0;
  Result<VoxelMap> a = Voxelize(scene, without);
  ASSERT_TRUE(a.ok()) << a.status().message();
  for (const auto& p : a->scan_positions) EXPECT_FALSE(in_closet(p)) << "the grid should miss the closet";
  EXPECT_EQ(a->pocket_positions, 0);
  Result<VoxelMap> b = Voxelize(scene, VoxelizeOptions{});
  ASSERT_TRUE(b.ok()) << b.status().message();
  int inside = 0;
  for (const auto& p : b->scan_positions) inside += in_closet(p);
  const double fa = closet_free(*a), fb = closet_free(*b);
  std::printf("closet free share at 0.8-1.8 m: %.3f without pocket positions, %.3f with (%d added)\n", fa, fb, b->pocket_positions);
  EXPECT_EQ(inside, 1);
  EXPECT_GE(b->pocket_positions, 1);
  EXPECT_LT(fa, 0.8);
  EXPECT_GE(fb, 0.97);
  // The main room keeps its grid positions, and nothing outside the flat gets one.
  EXPECT_EQ(std::vector<Eigen::Vector3d>(b->scan_positions.begin(), b->scan_positions.end() - b->pocket_positions), a->scan_positions);
  for (const auto& p : b->scan_positions) {
    EXPECT_TRUE(p.x() > 0 && p.x() < 5.15 && p.y() > 0 && p.y() < 3.0) << p.transpose();
    EXPECT_FALSE(p.x() > 0.1 && p.x() < 1.3 && p.y() > 2.0 && p.y() < 2.9) << "inside the closed wardrobe: " << p.transpose();
  }
}

// A room no door leads into: 1.8 m x 1.25 m beyond the solid east wall of the 4 m x 3 m room (a plan's opening
// drawn as wall), placed so that no point of the 1 m position grid has its clearance in it. It borders no seen
// free space, so only the sealed-room rule gives it a position: the first surfaces above and below its most
// open cell are the ceiling and the floor. A closed cabinet of about its size (1.75 x 1.2 x 2.1 m, in the main
// room, also missed by the grid) has its lid 0.4 m under the ceiling and gets none; with the rule off
// (tolerance 0) neither does the room. Both runs take sealed rooms from 0.25 m² of clear cells, so the lid, not
// the area, is what keeps the cabinet out.
TEST(Voxelize, RoomNoDoorLeadsIntoGetsAPositionButAClosedCabinetDoesNot) {
  const double T = 0.25, H = 2.5;
  std::vector<Box> boxes = RoomWithTable();
  boxes[0] = {{-T, -T, -T}, {6.3, 3.0 + T, 0}};  // Floor and ceiling slabs under the sealed room too.
  boxes[1] = {{-T, -T, H}, {6.3, 3.0 + T, H + T}};
  boxes.push_back({{6.05, -T, 0}, {6.3, 1.5, H}});     // Sealed room [4.25, 6.05] x [0, 1.25]: east wall,
  boxes.push_back({{4.25, -T, 0}, {6.05, 0, H}});      // south wall,
  boxes.push_back({{4.25, 1.25, 0}, {6.05, 1.5, H}});  // north wall.
  boxes.push_back({{2.2, 1.8, 0}, {3.95, 3.0, 2.1}});  // Closed cabinet, lid at 2.1 m.
  Scene scene;
  scene.mesh = ToMesh(boxes);
  auto sealed_free = [](const VoxelMap& map) { return FreeShare(map, {4.3, 0.05, 0.8}, {6.0, 1.2, 1.8}); };
  auto in_sealed = [](const Eigen::Vector3d& p) { return p.x() > 4.25 && p.x() < 6.05 && p.y() > 0 && p.y() < 1.25; };
  auto in_cabinet = [](const Eigen::Vector3d& p) { return p.x() > 2.2 && p.x() < 3.95 && p.y() > 1.8 && p.y() < 3.0; };
  VoxelizeOptions on;
  on.min_sealed_room_m2 = 0.25;
  VoxelizeOptions off = on;
  off.sealed_room_tolerance_m = 0;
  Result<VoxelMap> a = Voxelize(scene, off);
  ASSERT_TRUE(a.ok()) << a.status().message();
  for (const auto& p : a->scan_positions) EXPECT_FALSE(in_cabinet(p)) << "the grid should miss the cabinet: " << p.transpose();
  Result<VoxelMap> b = Voxelize(scene, on);
  ASSERT_TRUE(b.ok()) << b.status().message();
  int sealed_a = 0, sealed_b = 0;
  for (const auto& p : a->scan_positions) sealed_a += in_sealed(p);
  for (const auto& p : b->scan_positions) {
    sealed_b += in_sealed(p);
    EXPECT_FALSE(in_cabinet(p)) << "inside the closed cabinet: " << p.transpose();
    EXPECT_TRUE(p.x() > 0 && p.x() < 6.05 && p.y() > 0 && p.y() < 3.0) << "outside the flat: " << p.transpose();
  }
  const double fa = sealed_free(*a), fb = sealed_free(*b);
  std::printf("sealed room free share at 0.8-1.8 m: %.3f without the rule, %.3f with it\n", fa, fb);
  EXPECT_EQ(sealed_a, 0);
  EXPECT_EQ(sealed_b, 1);
  EXPECT_LT(fa, 0.05);
  EXPECT_GE(fb, 0.97);
}

// CastFreeSpace (precomputed targets, rays stepped four at a time with the inside-grid traversal, parallel
// over the targets) marks exactly the voxels of a plain serial cast with the general traversal, from
// positions in the middle of the room, on cell borders, and next to the grid's border.
TEST(Voxelize, CastFreeSpaceEqualsAPlainSerialCast) {
  Scene scene;
  scene.mesh = ToMesh(RoomWithTable());
  VoxelizeOptions options;
  options.free_space = false;
  Result<VoxelMap> map = Voxelize(scene, options);
  ASSERT_TRUE(map.ok());
  const VoxelGrid surface = map->grid;
  // (1.0, 1.0, 1.5) lies on cell borders on all three axes.
  const std::vector<Eigen::Vector3d> all_positions = {{1.0, 1.0, 1.5}, {3.2, 2.1, 0.4}, {2.0, 1.4, 0.3}, {-0.27, 1.5, 1.0},
                                                  {4.28, 3.28, 2.78}};
  // Each position alone (a wrong ray shows; with all of them other rays may free its cells), then all.
  std::vector<std::vector<Eigen::Vector3d>> sets;
  for (const Eigen::Vector3d& p : all_positions) sets.push_back({p});
  sets.push_back(all_positions);
  for (const std::vector<Eigen::Vector3d>& positions : sets)
  for (double max_range : {10.0, 1.5}) {
    VoxelGrid fast = surface;
    const size_t rays = CastFreeSpace(positions, max_range, &fast);
    VoxelGrid plain = surface;
    size_t plain_rays = 0;
    const int okey[3] = {plain.origin_key()[0], plain.origin_key()[1], plain.origin_key()[2]};
    const int dims[3] = {plain.dims()[0], plain.dims()[1], plain.dims()[2]};
    for (const Eigen::Vector3d& pos : positions) {
      const auto oc = plain.CellOf(pos);
      if (plain.Contains(oc[0], oc[1], oc[2]) && plain.state(plain.Index(oc[0], oc[1], oc[2])) != VoxelState::kOccupied)
        plain.set_state(plain.Index(oc[0], oc[1], oc[2]), VoxelState::kFree);
      for (size_t i = 0; i < surface.size(); ++i) {
        if (surface.state(i) != VoxelState::kOccupied) continue;
        const auto c = plain.Cell(i);
        const Eigen::Vector3d target = plain.CellCenter(c[0], c[1], c[2]);
        if ((target - pos).squaredNorm() > max_range * max_range) continue;
        ++plain_rays;
        const Eigen::Vector3d dir = (target - pos).normalized();
        TraverseGrid(pos.cast<float>(), (target + dir * (0.5 * plain.resolution())).cast<float>(), plain.resolution(), okey,
                     dims, [&](size_t idx) {
                       if (plain.state(idx) == VoxelState::kOccupied) return false;
                       if (plain.state(idx) == VoxelState::kUnknown) plain.set_state(idx, VoxelState::kFree);
                       return true;
                     });
      }
    }
    EXPECT_EQ(rays, plain_rays);
    size_t differ = 0;
    for (size_t i = 0; i < plain.size(); ++i) differ += plain.state(i) != fast.state(i);
    EXPECT_EQ(differ, 0u) << "max range " << max_range << ", " << positions.size() << " positions from " << positions[0].transpose();
    if (positions.size() > 1) EXPECT_GT(fast.CountStates()[1], 1000u);
  }
}

TEST(Voxelize, RejectsBadOptionsAndHugeGrids) {
  Scene scene;
  scene.mesh = ToMesh(RoomWithTable());
  VoxelizeOptions opt;
  opt.voxel_size_m = 0;
  Result<VoxelMap> r = Voxelize(scene, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("voxel_size_m"), std::string::npos);
  opt = VoxelizeOptions();
  opt.max_voxels = 1000;
  r = Voxelize(scene, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("max_voxels"), std::string::npos);
}

}  // namespace
}  // namespace semvox
