// Room segmentation on generated apartments with known rooms: the clean mesh of each
// apartment is voxelised, the floor plan (walls, doors from their lintels, clutter) computed from the voxels
// and segmented with the default options, and the rooms scored (Bormann et al. recall and precision) against
// the generator's rooms. Ground truth: rooms_gt ids at the plan's cell centres, with the rooms of one open-plan
// area (RoomGt::open_to, no wall in between) merged into one room, since no geometric cue separates them.
// Floors stated here, per apartment and mean; the measured values are printed (and recorded in
// docs/rooms.md, "Tests").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

#include "mapping/occupancy_map.h"
#include "mapping/voxelizer.h"
#include "rooms/floor_plan.h"
#include "rooms/room_score.h"
#include "rooms/room_segmentation.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"

namespace semvox {
namespace {

struct Scored {
  RoomScore score;
  int merged_truth_rooms = 0;
};

Scored SegmentGeneratedApartment(uint64_t seed) {
  ApartmentOptions ao;
  ao.seed = seed;
  Result<Apartment> a = GenerateApartment(ao);
  EXPECT_TRUE(a.ok()) << a.status().message();
  if (!a.ok()) return {};
  Scene scene;
  scene.format = "ply";
  scene.mesh = a->mesh;
  Result<VoxelMap> map = Voxelize(scene, VoxelizeOptions());
  EXPECT_TRUE(map.ok()) << map.status().message();
  if (!map.ok()) return {};
  const OccupancyMap occ = ComputeOccupancy(map->grid, map->floor_z, OccupancyOptions());
  const FloorPlan plan = FloorPlanFromVoxels(map->grid, map->floor_z, map->ceiling_z, occ, FloorPlanOptions());
  const RoomSegmentation rooms = SegmentRooms(plan, RoomSegmentationOptions());
  // Ground truth: open-plan groups merged (union-find over open_to), on the plan's cells.
  std::vector<int> parent(a->rooms.size() + 1);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    return i;
  };
  for (const RoomGt& r : a->rooms)
    for (int o : r.open_to)
      if (o >= 1 && o <= int(a->rooms.size())) parent[size_t(find(r.id))] = find(o);
  const FloorGrid grid = MakeFloorGrid(*a, GroundTruthOptions());
  const ImageU16 gt_rooms = RasterizeRooms(*a, grid);
  ImageU16 truth(plan.width(), plan.height(), 1, 0);
  for (int y = 0; y < plan.height(); ++y)
    for (int x = 0; x < plan.width(); ++x) {
      const double wx = plan.origin_x + (x + 0.5) * plan.resolution_m, wy = plan.origin_y + (plan.height() - y - 0.5) * plan.resolution_m;
      int c = 0, r = 0;
      if (!grid.PixelOf(wx, wy, &c, &r)) continue;
      if (const int id = gt_rooms.at(c, r); id >= 1 && id <= int(a->rooms.size())) truth.at(x, y) = uint16_t(find(id));
    }
  Scored s;
  // Where recall is lost: true room cells outside every predicted room, by plan cell kind.
  size_t truth_cells = 0, outside = 0, outside_wall = 0;
  for (size_t i = 0; i < truth.data.size(); ++i) {
    if (!truth.data[i]) continue;
    ++truth_cells;
    if (rooms.room_extent_ids.data[i]) continue;
    ++outside;
    outside_wall += plan.cells.data[i] == uint8_t(FloorCell::kWall);
  }
  std::printf("  voxelise %.2f s; true room cells outside every predicted room %.3f (of which plan wall %.3f)\n",
              map->seconds_surface + map->seconds_floor + map->seconds_free_space, double(outside) / std::max<size_t>(1, truth_cells),
              double(outside_wall) / std::max<size_t>(1, outside));
  s.score = ScoreRooms(rooms.room_extent_ids, truth);
  for (size_t i = 1; i < parent.size(); ++i) s.merged_truth_rooms += find(int(i)) == int(i);
  return s;
}

TEST(GeneratedApartmentRooms, RecallAndPrecisionAboveTheStatedFloors) {
  // Validation apartments 100, 102, 103 (generator seeds: 5, 2 and 2 rooms after merging open plans; 101,
  // the largest, would double the time); floors per apartment and on the mean. Measured (recall / precision):
  // 100: 0.903 / 0.994, 102: 0.927 / 0.993, 103: 0.916 / 0.991; mean 0.916 / 0.993. The recall lost is the
  // 6-9 % of true room cells outside every predicted room, 58-76 % of them plan walls (voxels along the wall
  // faces and furniture against walls), the rest unknown cells.
  const double kMinRecall = 0.85, kMinPrecision = 0.95, kMinMeanRecall = 0.88, kMinMeanPrecision = 0.97;
  double sum_r = 0, sum_p = 0;
  int n = 0;
  for (uint64_t seed : {100, 102, 103}) {
    const Scored s = SegmentGeneratedApartment(seed);
    std::printf("seed %llu: %d predicted rooms, %d true rooms (open plan merged), recall %.3f, precision %.3f\n", (unsigned long long)seed,
                s.score.num_predicted_rooms, s.merged_truth_rooms, s.score.recall, s.score.precision);
    EXPECT_GE(s.score.recall, kMinRecall) << "seed " << seed;
    EXPECT_GE(s.score.precision, kMinPrecision) << "seed " << seed;
    sum_r += s.score.recall, sum_p += s.score.precision, ++n;
  }
  std::printf("mean: recall %.3f, precision %.3f\n", sum_r / n, sum_p / n);
  EXPECT_GE(sum_r / n, kMinMeanRecall);
  EXPECT_GE(sum_p / n, kMinMeanPrecision);
}

}  // namespace
}  // namespace semvox
